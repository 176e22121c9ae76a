// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/prober.hpp"

#include <cctype>
#include <string>
#include <utility>
#include <vector>

namespace rmw_introspect
{

namespace
{

// lifecycle_msgs/msg/Transition ids.
constexpr uint8_t kTransitionConfigure = 1;
constexpr uint8_t kTransitionActivate = 3;

const char * transition_label(uint8_t id)
{
  switch (id) {
    case kTransitionConfigure: return "configure";
    case kTransitionActivate: return "activate";
    default: return "";
  }
}

// The transitions from `state` towards `target` (only ever forward: a node already further
// than its target is left where it is).
std::vector<uint8_t> plan(const std::string & state, LifecycleTarget target)
{
  if (target == LifecycleTarget::kActive) {
    if (state == "unconfigured") {
      return {kTransitionConfigure, kTransitionActivate};
    }
    if (state == "inactive") {
      return {kTransitionActivate};
    }
  } else if (target == LifecycleTarget::kInactive && state == "unconfigured") {
    return {kTransitionConfigure};
  }
  return {};
}

struct ServiceSpec
{
  const char * suffix;
  const char * type;
};
constexpr ServiceSpec kListParameters{"/list_parameters", "rcl_interfaces/srv/ListParameters"};
constexpr ServiceSpec kDescribeParameters{
  "/describe_parameters", "rcl_interfaces/srv/DescribeParameters"};
constexpr ServiceSpec kGetParameters{"/get_parameters", "rcl_interfaces/srv/GetParameters"};
constexpr ServiceSpec kGetState{"/get_state", "lifecycle_msgs/srv/GetState"};
constexpr ServiceSpec kChangeState{"/change_state", "lifecycle_msgs/srv/ChangeState"};

// The live service `spec` of node `node_id` in `snapshot`, or NULL.
const EndpointRecord * find_service(
  const RecorderSnapshot & snapshot, uint64_t node_id, const std::string & fqn,
  const ServiceSpec & spec)
{
  const std::string name = fqn + spec.suffix;
  for (const auto & e : snapshot.endpoints) {
    if (e.kind == EndpointKind::Service && e.node_id == node_id && e.alive && e.name == name &&
        e.type == spec.type)
    {
      return &e;
    }
  }
  return nullptr;
}

const NodeRecord * find_node(const RecorderSnapshot & snapshot, uint64_t node_id)
{
  for (const auto & n : snapshot.nodes) {
    if (n.id == node_id) {
      return &n;
    }
  }
  return nullptr;
}

const std::vector<DynValue> & items_of(const DynValue & value, const char * field)
{
  static const std::vector<DynValue> kNone;
  const DynValue * f = value.field(field);
  return f != nullptr && f->kind == DynValue::Kind::Sequence ? f->items : kNone;
}

std::string string_of(const DynValue & value, const char * field)
{
  const DynValue * f = value.field(field);
  return f != nullptr && f->kind == DynValue::Kind::String ? f->s : std::string();
}

const DynValue & field_of(const DynValue & value, const char * field)
{
  static const DynValue kNull;
  const DynValue * f = value.field(field);
  return f != nullptr ? *f : kNull;
}

}  // namespace

const char * lifecycle_target_name(LifecycleTarget target)
{
  switch (target) {
    case LifecycleTarget::kActive: return "active";
    case LifecycleTarget::kInactive: return "inactive";
    case LifecycleTarget::kUnconfigured: return "unconfigured";
    case LifecycleTarget::kNone: return "none";
  }
  return "none";
}

bool parse_lifecycle_target(const std::string & text, LifecycleTarget * out)
{
  std::string t;
  for (char c : text) {
    t.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  for (LifecycleTarget target :
       {LifecycleTarget::kActive, LifecycleTarget::kInactive, LifecycleTarget::kUnconfigured,
        LifecycleTarget::kNone})
  {
    if (t == lifecycle_target_name(target)) {
      *out = target;
      return true;
    }
  }
  return false;
}

ParameterValue parse_parameter_value(const DynValue & value)
{
  ParameterValue v;
  v.type = static_cast<uint8_t>(field_of(value, "type").as_uint());
  v.bool_value = field_of(value, "bool_value").as_bool();
  v.integer_value = field_of(value, "integer_value").as_int();
  v.double_value = field_of(value, "double_value").as_double();
  v.string_value = string_of(value, "string_value");
  for (const auto & item : items_of(value, "byte_array_value")) {
    v.byte_array_value.push_back(static_cast<uint8_t>(item.as_uint()));
  }
  for (const auto & item : items_of(value, "bool_array_value")) {
    v.bool_array_value.push_back(item.as_bool());
  }
  for (const auto & item : items_of(value, "integer_array_value")) {
    v.integer_array_value.push_back(item.as_int());
  }
  for (const auto & item : items_of(value, "double_array_value")) {
    v.double_array_value.push_back(item.as_double());
  }
  for (const auto & item : items_of(value, "string_array_value")) {
    v.string_array_value.push_back(item.kind == DynValue::Kind::String ? item.s : std::string());
  }
  return v;
}

void parse_parameter_descriptor(const DynValue & descriptor, ParameterRecord * record)
{
  const std::string name = string_of(descriptor, "name");
  if (!name.empty()) {
    record->name = name;
  }
  record->descriptor_type = static_cast<uint8_t>(field_of(descriptor, "type").as_uint());
  record->description = string_of(descriptor, "description");
  record->additional_constraints = string_of(descriptor, "additional_constraints");
  record->read_only = field_of(descriptor, "read_only").as_bool();
  record->dynamic_typing = field_of(descriptor, "dynamic_typing").as_bool();
  const auto & fp = items_of(descriptor, "floating_point_range");
  record->has_floating_point_range = !fp.empty();
  if (!fp.empty()) {
    record->floating_point_range.from_value = field_of(fp[0], "from_value").as_double();
    record->floating_point_range.to_value = field_of(fp[0], "to_value").as_double();
    record->floating_point_range.step = field_of(fp[0], "step").as_double();
  }
  const auto & ir = items_of(descriptor, "integer_range");
  record->has_integer_range = !ir.empty();
  if (!ir.empty()) {
    record->integer_range.from_value = field_of(ir[0], "from_value").as_int();
    record->integer_range.to_value = field_of(ir[0], "to_value").as_int();
    record->integer_range.step = field_of(ir[0], "step").as_uint();
  }
}

Prober::Prober(const ProbeSettings & settings)
: settings_(settings)
{
}

const NodeProbe * Prober::result(uint64_t node_id) const
{
  const auto it = tasks_.find(node_id);
  return it != tasks_.end() ? &it->second.result : nullptr;
}

bool Prober::next(const RecorderSnapshot & snapshot, ProbeRequest * out)
{
  if (out == nullptr) {
    return false;
  }
  while (true) {
    auto it = tasks_.find(current_);
    if (it == tasks_.end() || it->second.step == Step::kDone) {
      current_ = 0;
      for (const auto & n : snapshot.nodes) {
        if (n.alive && tasks_.count(n.id) == 0) {
          current_ = n.id;
          break;
        }
      }
      if (current_ == 0) {
        return false;
      }
      Task & task = tasks_[current_];
      task.node_id = current_;
      start_task(task, snapshot);
      continue;
    }
    Task & task = it->second;
    const NodeRecord * node = find_node(snapshot, task.node_id);
    if (node == nullptr || !node->alive) {
      task.step = Step::kDone;  // destroyed meanwhile: nothing more to ask
      continue;
    }
    if (request_for(task, snapshot, out)) {
      ++requests_;
      return true;
    }
    on_no_answer("the node has no service " + out->service_name + " (any more)");
  }
}

void Prober::start_task(Task & task, const RecorderSnapshot & snapshot)
{
  const NodeRecord * node = find_node(snapshot, task.node_id);
  task.fqn = node != nullptr ? node->fqn : std::string();
  const uint64_t id = task.node_id;
  const bool has_parameter_services =
    find_service(snapshot, id, task.fqn, kListParameters) != nullptr &&
    find_service(snapshot, id, task.fqn, kDescribeParameters) != nullptr &&
    find_service(snapshot, id, task.fqn, kGetParameters) != nullptr;
  const bool has_lifecycle_services = find_service(snapshot, id, task.fqn, kGetState) != nullptr &&
    find_service(snapshot, id, task.fqn, kChangeState) != nullptr;
  task.parameters = settings_.parameters && has_parameter_services;
  // `none` drives nothing, but the state is still asked (with the parameters): a node that
  // drives itself is recorded in the state it reached, not as unknown
  task.lifecycle = has_lifecycle_services &&
    (settings_.lifecycle != LifecycleTarget::kNone || settings_.parameters);
  task.result.has_lifecycle = has_lifecycle_services;
  if (has_lifecycle_services) {
    task.result.lifecycle.target = lifecycle_target_name(settings_.lifecycle);
  }
  if (task.lifecycle) {
    task.step = Step::kGetState;
  } else if (task.parameters) {
    start_parameter_round(task, "");
  } else {
    task.step = Step::kDone;
  }
}

bool Prober::request_for(
  const Task & task, const RecorderSnapshot & snapshot, ProbeRequest * out) const
{
  const ServiceSpec * spec = nullptr;
  DynValue request = DynValue::structure();
  ProbeRequest r;
  switch (task.step) {
    case Step::kGetState: spec = &kGetState; break;
    case Step::kList:
      spec = &kListParameters;
      request.set("prefixes", DynValue::sequence());
      request.set("depth", DynValue::uinteger(0));  // DEPTH_RECURSIVE
      break;
    case Step::kDescribe:
    case Step::kDescribeOne:
    case Step::kGet:
    case Step::kGetOne:
      {
        const bool describe = task.step == Step::kDescribe || task.step == Step::kDescribeOne;
        const bool one = task.step == Step::kDescribeOne || task.step == Step::kGetOne;
        spec = describe ? &kDescribeParameters : &kGetParameters;
        request.set(
          "names", one ? string_sequence({task.names.at(task.one)}) : string_sequence(task.names));
        break;
      }
    case Step::kChangeState:
      {
        spec = &kChangeState;
        const LifecycleTransitionRecord & t = task.result.lifecycle.transitions.back();
        DynValue transition = DynValue::structure();
        transition.set("id", DynValue::uinteger(t.id));
        transition.set("label", DynValue::string(t.label));
        request.set("transition", std::move(transition));
        r.changes_node = true;
        r.transition = t.label;
        break;
      }
    case Step::kDone: return false;
  }
  r.node_id = task.node_id;
  r.service_name = task.fqn + spec->suffix;
  r.service_type = spec->type;
  r.request = std::move(request);
  const EndpointRecord * service = find_service(snapshot, task.node_id, task.fqn, *spec);
  r.service_id = service != nullptr ? service->id : 0;
  *out = std::move(r);
  return service != nullptr;
}

void Prober::on_answer(const DynValue & response)
{
  auto it = tasks_.find(current_);
  if (it == tasks_.end()) {
    return;
  }
  Task & task = it->second;
  switch (task.step) {
    case Step::kGetState:
      after_state(task, string_of(field_of(response, "current_state"), "label"));
      break;
    case Step::kChangeState:
      {
        const bool success = field_of(response, "success").as_bool();
        task.result.lifecycle.transitions.back().result = success ?
          LifecycleTransitionRecord::Result::kSuccess :
          LifecycleTransitionRecord::Result::kFailure;
        if (!success) {
          task.todo.clear();
        }
        task.step = Step::kGetState;
        break;
      }
    case Step::kList:
      {
        task.names.clear();
        for (const auto & item : items_of(field_of(response, "result"), "names")) {
          if (item.kind == DynValue::Kind::String && task.known.count(item.s) == 0) {
            task.names.push_back(item.s);
          }
        }
        if (task.names.empty()) {
          after_parameter_round(task);
          break;
        }
        task.round.assign(task.names.size(), ParameterRecord());
        for (size_t k = 0; k < task.names.size(); ++k) {
          task.round[k].name = task.names[k];
        }
        task.described.assign(task.names.size(), false);
        task.step = Step::kDescribe;
        break;
      }
    case Step::kDescribe:
      {
        const auto & descriptors = items_of(response, "descriptors");
        if (descriptors.size() != task.names.size()) {
          task.one = 0;
          task.step = Step::kDescribeOne;  // some name has no descriptor: one at a time
          break;
        }
        for (size_t k = 0; k < descriptors.size(); ++k) {
          parse_parameter_descriptor(descriptors[k], &task.round[k]);
          task.round[k].name = task.names[k];
          task.described[k] = true;
        }
        task.step = Step::kGet;
        break;
      }
    case Step::kDescribeOne:
      {
        const auto & descriptors = items_of(response, "descriptors");
        if (descriptors.size() == 1) {
          parse_parameter_descriptor(descriptors[0], &task.round[task.one]);
          task.round[task.one].name = task.names[task.one];
          task.described[task.one] = true;
        }
        if (++task.one == task.names.size()) {
          task.step = Step::kGet;
        }
        break;
      }
    case Step::kGet:
      {
        const auto & values = items_of(response, "values");
        if (values.size() != task.names.size()) {
          task.one = 0;
          task.step = Step::kGetOne;  // some parameter has no value (rclpy answers none)
          break;
        }
        for (size_t k = 0; k < values.size(); ++k) {
          task.round[k].value = parse_parameter_value(values[k]);
        }
        commit_round(task);
        break;
      }
    case Step::kGetOne:
      {
        const auto & values = items_of(response, "values");
        if (values.size() == 1) {
          task.round[task.one].value = parse_parameter_value(values[0]);
        }
        if (++task.one == task.names.size()) {
          commit_round(task);
        }
        break;
      }
    case Step::kDone: break;
  }
}

void Prober::on_no_answer(const std::string & why)
{
  auto it = tasks_.find(current_);
  if (it == tasks_.end()) {
    return;
  }
  Task & task = it->second;
  ++unanswered_;
  switch (task.step) {
    case Step::kGetState: task.result.lifecycle.error = why; break;
    case Step::kChangeState:
      task.result.lifecycle.transitions.back().result =
        LifecycleTransitionRecord::Result::kNoAnswer;
      task.result.lifecycle.error = "transition " + task.result.lifecycle.transitions.back().label +
        " of " + task.fqn + ": " + why;
      break;
    case Step::kDone: return;
    default: task.result.parameters_error = why; break;
  }
  task.todo.clear();
  task.step = Step::kDone;  // a node that does not answer is not asked again
}

void Prober::after_state(Task & task, const std::string & label)
{
  LifecycleRecord & lc = task.result.lifecycle;
  if (lc.transitions.empty()) {
    lc.initial_state = label;
    lc.state = label;
    task.todo = plan(label, settings_.lifecycle);
    if (task.parameters) {
      start_parameter_round(task, "");
    } else {
      next_transition(task);
    }
    return;
  }
  lc.state = label;
  const LifecycleTransitionRecord & last = lc.transitions.back();
  if (last.result == LifecycleTransitionRecord::Result::kFailure) {
    lc.error = "transition " + last.label + " of " + task.fqn +
      " failed: change_state answered success=false (the callback returned FAILURE or ERROR, "
      "or raised); state now " +
      (label.empty() ? std::string("unknown") : label);
  }
  if (task.parameters) {
    start_parameter_round(task, last.label);
  } else {
    next_transition(task);
  }
}

void Prober::start_parameter_round(Task & task, const std::string & label)
{
  task.round_label = label;
  task.names.clear();
  task.round.clear();
  task.described.clear();
  task.step = Step::kList;
}

void Prober::commit_round(Task & task)
{
  for (size_t k = 0; k < task.round.size(); ++k) {
    if (!task.described[k]) {
      continue;  // undeclared between list and describe
    }
    task.round[k].declared_in = task.round_label;
    task.known.insert(task.round[k].name);
    task.result.parameters.push_back(std::move(task.round[k]));
  }
  task.round.clear();
  task.names.clear();
  task.described.clear();
  after_parameter_round(task);
}

void Prober::after_parameter_round(Task & task)
{
  task.result.has_parameters = true;
  next_transition(task);
}

void Prober::next_transition(Task & task)
{
  if (task.todo.empty()) {
    task.step = Step::kDone;
    return;
  }
  LifecycleTransitionRecord t;
  t.id = task.todo.front();
  t.label = transition_label(t.id);
  task.todo.erase(task.todo.begin());
  task.result.lifecycle.transitions.push_back(t);
  task.step = Step::kChangeState;
}

}  // namespace rmw_introspect
