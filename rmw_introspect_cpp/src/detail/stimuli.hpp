// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__STIMULI_HPP_
#define DETAIL__STIMULI_HPP_

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "detail/recorder.hpp"

namespace rmw_introspect
{

/// RMW_INTROSPECT_STIMULI: fully qualified topic or service names separated by commas
/// (spaces around them are ignored). Each valid name once, in the order given; a name that
/// is not a valid fully qualified name, or one named twice, adds a line to `warnings` and is
/// left out. Empty entries (a trailing comma) are ignored.
std::vector<std::string> parse_stimuli(const char * text, std::vector<std::string> * warnings);

/// The label a stimulus leaves on the endpoints its node creates afterwards (created_in).
std::string stimulus_label(const std::string & name);

/// What happened to one stimulus target (a subscription or a service of that name).
struct StimulusTargetRecord
{
  enum class Result {
    kPending,   // not reached yet, or in flight
    kTaken,     // the subscription took its message
    kAnswered,  // the service answered (the answer is read and discarded)
    kNotTaken,  // the subscription did not take it within the answer timeout
    kNoAnswer,  // the service did not answer within the answer timeout
    kFailed,    // it could not be delivered (see error)
  };
  EndpointKind kind = EndpointKind::Subscription;  // Subscription or Service
  uint64_t endpoint_id = 0;
  uint64_t node_id = 0;
  std::string node;  // fully qualified name of the endpoint's node
  std::string type;  // the message or service type
  Result result = Result::kPending;
  std::string error;  // "" = none
};

/// One name of RMW_INTROSPECT_STIMULI and what it reached.
struct StimulusRecord
{
  enum class State {
    kPending,  // not reached yet
    kDone,     // every target was handled (see their results)
    kNoMatch,  // no subscription or service of that name was alive when its turn came
    kSkipped,  // never reached (see error: no executor ever waited)
  };
  std::string name;
  State state = State::kPending;
  std::vector<StimulusTargetRecord> targets;
  std::string error;  // "" = none
};

const char * stimulus_state_name(StimulusRecord::State state);
const char * stimulus_result_name(StimulusTargetRecord::Result result);

/// One delivery to make: a default message to a subscription, or a default request to a
/// service.
struct StimulusRequest
{
  std::string name;         // the stimulus (= the endpoint's name)
  EndpointKind kind = EndpointKind::Subscription;
  uint64_t endpoint_id = 0;  // the endpoint's record id
  uint64_t node_id = 0;
  std::string node;          // the node's fully qualified name
};

/// Which endpoint gets the next stimulus and what the deliveries came to: a state machine with
/// no thread, no lock and no middleware in it (unit-tested on made-up graphs). The names are
/// taken in the order given; each is matched when its turn comes (so an endpoint an earlier
/// stimulus made the node create can be the next one's target) against the live subscriptions
/// and services of that exact name, in creation order, each getting one delivery. A name that
/// matches nothing is recorded as kNoMatch with an error that names it and lists what there
/// is.
class StimulusPlan
{
public:
  explicit StimulusPlan(const std::vector<std::string> & names);

  bool empty() const { return records_.empty(); }
  /// The next delivery, matched on the current `snapshot`. False when nothing is left.
  bool next(const RecorderSnapshot & snapshot, StimulusRequest * out);
  /// The delivery next() returned last was taken (subscription) or answered (service).
  void on_delivered();
  /// It was not: `why` says why; `timed_out`: no take / no answer within the answer timeout.
  void on_failed(const std::string & why, bool timed_out);
  /// The names not reached yet will not be: `why`.
  void skip_remaining(const std::string & why);

  const std::vector<StimulusRecord> & records() const { return records_; }

private:
  StimulusTargetRecord * current_target();

  std::vector<StimulusRecord> records_;
  size_t name_ = 0;     // index of the name being delivered
  size_t target_ = 0;   // index of its next target
  bool in_flight_ = false;
};

}  // namespace rmw_introspect

#endif  // DETAIL__STIMULI_HPP_
