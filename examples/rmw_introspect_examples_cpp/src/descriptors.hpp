// Parameter descriptors in one line each: a range, read-only, a description.
#ifndef DESCRIPTORS_HPP_
#define DESCRIPTORS_HPP_

#include <string>

#include "rcl_interfaces/msg/parameter_descriptor.hpp"

namespace rmw_introspect_examples_cpp
{

inline rcl_interfaces::msg::ParameterDescriptor described(
  const std::string & text, bool read_only = false)
{
  rcl_interfaces::msg::ParameterDescriptor descriptor;
  descriptor.description = text;
  descriptor.read_only = read_only;
  return descriptor;
}

inline rcl_interfaces::msg::ParameterDescriptor in_range(
  const std::string & text, double from, double to)
{
  auto descriptor = described(text);
  descriptor.floating_point_range.resize(1);
  descriptor.floating_point_range[0].from_value = from;
  descriptor.floating_point_range[0].to_value = to;
  return descriptor;
}

inline rcl_interfaces::msg::ParameterDescriptor in_range(
  const std::string & text, int64_t from, int64_t to, uint64_t step)
{
  auto descriptor = described(text);
  descriptor.integer_range.resize(1);
  descriptor.integer_range[0].from_value = from;
  descriptor.integer_range[0].to_value = to;
  descriptor.integer_range[0].step = step;
  return descriptor;
}

}  // namespace rmw_introspect_examples_cpp

#endif  // DESCRIPTORS_HPP_
