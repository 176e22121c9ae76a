// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Building requests and reading responses through the C and the C++ introspection type
// supports (the layouts rclpy and rclcpp hand to rmw_take_request / rmw_send_response):
// rcl_interfaces and lifecycle_msgs services, and test_msgs for nested messages, fixed
// arrays, bounded and unbounded sequences, bounded strings and wstrings.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "lifecycle_msgs/srv/change_state.h"
#include "lifecycle_msgs/srv/change_state.hpp"
#include "rcl_interfaces/msg/floating_point_range.h"
#include "rcl_interfaces/msg/integer_range.h"
#include "rcl_interfaces/msg/parameter_descriptor.h"
#include "rcl_interfaces/srv/describe_parameters.h"
#include "rcl_interfaces/srv/describe_parameters.hpp"
#include "rcl_interfaces/srv/get_parameters.h"
#include "rcl_interfaces/srv/get_parameters.hpp"
#include "rosidl_runtime_c/string_functions.h"
#include "rosidl_typesupport_cpp/message_type_support.hpp"
#include "rosidl_typesupport_cpp/service_type_support.hpp"
#include "rosidl_typesupport_introspection_c/message_introspection.h"
#include "rosidl_typesupport_introspection_cpp/message_introspection.hpp"
#include "test_msgs/msg/arrays.h"
#include "test_msgs/msg/arrays.hpp"
#include "test_msgs/msg/basic_types.h"
#include "test_msgs/msg/bounded_sequences.h"
#include "test_msgs/msg/bounded_sequences.hpp"
#include "test_msgs/msg/multi_nested.h"
#include "test_msgs/msg/multi_nested.hpp"
#include "test_msgs/msg/strings.h"
#include "test_msgs/msg/unbounded_sequences.h"
#include "test_msgs/msg/unbounded_sequences.hpp"
#include "test_msgs/msg/strings.hpp"
#include "test_msgs/msg/w_strings.h"
#include "test_msgs/msg/w_strings.hpp"

#include "detail/dynamic_value.hpp"
#include "detail/message_walker.hpp"
#include "detail/typesupport.hpp"

using rmw_introspect::DynValue;
using rmw_introspect::MessageLayout;

namespace
{

MessageLayout layout_of(const rosidl_message_type_support_t * ts)
{
  rmw_introspect::ResolvedType type;
  std::string error;
  EXPECT_TRUE(rmw_introspect::resolve_message_type(ts, &type, &error)) << error;
  return MessageLayout{type.members, type.is_cpp};
}

template<typename CppMsg>
MessageLayout cpp_layout()
{
  return layout_of(rosidl_typesupport_cpp::get_message_type_support_handle<CppMsg>());
}

std::pair<MessageLayout, MessageLayout> service_layouts(const rosidl_service_type_support_t * ts)
{
  rmw_introspect::ResolvedType type;
  std::string error;
  EXPECT_TRUE(rmw_introspect::resolve_service_type(ts, &type, &error)) << error;
  MessageLayout request, response;
  EXPECT_TRUE(rmw_introspect::service_message_layouts(type, &request, &response, &error)) << error;
  return {request, response};
}

// A message of `layout` made and destroyed through its own init / fini functions.
class Message
{
public:
  explicit Message(const MessageLayout & layout)
  : layout_(layout)
  {
    if (layout.is_cpp) {
      const auto * m =
        static_cast<const rosidl_typesupport_introspection_cpp::MessageMembers *>(layout.members);
      memory_.reset(new std::max_align_t[m->size_of_ / sizeof(std::max_align_t) + 1]);
      m->init_function(memory_.get(), rosidl_runtime_cpp::MessageInitialization::ALL);
    } else {
      const auto * m =
        static_cast<const rosidl_typesupport_introspection_c__MessageMembers *>(layout.members);
      memory_.reset(new std::max_align_t[m->size_of_ / sizeof(std::max_align_t) + 1]);
      m->init_function(memory_.get(), ROSIDL_RUNTIME_C_MSG_INIT_ALL);
    }
  }
  ~Message()
  {
    if (layout_.is_cpp) {
      static_cast<const rosidl_typesupport_introspection_cpp::MessageMembers *>(layout_.members)
        ->fini_function(memory_.get());
    } else {
      static_cast<const rosidl_typesupport_introspection_c__MessageMembers *>(layout_.members)
        ->fini_function(memory_.get());
    }
  }
  Message(const Message &) = delete;
  Message & operator=(const Message &) = delete;
  void * get() { return memory_.get(); }

private:
  MessageLayout layout_;
  std::unique_ptr<std::max_align_t[]> memory_;
};

DynValue read(const MessageLayout & layout, const void * msg)
{
  DynValue out;
  std::string error;
  EXPECT_TRUE(rmw_introspect::read_message(layout, msg, &out, &error)) << error;
  return out;
}

void write(const MessageLayout & layout, const DynValue & value, void * msg)
{
  std::string error;
  ASSERT_TRUE(rmw_introspect::write_message(layout, value, msg, &error)) << error;
}

std::string write_error(const MessageLayout & layout, const DynValue & value)
{
  Message msg(layout);
  std::string error;
  EXPECT_FALSE(rmw_introspect::write_message(layout, value, msg.get(), &error));
  return error;
}

const DynValue & at(const DynValue & v, const std::string & path)
{
  const DynValue * cur = &v;
  size_t start = 0;
  while (start <= path.size()) {
    size_t end = path.find('.', start);
    if (end == std::string::npos) {
      end = path.size();
    }
    const std::string part = path.substr(start, end - start);
    if (!part.empty() && std::isdigit(static_cast<unsigned char>(part[0]))) {
      const size_t k = std::stoul(part);
      EXPECT_LT(k, cur->items.size()) << path;
      cur = &cur->items.at(k);
    } else {
      cur = cur->field(part);
      EXPECT_NE(nullptr, cur) << path;
      if (cur == nullptr) {
        static DynValue none;
        return none;
      }
    }
    start = end + 1;
  }
  return *cur;
}

// A value of every primitive kind for test_msgs/BasicTypes.
DynValue basic_types(int k)
{
  DynValue v = DynValue::structure();
  v.set("bool_value", DynValue::boolean(k % 2 == 1));
  v.set("byte_value", DynValue::uinteger(200 + k));
  v.set("char_value", DynValue::uinteger(65 + k));
  v.set("float32_value", DynValue::real(1.5 * k));
  v.set("float64_value", DynValue::real(-2.25 * k));
  v.set("int8_value", DynValue::integer(-100 - k));
  v.set("uint8_value", DynValue::uinteger(250 + k));
  v.set("int16_value", DynValue::integer(-30000 - k));
  v.set("uint16_value", DynValue::uinteger(65530 + k));
  v.set("int32_value", DynValue::integer(-2000000000 - k));
  v.set("uint32_value", DynValue::uinteger(4000000000u + k));
  v.set("int64_value", DynValue::integer(std::numeric_limits<int64_t>::min() + k));
  v.set("uint64_value", DynValue::uinteger(std::numeric_limits<uint64_t>::max() - k));
  return v;
}

void expect_basic_types(const DynValue & v, int k)
{
  EXPECT_EQ(k % 2 == 1, at(v, "bool_value").b);
  EXPECT_EQ(200u + k, at(v, "byte_value").u);
  EXPECT_EQ(65u + k, at(v, "char_value").u);
  EXPECT_DOUBLE_EQ(1.5 * k, at(v, "float32_value").d);
  EXPECT_DOUBLE_EQ(-2.25 * k, at(v, "float64_value").d);
  EXPECT_EQ(-100 - k, at(v, "int8_value").i);
  EXPECT_EQ(250u + k, at(v, "uint8_value").u);
  EXPECT_EQ(-30000 - k, at(v, "int16_value").i);
  EXPECT_EQ(65530u + k, at(v, "uint16_value").u);
  EXPECT_EQ(-2000000000 - k, at(v, "int32_value").i);
  EXPECT_EQ(4000000000u + k, at(v, "uint32_value").u);
  EXPECT_EQ(std::numeric_limits<int64_t>::min() + k, at(v, "int64_value").i);
  EXPECT_EQ(std::numeric_limits<uint64_t>::max() - k, at(v, "uint64_value").u);
}

}  // namespace

// ----------------------------------------------------------------- rcl_interfaces, C (rclpy)
TEST(MessageWalkerC, builds_a_get_parameters_request_rclpy_takes)
{
  auto layouts = service_layouts(ROSIDL_GET_SRV_TYPE_SUPPORT(rcl_interfaces, srv, GetParameters));
  EXPECT_EQ(
    "rcl_interfaces/srv/GetParameters_Request", rmw_introspect::layout_type_name(layouts.first));
  rcl_interfaces__srv__GetParameters_Request * req =
    rcl_interfaces__srv__GetParameters_Request__create();
  ASSERT_NE(nullptr, req);
  DynValue value = DynValue::structure();
  value.set("names", rmw_introspect::string_sequence({"a", "nested.b", "ünïcode"}));
  write(layouts.first, value, req);
  ASSERT_EQ(3u, req->names.size);
  EXPECT_STREQ("a", req->names.data[0].data);
  EXPECT_STREQ("nested.b", req->names.data[1].data);
  EXPECT_STREQ("ünïcode", req->names.data[2].data);
  // Writing again resizes (shrinks) the sequence.
  value.set("names", rmw_introspect::string_sequence({"only"}));
  write(layouts.first, value, req);
  ASSERT_EQ(1u, req->names.size);
  EXPECT_STREQ("only", req->names.data[0].data);
  rcl_interfaces__srv__GetParameters_Request__destroy(req);
}

TEST(MessageWalkerC, reads_a_describe_parameters_response_rclpy_sends)
{
  auto layouts =
    service_layouts(ROSIDL_GET_SRV_TYPE_SUPPORT(rcl_interfaces, srv, DescribeParameters));
  rcl_interfaces__srv__DescribeParameters_Response * res =
    rcl_interfaces__srv__DescribeParameters_Response__create();
  ASSERT_TRUE(rcl_interfaces__msg__ParameterDescriptor__Sequence__init(&res->descriptors, 2));
  auto & d0 = res->descriptors.data[0];
  rosidl_runtime_c__String__assign(&d0.name, "gain");
  d0.type = 3;
  rosidl_runtime_c__String__assign(&d0.description, "loop gain");
  rosidl_runtime_c__String__assign(&d0.additional_constraints, "> 0");
  d0.read_only = true;
  ASSERT_TRUE(rcl_interfaces__msg__FloatingPointRange__Sequence__init(&d0.floating_point_range, 1));
  d0.floating_point_range.data[0].from_value = 0.0;
  d0.floating_point_range.data[0].to_value = 10.5;
  d0.floating_point_range.data[0].step = 0.5;
  auto & d1 = res->descriptors.data[1];
  rosidl_runtime_c__String__assign(&d1.name, "count");
  d1.type = 2;
  d1.dynamic_typing = true;
  ASSERT_TRUE(rcl_interfaces__msg__IntegerRange__Sequence__init(&d1.integer_range, 1));
  d1.integer_range.data[0].from_value = -5;
  d1.integer_range.data[0].to_value = 5;
  d1.integer_range.data[0].step = 1;

  const DynValue v = read(layouts.second, res);
  ASSERT_EQ(2u, at(v, "descriptors").items.size());
  EXPECT_EQ("gain", at(v, "descriptors.0.name").s);
  EXPECT_EQ(3u, at(v, "descriptors.0.type").u);
  EXPECT_EQ("loop gain", at(v, "descriptors.0.description").s);
  EXPECT_EQ("> 0", at(v, "descriptors.0.additional_constraints").s);
  EXPECT_TRUE(at(v, "descriptors.0.read_only").b);
  EXPECT_FALSE(at(v, "descriptors.0.dynamic_typing").b);
  EXPECT_DOUBLE_EQ(10.5, at(v, "descriptors.0.floating_point_range.0.to_value").d);
  EXPECT_TRUE(at(v, "descriptors.0.integer_range").items.empty());
  EXPECT_EQ(-5, at(v, "descriptors.1.integer_range.0.from_value").i);
  EXPECT_EQ(1u, at(v, "descriptors.1.integer_range.0.step").u);
  EXPECT_TRUE(at(v, "descriptors.1.dynamic_typing").b);
  rcl_interfaces__srv__DescribeParameters_Response__destroy(res);
}

// ----------------------------------------------------------------- rcl_interfaces, C++ (rclcpp)
TEST(MessageWalkerCpp, builds_requests_rclcpp_takes)
{
  auto layouts = service_layouts(
    rosidl_typesupport_cpp::get_service_type_support_handle<rcl_interfaces::srv::GetParameters>());
  ASSERT_TRUE(layouts.first.is_cpp);
  rcl_interfaces::srv::GetParameters::Request req;
  DynValue value = DynValue::structure();
  value.set("names", rmw_introspect::string_sequence({"x", "y.z"}));
  write(layouts.first, value, &req);
  EXPECT_EQ((std::vector<std::string>{"x", "y.z"}), req.names);

  auto lc = service_layouts(
    rosidl_typesupport_cpp::get_service_type_support_handle<lifecycle_msgs::srv::ChangeState>());
  lifecycle_msgs::srv::ChangeState::Request change;
  DynValue transition = DynValue::structure();
  transition.set("id", DynValue::uinteger(3)).set("label", DynValue::string("activate"));
  DynValue request = DynValue::structure();
  request.set("transition", transition);
  write(lc.first, request, &change);
  EXPECT_EQ(3, change.transition.id);
  EXPECT_EQ("activate", change.transition.label);
}

TEST(MessageWalkerCpp, reads_a_get_parameters_response_with_every_value_kind)
{
  auto layouts = service_layouts(
    rosidl_typesupport_cpp::get_service_type_support_handle<rcl_interfaces::srv::GetParameters>());
  rcl_interfaces::srv::GetParameters::Response res;
  rcl_interfaces::msg::ParameterValue v;
  v.type = 6;
  v.bool_array_value = {true, false, true};  // std::vector<bool>: fetch, no get function
  res.values.push_back(v);
  v = rcl_interfaces::msg::ParameterValue();
  v.type = 5;
  v.byte_array_value = {0, 255, 7};
  res.values.push_back(v);
  v = rcl_interfaces::msg::ParameterValue();
  v.type = 9;
  v.string_array_value = {"a", "b"};
  v.double_array_value = {0.1, -1e300};
  v.integer_array_value = {std::numeric_limits<int64_t>::min()};
  res.values.push_back(v);
  const DynValue r = read(layouts.second, &res);
  ASSERT_EQ(3u, at(r, "values").items.size());
  EXPECT_EQ(6u, at(r, "values.0.type").u);
  const DynValue & bools = at(r, "values.0.bool_array_value");
  ASSERT_EQ(3u, bools.items.size());
  EXPECT_TRUE(bools.items[0].b);
  EXPECT_FALSE(bools.items[1].b);
  EXPECT_TRUE(bools.items[2].b);
  EXPECT_EQ(255u, at(r, "values.1.byte_array_value.1").u);
  EXPECT_EQ("b", at(r, "values.2.string_array_value.1").s);
  EXPECT_DOUBLE_EQ(-1e300, at(r, "values.2.double_array_value.1").d);
  EXPECT_EQ(std::numeric_limits<int64_t>::min(), at(r, "values.2.integer_array_value.0").i);

  // And back: vector<bool> written through the assign function.
  rcl_interfaces::srv::GetParameters::Response copy;
  write(layouts.second, r, &copy);
  EXPECT_EQ(res, copy);
}

// ----------------------------------------------------------------- test_msgs, both layouts
template<typename ArraysT>
void arrays_round_trip(const MessageLayout & layout)
{
  DynValue v = DynValue::structure();
  DynValue nested = DynValue::sequence();
  for (int k = 0; k < 3; ++k) {
    nested.push(basic_types(k));
  }
  v.set("basic_types_values", nested);
  v.set(
    "int8_values",
    DynValue::sequence({DynValue::integer(-128), DynValue::integer(0), DynValue::integer(127)}));
  v.set(
    "bool_values",
    DynValue::sequence(
      {DynValue::boolean(true), DynValue::boolean(false), DynValue::boolean(true)}));
  v.set("string_values", rmw_introspect::string_sequence({"one", "", "three"}));
  v.set("alignment_check", DynValue::integer(42));
  ArraysT msg;
  write(layout, v, &msg);
  const DynValue r = read(layout, &msg);
  for (int k = 0; k < 3; ++k) {
    expect_basic_types(at(r, "basic_types_values." + std::to_string(k)), k);
  }
  EXPECT_EQ(-128, at(r, "int8_values.0").i);
  EXPECT_EQ(127, at(r, "int8_values.2").i);
  EXPECT_TRUE(at(r, "bool_values.2").b);
  EXPECT_EQ("three", at(r, "string_values.2").s);
  EXPECT_EQ("", at(r, "string_values.1").s);
  EXPECT_EQ(42, at(r, "alignment_check").i);
  // Defaults the writer left alone are read as they are.
  EXPECT_EQ("max value", at(r, "string_values_default.1").s);
  EXPECT_EQ(std::numeric_limits<uint64_t>::max(), at(r, "uint64_values_default.2").u);
  EXPECT_DOUBLE_EQ(-3.1415, at(r, "float64_values_default.2").d);
}

TEST(MessageWalkerC, fixed_arrays_of_primitives_strings_and_nested_messages)
{
  struct CArrays : test_msgs__msg__Arrays
  {
    CArrays() { test_msgs__msg__Arrays__init(this); }
    ~CArrays() { test_msgs__msg__Arrays__fini(this); }
  };
  arrays_round_trip<CArrays>(layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, Arrays)));
}

TEST(MessageWalkerCpp, fixed_arrays_of_primitives_strings_and_nested_messages)
{
  arrays_round_trip<test_msgs::msg::Arrays>(cpp_layout<test_msgs::msg::Arrays>());
}

void bounded_sequences(const MessageLayout & layout)
{
  Message msg(layout);
  DynValue v = DynValue::structure();
  v.set("uint16_values", DynValue::sequence({DynValue::uinteger(1), DynValue::uinteger(65535)}));
  v.set("basic_types_values", DynValue::sequence({basic_types(1)}));
  v.set("string_values", rmw_introspect::string_sequence({"x", "y", "z"}));
  write(layout, v, msg.get());
  const DynValue r = read(layout, msg.get());
  ASSERT_EQ(2u, at(r, "uint16_values").items.size());
  EXPECT_EQ(65535u, at(r, "uint16_values.1").u);
  ASSERT_EQ(1u, at(r, "basic_types_values").items.size());
  expect_basic_types(at(r, "basic_types_values.0"), 1);
  EXPECT_TRUE(at(r, "bool_values").items.empty());
  EXPECT_EQ(3u, at(r, "bool_values_default").items.size());

  // A fourth item does not fit a sequence bounded to 3.
  DynValue too_long = DynValue::structure();
  too_long.set("string_values", rmw_introspect::string_sequence({"1", "2", "3", "4"}));
  EXPECT_EQ("string_values: 4 items for an array of at most 3", write_error(layout, too_long));
}

TEST(MessageWalkerC, bounded_sequences)
{
  bounded_sequences(layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BoundedSequences)));
}

TEST(MessageWalkerCpp, bounded_sequences)
{
  bounded_sequences(cpp_layout<test_msgs::msg::BoundedSequences>());
}

void multi_nested(const MessageLayout & layout)
{
  Message msg(layout);
  DynValue inner = DynValue::structure();
  inner.set("int32_values", DynValue::sequence({DynValue::integer(-7)}));
  inner.set("string_values", rmw_introspect::string_sequence({"deep"}));
  DynValue v = DynValue::structure();
  v.set(
    "unbounded_sequence_of_unbounded_sequences",
    DynValue::sequence({DynValue::structure(), inner}));
  v.set("bounded_sequence_of_bounded_sequences", DynValue::sequence({inner}));
  write(layout, v, msg.get());
  const DynValue r = read(layout, msg.get());
  EXPECT_EQ(2u, at(r, "unbounded_sequence_of_unbounded_sequences").items.size());
  EXPECT_EQ(-7, at(r, "unbounded_sequence_of_unbounded_sequences.1.int32_values.0").i);
  EXPECT_EQ("deep", at(r, "unbounded_sequence_of_unbounded_sequences.1.string_values.0").s);
  EXPECT_EQ("deep", at(r, "bounded_sequence_of_bounded_sequences.0.string_values.0").s);
  EXPECT_EQ(3u, at(r, "array_of_arrays").items.size());
  EXPECT_EQ(0u, at(r, "unbounded_sequence_of_arrays").items.size());

  DynValue bad = DynValue::structure();
  DynValue wrong = DynValue::structure();
  wrong.set("int32_values", DynValue::sequence({DynValue::string("seven")}));
  bad.set("unbounded_sequence_of_unbounded_sequences", DynValue::sequence({wrong}));
  EXPECT_EQ(
    "unbounded_sequence_of_unbounded_sequences[0].int32_values[0]: value of the wrong kind or out "
    "of range",
    write_error(layout, bad));
}

TEST(MessageWalkerC, nested_sequences_of_messages)
{
  multi_nested(layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, MultiNested)));
}

TEST(MessageWalkerCpp, nested_sequences_of_messages)
{
  multi_nested(cpp_layout<test_msgs::msg::MultiNested>());
}

void strings(const MessageLayout & strings_layout, const MessageLayout & wstrings_layout)
{
  {
    Message msg(strings_layout);
    DynValue v = DynValue::structure();
    v.set("string_value", DynValue::string("hello \"world\""));
    v.set("bounded_string_value", DynValue::string(std::string(22, 'x')));
    write(strings_layout, v, msg.get());
    const DynValue r = read(strings_layout, msg.get());
    EXPECT_EQ("hello \"world\"", at(r, "string_value").s);
    EXPECT_EQ(std::string(22, 'x'), at(r, "bounded_string_value").s);
    EXPECT_EQ("Hello'world!", at(r, "string_value_default2").s);
    DynValue too_long = DynValue::structure();
    too_long.set("bounded_string_value", DynValue::string(std::string(23, 'x')));
    EXPECT_EQ(
      "bounded_string_value: string longer than its bound 22",
      write_error(strings_layout, too_long));
  }
  Message msg(wstrings_layout);
  DynValue v = DynValue::structure();
  v.set("wstring_value", DynValue::string("ハロー 🤖"));
  v.set("array_of_wstrings", rmw_introspect::string_sequence({"a", "ö", "ワ"}));
  v.set("unbounded_sequence_of_wstrings", rmw_introspect::string_sequence({"x"}));
  write(wstrings_layout, v, msg.get());
  const DynValue r = read(wstrings_layout, msg.get());
  EXPECT_EQ("ハロー 🤖", at(r, "wstring_value").s);
  EXPECT_EQ("ö", at(r, "array_of_wstrings.1").s);
  EXPECT_EQ("x", at(r, "unbounded_sequence_of_wstrings.0").s);
  EXPECT_EQ("Hellö wörld!", at(r, "wstring_value_default2").s);
}

TEST(MessageWalkerC, strings_bounded_strings_and_wstrings)
{
  strings(
    layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, Strings)),
    layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, WStrings)));
}

TEST(MessageWalkerCpp, strings_bounded_strings_and_wstrings)
{
  strings(cpp_layout<test_msgs::msg::Strings>(), cpp_layout<test_msgs::msg::WStrings>());
}

void rejects(const MessageLayout & layout)
{
  DynValue v = DynValue::structure();
  v.set("no_such_field", DynValue::integer(1));
  EXPECT_EQ(
    "no_such_field: no such field in test_msgs/msg/BoundedSequences", write_error(layout, v));
  v = DynValue::structure();
  v.set("int8_values", DynValue::sequence({DynValue::integer(128)}));
  EXPECT_EQ("int8_values[0]: value of the wrong kind or out of range", write_error(layout, v));
  v = DynValue::structure();
  v.set("uint8_values", DynValue::sequence({DynValue::integer(-1)}));
  EXPECT_EQ("uint8_values[0]: value of the wrong kind or out of range", write_error(layout, v));
  v = DynValue::structure();
  v.set("bool_values", DynValue::sequence({DynValue::integer(2)}));
  EXPECT_EQ("bool_values[0]: value of the wrong kind or out of range", write_error(layout, v));
  v = DynValue::structure();
  v.set("alignment_check", DynValue::string("x"));
  EXPECT_EQ("alignment_check: value of the wrong kind or out of range", write_error(layout, v));
  v = DynValue::structure();
  v.set("string_values", DynValue::string("not a sequence"));
  EXPECT_EQ("string_values: expects a sequence", write_error(layout, v));
  v = DynValue::structure();
  v.set("basic_types_values", DynValue::sequence({DynValue::integer(1)}));
  EXPECT_EQ("basic_types_values[0]: a message needs a struct value", write_error(layout, v));
  EXPECT_EQ("a message needs a struct value", write_error(layout, DynValue::integer(3)));
  // Integral doubles are integers; others are not.
  v = DynValue::structure();
  v.set("alignment_check", DynValue::real(7.0));
  Message msg(layout);
  std::string error;
  EXPECT_TRUE(rmw_introspect::write_message(layout, v, msg.get(), &error)) << error;
  v.set("alignment_check", DynValue::real(7.5));
  EXPECT_EQ("alignment_check: value of the wrong kind or out of range", write_error(layout, v));
}

TEST(MessageWalkerC, rejects_what_does_not_fit)
{
  rejects(layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BoundedSequences)));
}

TEST(MessageWalkerCpp, rejects_what_does_not_fit)
{
  rejects(cpp_layout<test_msgs::msg::BoundedSequences>());
}

// A sequence written from a value holds the value's items and nothing of before: fields the
// value leaves out are at their defaults, in C and C++ alike.
TEST(MessageWalkerC, a_written_sequence_keeps_nothing_of_before)
{
  const MessageLayout layout =
    layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, UnboundedSequences));
  Message msg(layout);
  auto * c_msg = static_cast<test_msgs__msg__UnboundedSequences *>(msg.get());
  ASSERT_TRUE(test_msgs__msg__BasicTypes__Sequence__init(&c_msg->basic_types_values, 1));
  c_msg->basic_types_values.data[0].int32_value = 5;
  DynValue item = DynValue::structure();
  item.set("bool_value", DynValue::boolean(true));
  DynValue v = DynValue::structure();
  v.set("basic_types_values", DynValue::sequence({item}));
  write(layout, v, msg.get());
  const DynValue r = read(layout, msg.get());
  EXPECT_TRUE(at(r, "basic_types_values.0.bool_value").b);
  EXPECT_EQ(0, at(r, "basic_types_values.0.int32_value").i);
}

TEST(MessageWalkerCpp, a_written_sequence_keeps_nothing_of_before)
{
  const MessageLayout layout = cpp_layout<test_msgs::msg::UnboundedSequences>();
  test_msgs::msg::UnboundedSequences msg;
  msg.basic_types_values.resize(1);
  msg.basic_types_values[0].int32_value = 5;
  DynValue item = DynValue::structure();
  item.set("bool_value", DynValue::boolean(true));
  DynValue v = DynValue::structure();
  v.set("basic_types_values", DynValue::sequence({item}));
  write(layout, v, &msg);
  ASSERT_EQ(1u, msg.basic_types_values.size());
  EXPECT_TRUE(msg.basic_types_values[0].bool_value);
  EXPECT_EQ(0, msg.basic_types_values[0].int32_value);
}

TEST(MessageWalker, checks_its_arguments)
{
  DynValue out;
  std::string error;
  EXPECT_FALSE(rmw_introspect::read_message(MessageLayout{}, &out, &out, &error));
  EXPECT_EQ("no introspection members", error);
  const MessageLayout layout = layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, Strings));
  EXPECT_FALSE(rmw_introspect::read_message(layout, nullptr, &out, &error));
  EXPECT_FALSE(rmw_introspect::read_message(layout, &out, nullptr, &error));
  EXPECT_FALSE(rmw_introspect::write_message(layout, DynValue::structure(), nullptr, &error));
  rmw_introspect::ResolvedType empty;
  MessageLayout a, b;
  EXPECT_FALSE(rmw_introspect::service_message_layouts(empty, &a, &b, &error));
  EXPECT_EQ("", rmw_introspect::layout_type_name(MessageLayout{}));
}
