// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__NODE_PROBE_HPP_
#define DETAIL__NODE_PROBE_HPP_

#include <cstdint>
#include <string>
#include <vector>

namespace rmw_introspect
{

/// What the middleware learnt by asking a node's own services (prober.hpp): its parameters
/// and its lifecycle. Kept with the node's record and written into the capture.

/// rcl_interfaces/msg/ParameterType values.
enum ParameterTypeId : uint8_t {
  kParameterNotSet = 0,
  kParameterBool = 1,
  kParameterInteger = 2,
  kParameterDouble = 3,
  kParameterString = 4,
  kParameterByteArray = 5,
  kParameterBoolArray = 6,
  kParameterIntegerArray = 7,
  kParameterDoubleArray = 8,
  kParameterStringArray = 9,
};

/// The NoDL spelling of a parameter type ("bool", "integer", ..., "string_array"); NULL for
/// "not set" and unknown values.
const char * parameter_type_name(uint8_t type);

/// rcl_interfaces/msg/ParameterValue: `type` says which member holds the value.
struct ParameterValue
{
  uint8_t type = kParameterNotSet;
  bool bool_value = false;
  int64_t integer_value = 0;
  double double_value = 0.0;
  std::string string_value;
  std::vector<uint8_t> byte_array_value;
  std::vector<bool> bool_array_value;
  std::vector<int64_t> integer_array_value;
  std::vector<double> double_array_value;
  std::vector<std::string> string_array_value;
};

struct IntegerRange
{
  int64_t from_value = 0;
  int64_t to_value = 0;
  uint64_t step = 0;
};

struct FloatingPointRange
{
  double from_value = 0.0;
  double to_value = 0.0;
  double step = 0.0;
};

/// One parameter: its descriptor (describe_parameters) and its value (get_parameters).
struct ParameterRecord
{
  std::string name;
  uint8_t descriptor_type = kParameterNotSet;
  ParameterValue value;  // type kParameterNotSet: declared without a value
  bool read_only = false;
  bool dynamic_typing = false;
  std::string description;
  std::string additional_constraints;
  bool has_integer_range = false;
  IntegerRange integer_range;
  bool has_floating_point_range = false;
  FloatingPointRange floating_point_range;
  /// "" = there when the parameters were first read; else the label of the lifecycle
  /// transition after which it first appeared ("configure").
  std::string declared_in;

  /// The value's type, else the descriptor's.
  uint8_t type() const { return value.type != kParameterNotSet ? value.type : descriptor_type; }
};

/// One change_state request the middleware sent.
struct LifecycleTransitionRecord
{
  enum class Result { kPending, kSuccess, kFailure, kNoAnswer };
  uint8_t id = 0;
  std::string label;
  Result result = Result::kPending;
};

struct LifecycleRecord
{
  std::string target;         // "active", "inactive", "unconfigured", "none"
  std::string initial_state;  // get_state before any transition ("" = not read)
  std::string state;          // get_state after the last transition ("" = not read)
  std::vector<LifecycleTransitionRecord> transitions;
  std::string error;          // "" = none
};

struct NodeProbe
{
  /// The parameters were read (the node has the parameter services and answered).
  bool has_parameters = false;
  std::vector<ParameterRecord> parameters;
  std::string parameters_error;  // why they could not be read ("" = no error)
  /// The node has the lifecycle services (change_state, get_state).
  bool has_lifecycle = false;
  LifecycleRecord lifecycle;
};

}  // namespace rmw_introspect

#endif  // DETAIL__NODE_PROBE_HPP_
