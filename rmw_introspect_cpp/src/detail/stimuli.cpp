// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/stimuli.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "rmw/validate_full_topic_name.h"

namespace rmw_introspect
{

namespace
{

std::string trim(const std::string & text)
{
  size_t begin = 0;
  size_t end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) {
    ++begin;
  }
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) {
    --end;
  }
  return text.substr(begin, end - begin);
}

// Why `name` is not a fully qualified ROS name ("" when it is one).
std::string invalid_name_reason(const std::string & name)
{
  int result = RMW_TOPIC_VALID;
  size_t index = 0;
  if (rmw_validate_full_topic_name(name.c_str(), &result, &index) != RMW_RET_OK) {
    rcutils_reset_error();
    return "it cannot be validated";
  }
  if (result == RMW_TOPIC_VALID) {
    return "";
  }
  const char * why = rmw_full_topic_name_validation_result_string(result);
  return std::string(why != nullptr ? why : "invalid") + " (at character " +
    std::to_string(index + 1) + ")";
}

// Services every rclpy/rclcpp node has by itself: left out of the "there is" list.
bool is_standard_service(const std::string & name)
{
  static const char * const kLeaves[] = {
    "/describe_parameters",
    "/get_parameter_types",
    "/get_parameters",
    "/list_parameters",
    "/set_parameters",
    "/set_parameters_atomically",
    "/get_type_description",
    "/change_state",
    "/get_state",
    "/get_available_states",
    "/get_available_transitions",
    "/get_transition_graph",
    "/get_logger_levels",
    "/set_logger_levels"};
  for (const char * leaf : kLeaves) {
    const size_t n = std::strlen(leaf);
    if (name.size() > n && name.compare(name.size() - n, n, leaf) == 0) {
      return true;
    }
  }
  return false;
}

std::string listing(const std::set<std::string> & names)
{
  constexpr size_t kMax = 12;
  if (names.empty()) {
    return "none";
  }
  std::string out;
  size_t count = 0;
  for (const auto & name : names) {
    if (count == kMax) {
      out += ", ... (" + std::to_string(names.size() - kMax) + " more)";
      break;
    }
    out += (count++ == 0 ? "" : ", ") + name;
  }
  return out;
}

std::string no_match_error(const std::string & name, const RecorderSnapshot & snapshot)
{
  std::set<std::string> subscriptions;
  std::set<std::string> services;
  std::string other_kind;  // a publisher or client of that very name
  for (const auto & e : snapshot.endpoints) {
    if (!e.alive) {
      continue;
    }
    if (e.kind == EndpointKind::Subscription) {
      subscriptions.insert(e.name);
    } else if (e.kind == EndpointKind::Service && !is_standard_service(e.name)) {
      services.insert(e.name);
    } else if (e.name == name && other_kind.empty()) {
      other_kind = std::string(" There is a ") + endpoint_kind_to_string(e.kind) + " " + name +
        " (of " + e.node_fqn + "), but stimuli go to subscriptions and services.";
    }
  }
  return "no subscription or service named " + name +
    " in this process (subscriptions: " + listing(subscriptions) +
    "; services: " + listing(services) + ")." + other_kind +
    " A stimulus names the fully resolved name as the capture shows it, and is matched "
    "after the process first settled (and its lifecycle nodes were driven), before virtual "
    "time advances: an endpoint a timer creates later is not reached";
}

}  // namespace

std::vector<std::string> parse_stimuli(const char * text, std::vector<std::string> * warnings)
{
  std::vector<std::string> names;
  if (text == nullptr) {
    return names;
  }
  const std::string all(text);
  size_t start = 0;
  while (start <= all.size()) {
    size_t comma = all.find(',', start);
    if (comma == std::string::npos) {
      comma = all.size();
    }
    const std::string name = trim(all.substr(start, comma - start));
    start = comma + 1;
    if (name.empty()) {
      continue;
    }
    const std::string why = invalid_name_reason(name);
    if (!why.empty()) {
      if (warnings != nullptr) {
        warnings->push_back(
          "RMW_INTROSPECT_STIMULI: '" + name +
          "' is not a fully qualified topic or service "
          "name (" +
          why + "): ignored; write the resolved name, e.g. /camera_info");
      }
      continue;
    }
    if (std::find(names.begin(), names.end(), name) != names.end()) {
      if (warnings != nullptr) {
        warnings->push_back(
          "RMW_INTROSPECT_STIMULI: '" + name + "' is named twice: it is stimulated once");
      }
      continue;
    }
    names.push_back(name);
  }
  return names;
}

std::string stimulus_label(const std::string & name)
{
  return "stimulus:" + name;
}

const char * stimulus_state_name(StimulusRecord::State state)
{
  switch (state) {
    case StimulusRecord::State::kPending: return "pending";
    case StimulusRecord::State::kDone: return "done";
    case StimulusRecord::State::kNoMatch: return "no_match";
    case StimulusRecord::State::kSkipped: return "skipped";
  }
  return "pending";
}

const char * stimulus_result_name(StimulusTargetRecord::Result result)
{
  switch (result) {
    case StimulusTargetRecord::Result::kPending: return "pending";
    case StimulusTargetRecord::Result::kTaken: return "taken";
    case StimulusTargetRecord::Result::kAnswered: return "answered";
    case StimulusTargetRecord::Result::kNotTaken: return "not_taken";
    case StimulusTargetRecord::Result::kNoAnswer: return "no_answer";
    case StimulusTargetRecord::Result::kFailed: return "failed";
  }
  return "pending";
}

StimulusPlan::StimulusPlan(const std::vector<std::string> & names)
{
  for (const auto & name : names) {
    StimulusRecord record;
    record.name = name;
    records_.push_back(record);
  }
}

StimulusTargetRecord * StimulusPlan::current_target()
{
  if (name_ >= records_.size() || target_ >= records_[name_].targets.size()) {
    return nullptr;
  }
  return &records_[name_].targets[target_];
}

bool StimulusPlan::next(const RecorderSnapshot & snapshot, StimulusRequest * out)
{
  if (out == nullptr) {
    return false;
  }
  if (in_flight_) {
    on_failed("no outcome was reported", false);  // never left in flight
  }
  while (name_ < records_.size()) {
    StimulusRecord & record = records_[name_];
    if (record.state == StimulusRecord::State::kPending) {
      // Its turn: match it on the graph as it is now.
      for (const auto & e : snapshot.endpoints) {
        if (!e.alive || e.name != record.name ||
            (e.kind != EndpointKind::Subscription && e.kind != EndpointKind::Service))
        {
          continue;
        }
        StimulusTargetRecord target;
        target.kind = e.kind;
        target.endpoint_id = e.id;
        target.node_id = e.node_id;
        target.node = e.node_fqn;
        target.type = e.type;
        record.targets.push_back(target);
      }
      target_ = 0;
      if (record.targets.empty()) {
        record.state = StimulusRecord::State::kNoMatch;
        record.error = no_match_error(record.name, snapshot);
        ++name_;
        continue;
      }
      record.state = StimulusRecord::State::kDone;  // the targets' results say the rest
    }
    StimulusTargetRecord * target = current_target();
    if (target == nullptr) {
      ++name_;
      target_ = 0;
      continue;
    }
    bool alive = false;
    for (const auto & e : snapshot.endpoints) {
      if (e.id == target->endpoint_id) {
        alive = e.alive;
        break;
      }
    }
    if (!alive) {
      target->result = StimulusTargetRecord::Result::kFailed;
      target->error = std::string("the ") + endpoint_kind_to_string(target->kind) + " " +
        record.name + " of " + target->node + " was destroyed before its turn";
      ++target_;
      continue;
    }
    out->name = record.name;
    out->kind = target->kind;
    out->endpoint_id = target->endpoint_id;
    out->node_id = target->node_id;
    out->node = target->node;
    in_flight_ = true;
    return true;
  }
  return false;
}

void StimulusPlan::on_delivered()
{
  StimulusTargetRecord * target = current_target();
  if (!in_flight_ || target == nullptr) {
    return;
  }
  in_flight_ = false;
  target->result = target->kind == EndpointKind::Service ? StimulusTargetRecord::Result::kAnswered :
                                                           StimulusTargetRecord::Result::kTaken;
  ++target_;
}

void StimulusPlan::on_failed(const std::string & why, bool timed_out)
{
  StimulusTargetRecord * target = current_target();
  if (!in_flight_ || target == nullptr) {
    return;
  }
  in_flight_ = false;
  if (timed_out) {
    target->result = target->kind == EndpointKind::Service ?
      StimulusTargetRecord::Result::kNoAnswer :
      StimulusTargetRecord::Result::kNotTaken;
  } else {
    target->result = StimulusTargetRecord::Result::kFailed;
  }
  target->error = why;
  ++target_;
}

void StimulusPlan::skip_remaining(const std::string & why)
{
  StimulusTargetRecord * target = current_target();
  if (in_flight_ && target != nullptr) {
    on_failed(why, false);
  }
  for (auto & record : records_) {
    if (record.state == StimulusRecord::State::kPending) {
      record.state = StimulusRecord::State::kSkipped;
      record.error = why;
    }
    for (auto & t : record.targets) {
      if (t.result == StimulusTargetRecord::Result::kPending) {
        t.result = StimulusTargetRecord::Result::kFailed;
        t.error = why;
      }
    }
  }
  name_ = records_.size();
}

}  // namespace rmw_introspect
