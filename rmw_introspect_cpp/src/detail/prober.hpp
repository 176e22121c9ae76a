// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__PROBER_HPP_
#define DETAIL__PROBER_HPP_

#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "detail/dynamic_value.hpp"
#include "detail/node_probe.hpp"
#include "detail/recorder.hpp"

namespace rmw_introspect
{

/// How far the middleware drives each lifecycle node (RMW_INTROSPECT_LIFECYCLE).
enum class LifecycleTarget { kActive, kInactive, kUnconfigured, kNone };

const char * lifecycle_target_name(LifecycleTarget target);
/// "active", "inactive", "unconfigured", "none" (any case); false for anything else.
bool parse_lifecycle_target(const std::string & text, LifecycleTarget * out);

struct ProbeSettings
{
  bool parameters = true;  // RMW_INTROSPECT_PARAMETERS
  LifecycleTarget lifecycle = LifecycleTarget::kActive;  // RMW_INTROSPECT_LIFECYCLE
  /// Anything to ask at all.
  bool enabled() const { return parameters || lifecycle != LifecycleTarget::kNone; }
};

/// One request to a node's own service.
struct ProbeRequest
{
  uint64_t node_id = 0;
  uint64_t service_id = 0;   // the service's endpoint record id
  std::string service_name;  // "/node/list_parameters"
  std::string service_type;  // "rcl_interfaces/srv/ListParameters"
  DynValue request;          // the request message's content
  /// change_state: the node changes; wait for it to settle again before the next request.
  bool changes_node = false;
  std::string transition;    // change_state: the transition's label ("configure")
};

/// What to ask each node, in which order, and what its answers mean: a state machine with no
/// thread, no lock and no middleware in it (unit-tested with made-up answers). Per node, in
/// creation order, one request at a time:
///
///   lifecycle services (and a target other than none): get_state;
///   parameter services (and parameters on): list_parameters (every name, any depth), then
///     describe_parameters and get_parameters of the names not read yet (one name at a time
///     when a node answers a batch short, as rclpy does when one parameter has no value);
///   then per transition towards the target (configure, activate): change_state, get_state,
///     and the parameters again (nodes declare parameters in on_configure).
///
/// A failed transition ends the driving (lifecycle.error names node and transition); a
/// request without an answer ends that node's probe (the error says which).
class Prober
{
public:
  explicit Prober(const ProbeSettings & settings);

  /// The next request, planned on the current `snapshot` (nodes alive in it, in creation
  /// order, each once). False when no node is left to ask.
  bool next(const RecorderSnapshot & snapshot, ProbeRequest * out);
  /// The answer (the response message's content) to the request next() returned last.
  void on_answer(const DynValue & response);
  /// The request next() returned last got no answer, for the reason `why`.
  void on_no_answer(const std::string & why);

  /// What is known of node `node_id` so far; NULL for a node not probed (yet).
  const NodeProbe * result(uint64_t node_id) const;
  const ProbeSettings & settings() const { return settings_; }
  size_t requests() const { return requests_; }
  size_t unanswered() const { return unanswered_; }

private:
  enum class Step {
    kGetState,
    kList,
    kDescribe,
    kGet,
    kDescribeOne,
    kGetOne,
    kChangeState,
    kDone,
  };
  struct Task
  {
    uint64_t node_id = 0;
    std::string fqn;
    bool parameters = false;  // has the parameter services and parameters are on
    bool lifecycle = false;   // has the lifecycle services and the target is not none
    Step step = Step::kDone;
    std::string round_label;  // the transition the parameter round follows ("" = start)
    std::vector<std::string> names;       // names of this parameter round
    std::vector<ParameterRecord> round;   // their records, same order
    std::vector<bool> described;          // per name: a descriptor came
    size_t one = 0;                       // per-name fallback: the index asked
    std::vector<uint8_t> todo;            // transitions still to drive
    std::set<std::string> known;          // parameter names already read
    NodeProbe result;
  };

  bool request_for(const Task & task, const RecorderSnapshot & snapshot, ProbeRequest * out) const;
  void start_task(Task & task, const RecorderSnapshot & snapshot);
  void after_state(Task & task, const std::string & label);
  void start_parameter_round(Task & task, const std::string & label);
  void after_parameter_round(Task & task);
  void next_transition(Task & task);
  void commit_round(Task & task);

  const ProbeSettings settings_;
  std::map<uint64_t, Task> tasks_;
  uint64_t current_ = 0;  // node of the request in flight (0: none)
  size_t requests_ = 0;
  size_t unanswered_ = 0;
};

/// Parse the content of rcl_interfaces/msg/ParameterValue / ParameterDescriptor.
ParameterValue parse_parameter_value(const DynValue & value);
void parse_parameter_descriptor(const DynValue & descriptor, ParameterRecord * record);

}  // namespace rmw_introspect

#endif  // DETAIL__PROBER_HPP_
