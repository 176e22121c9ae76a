// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Messages through the introspection type supports: CDR round trips (C, C++ and across the
// two), bounds and truncated input, and content filter expressions.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rosidl_runtime_c/primitives_sequence_functions.h"
#include "rosidl_runtime_c/string_functions.h"
#include "rosidl_typesupport_cpp/message_type_support.hpp"
#include "test_msgs/msg/arrays.h"
#include "test_msgs/msg/arrays.hpp"
#include "test_msgs/msg/basic_types.h"
#include "test_msgs/msg/basic_types.hpp"
#include "test_msgs/msg/bounded_plain_sequences.h"
#include "test_msgs/msg/bounded_plain_sequences.hpp"
#include "test_msgs/msg/multi_nested.hpp"
#include "test_msgs/msg/nested.h"
#include "test_msgs/msg/strings.h"
#include "test_msgs/msg/unbounded_sequences.h"
#include "test_msgs/msg/unbounded_sequences.hpp"
#include "test_msgs/msg/w_strings.hpp"

#include "detail/cdr.hpp"
#include "detail/content_filter.hpp"
#include "detail/typesupport.hpp"

using rmw_introspect::cdr_deserialize;
using rmw_introspect::cdr_serialize;
using rmw_introspect::ContentFilter;
using rmw_introspect::MessageLayout;

namespace
{
MessageLayout layout_of(const rosidl_message_type_support_t * ts)
{
  rmw_introspect::ResolvedType type;
  std::string error;
  EXPECT_TRUE(rmw_introspect::resolve_message_type(ts, &type, &error)) << error;
  MessageLayout layout;
  layout.members = type.members;
  layout.is_cpp = type.is_cpp;
  return layout;
}

template<typename T>
MessageLayout cpp_layout()
{
  return layout_of(rosidl_typesupport_cpp::get_message_type_support_handle<T>());
}

template<typename T>
T cpp_round_trip(const T & in, std::vector<uint8_t> * bytes = nullptr)
{
  const MessageLayout layout = cpp_layout<T>();
  std::vector<uint8_t> buffer;
  std::string error;
  EXPECT_TRUE(cdr_serialize(layout, &in, &buffer, &error)) << error;
  T out;
  EXPECT_TRUE(cdr_deserialize(layout, buffer.data(), buffer.size(), &out, &error)) << error;
  if (bytes) {
    *bytes = buffer;
  }
  return out;
}
}  // namespace

TEST(Cdr, header_and_primitives)
{
  test_msgs::msg::BasicTypes in;
  in.bool_value = true;
  in.byte_value = 0xab;
  in.char_value = 'k';
  in.float32_value = 3.5f;
  in.float64_value = -2.25;
  in.int8_value = -8;
  in.uint8_value = 200;
  in.int16_value = -1600;
  in.uint16_value = 60000;
  in.int32_value = -320000;
  in.uint32_value = 4000000000u;
  in.int64_value = -64;
  in.uint64_value = 0xfedcba9876543210ull;
  std::vector<uint8_t> bytes;
  EXPECT_EQ(in, cpp_round_trip(in, &bytes));
  ASSERT_GE(bytes.size(), 4u);
  EXPECT_EQ(0x00, bytes[0]);
  EXPECT_EQ(0x01, bytes[1]);  // little-endian plain CDR
  // bool, byte, char, (pad to 4) float32, float64 aligned to 8 in the body ...
  EXPECT_EQ(1u, bytes[4]);
  EXPECT_EQ(0xab, bytes[5]);
}

TEST(Cdr, cpp_nested_sequences_strings_and_bools)
{
  test_msgs::msg::MultiNested in;
  in.array_of_arrays[1].int32_values[2] = 42;
  in.array_of_arrays[2].string_values[0] = "in an array";
  in.array_of_bounded_sequences[0].bool_values = {true, false, true};
  in.array_of_unbounded_sequences[2].string_values = {"a", "", "ccc"};
  in.array_of_unbounded_sequences[2].float64_values = {1.5, -0.0, 1e300};
  in.unbounded_sequence_of_unbounded_sequences.resize(2);
  in.unbounded_sequence_of_unbounded_sequences[1].basic_types_values.resize(3);
  in.unbounded_sequence_of_unbounded_sequences[1].basic_types_values[2].uint64_value = 7;
  in.bounded_sequence_of_arrays.resize(1);
  in.bounded_sequence_of_arrays[0].bool_values = {true, true, false};
  EXPECT_EQ(in, cpp_round_trip(in));

  test_msgs::msg::BoundedPlainSequences bounded;
  bounded.bool_values.push_back(true);
  bounded.bool_values.push_back(false);
  bounded.int16_values.push_back(-7);
  EXPECT_EQ(bounded, cpp_round_trip(bounded));

  test_msgs::msg::WStrings w;
  w.wstring_value = u"wide \u00e9\u4e2d";
  w.array_of_wstrings[1] = u"x";
  w.unbounded_sequence_of_wstrings = {u"", u"yy"};
  EXPECT_EQ(w, cpp_round_trip(w));
}

TEST(Cdr, c_and_cpp_write_the_same_bytes)
{
  test_msgs__msg__UnboundedSequences c_in;
  ASSERT_TRUE(test_msgs__msg__UnboundedSequences__init(&c_in));
  ASSERT_TRUE(rosidl_runtime_c__boolean__Sequence__init(&c_in.bool_values, 2));
  c_in.bool_values.data[0] = false;  // __init does not clear primitive sequences
  c_in.bool_values.data[1] = true;
  ASSERT_TRUE(rosidl_runtime_c__int64__Sequence__init(&c_in.int64_values, 3));
  c_in.int64_values.data[0] = 0;
  c_in.int64_values.data[1] = 0;
  c_in.int64_values.data[2] = -99;
  ASSERT_TRUE(rosidl_runtime_c__String__Sequence__init(&c_in.string_values, 2));
  ASSERT_TRUE(rosidl_runtime_c__String__assign(&c_in.string_values.data[1], "second"));
  ASSERT_TRUE(test_msgs__msg__BasicTypes__Sequence__init(&c_in.basic_types_values, 1));
  c_in.basic_types_values.data[0].float32_value = 0.25f;
  c_in.alignment_check = 12345;

  const MessageLayout c_layout =
    layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, UnboundedSequences));
  ASSERT_FALSE(c_layout.is_cpp);
  const MessageLayout cpp = cpp_layout<test_msgs::msg::UnboundedSequences>();
  ASSERT_TRUE(cpp.is_cpp);
  std::vector<uint8_t> from_c;
  std::string error;
  ASSERT_TRUE(cdr_serialize(c_layout, &c_in, &from_c, &error)) << error;

  // C -> C++: the values arrive; C++ writes the same bytes back.
  test_msgs::msg::UnboundedSequences cpp_out;
  ASSERT_TRUE(cdr_deserialize(cpp, from_c.data(), from_c.size(), &cpp_out, &error)) << error;
  EXPECT_EQ((std::vector<bool>{false, true}), cpp_out.bool_values);
  EXPECT_EQ((std::vector<int64_t>{0, 0, -99}), cpp_out.int64_values);
  EXPECT_EQ((std::vector<std::string>{"", "second"}), cpp_out.string_values);
  ASSERT_EQ(1u, cpp_out.basic_types_values.size());
  EXPECT_EQ(0.25f, cpp_out.basic_types_values[0].float32_value);
  EXPECT_EQ(12345, cpp_out.alignment_check);
  std::vector<uint8_t> from_cpp;
  ASSERT_TRUE(cdr_serialize(cpp, &cpp_out, &from_cpp, &error)) << error;
  EXPECT_EQ(from_c, from_cpp);

  // ... and back into a C message already holding other data (it is resized, not leaked).
  test_msgs__msg__UnboundedSequences c_out;
  ASSERT_TRUE(test_msgs__msg__UnboundedSequences__init(&c_out));
  ASSERT_TRUE(rosidl_runtime_c__int64__Sequence__init(&c_out.int64_values, 10));
  ASSERT_TRUE(cdr_deserialize(c_layout, from_cpp.data(), from_cpp.size(), &c_out, &error)) << error;
  EXPECT_TRUE(test_msgs__msg__UnboundedSequences__are_equal(&c_in, &c_out));
  test_msgs__msg__UnboundedSequences__fini(&c_out);
  test_msgs__msg__UnboundedSequences__fini(&c_in);
}

TEST(Cdr, bounds_and_truncated_input)
{
  // C does not enforce sequence bounds (C++ BoundedVector throws): serialization does.
  const MessageLayout layout =
    layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BoundedPlainSequences));
  test_msgs__msg__BoundedPlainSequences too_long;
  ASSERT_TRUE(test_msgs__msg__BoundedPlainSequences__init(&too_long));
  ASSERT_TRUE(rosidl_runtime_c__int32__Sequence__init(&too_long.int32_values, 4));  // bound 3
  std::vector<uint8_t> bytes;
  std::string error;
  EXPECT_FALSE(cdr_serialize(layout, &too_long, &bytes, &error));
  EXPECT_NE(std::string::npos, error.find("int32_values")) << error;
  test_msgs__msg__BoundedPlainSequences__fini(&too_long);

  test_msgs::msg::MultiNested in;
  in.unbounded_sequence_of_bounded_sequences.resize(2);
  in.unbounded_sequence_of_bounded_sequences[1].string_values = {"abc", "de"};
  const MessageLayout nested = cpp_layout<test_msgs::msg::MultiNested>();
  ASSERT_TRUE(cdr_serialize(nested, &in, &bytes, &error)) << error;
  // Every strict prefix is refused, none crashes.
  for (size_t n = 0; n < bytes.size(); ++n) {
    test_msgs::msg::MultiNested out;
    EXPECT_FALSE(cdr_deserialize(nested, bytes.data(), n, &out, &error)) << n;
  }
  // A huge sequence length is refused before anything is allocated for it.
  std::vector<uint8_t> liar(bytes.begin(), bytes.begin() + 4);
  const uint8_t huge[4] = {0xff, 0xff, 0xff, 0x7f};
  liar.insert(liar.end(), huge, huge + 4);
  test_msgs::msg::UnboundedSequences out;
  EXPECT_FALSE(cdr_deserialize(
    cpp_layout<test_msgs::msg::UnboundedSequences>(), liar.data(), liar.size(), &out, &error));
}

TEST(ContentFilter, comparisons_on_a_c_message)
{
  const MessageLayout layout = layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BasicTypes));
  test_msgs__msg__BasicTypes msg;
  ASSERT_TRUE(test_msgs__msg__BasicTypes__init(&msg));
  msg.float32_value = 3.14159f;
  msg.int32_value = -5;
  msg.uint64_value = 18446744073709551615ull;
  msg.bool_value = true;
  std::string error;
  auto check = [&](const std::string & expression, const std::vector<std::string> & params) {
    auto filter = ContentFilter::compile(layout, expression, params, &error);
    EXPECT_NE(nullptr, filter) << expression << ": " << error;
    return filter && filter->matches(&msg);
  };
  // float32 fields compare in float precision (test_subscription.cpp's filters).
  EXPECT_TRUE(check("float32_value=%0", {"3.14159"}));
  EXPECT_FALSE(check("float32_value=%0", {"3.14"}));
  msg.float32_value = 3.14f;
  EXPECT_TRUE(check("float32_value = %0", {"3.14"}));
  EXPECT_TRUE(check("int32_value < 0 AND NOT (int32_value = -4)", {}));
  EXPECT_TRUE(check("int32_value > 0 OR bool_value = TRUE", {}));
  EXPECT_FALSE(check("int32_value <> -5", {}));
  EXPECT_TRUE(check("int32_value BETWEEN -10 AND %0", {"0"}));
  EXPECT_FALSE(check("int32_value NOT BETWEEN -10 AND 0", {}));
  EXPECT_TRUE(check("uint64_value > int32_value", {}));  // unsigned vs signed, exactly
  EXPECT_TRUE(check("uint64_value = 18446744073709551615", {}));
  test_msgs__msg__BasicTypes__fini(&msg);
}

TEST(ContentFilter, strings_nested_fields_and_arrays)
{
  test_msgs__msg__Strings strings;
  ASSERT_TRUE(test_msgs__msg__Strings__init(&strings));
  ASSERT_TRUE(rosidl_runtime_c__String__assign(&strings.string_value, "hello world"));
  const MessageLayout s_layout = layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, Strings));
  std::string error;
  auto s_filter = ContentFilter::compile(s_layout, "string_value LIKE %0", {"'hello%'"}, &error);
  ASSERT_NE(nullptr, s_filter) << error;
  EXPECT_TRUE(s_filter->matches(&strings));
  s_filter = ContentFilter::compile(s_layout, "string_value = 'hello_world'", {}, &error);
  ASSERT_NE(nullptr, s_filter) << error;
  EXPECT_FALSE(s_filter->matches(&strings));
  s_filter = ContentFilter::compile(s_layout, "string_value LIKE 'hello_world'", {}, &error);
  ASSERT_NE(nullptr, s_filter) << error;
  EXPECT_TRUE(s_filter->matches(&strings));
  test_msgs__msg__Strings__fini(&strings);

  test_msgs__msg__Nested nested;
  ASSERT_TRUE(test_msgs__msg__Nested__init(&nested));
  nested.basic_types_value.int16_value = 7;
  auto n_filter = ContentFilter::compile(
    layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, Nested)),
    "basic_types_value.int16_value >= 7", {}, &error);
  ASSERT_NE(nullptr, n_filter) << error;
  EXPECT_TRUE(n_filter->matches(&nested));
  test_msgs__msg__Nested__fini(&nested);

  test_msgs::msg::Arrays arrays;
  arrays.int32_values[1] = 11;
  arrays.basic_types_values[2].bool_value = true;
  auto a_filter = ContentFilter::compile(
    cpp_layout<test_msgs::msg::Arrays>(),
    "int32_values[1] = 11 AND basic_types_values[2].bool_value = TRUE", {}, &error);
  ASSERT_NE(nullptr, a_filter) << error;
  EXPECT_TRUE(a_filter->matches(&arrays));
  // An element that is not there makes the comparison false, not an error.
  test_msgs::msg::UnboundedSequences seq;
  auto u_filter = ContentFilter::compile(
    cpp_layout<test_msgs::msg::UnboundedSequences>(), "bool_values[4] = FALSE", {}, &error);
  ASSERT_NE(nullptr, u_filter) << error;
  EXPECT_FALSE(u_filter->matches(&seq));
  seq.bool_values.resize(5);
  EXPECT_TRUE(u_filter->matches(&seq));
}

TEST(ContentFilter, bad_expressions_are_refused)
{
  const MessageLayout layout = layout_of(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BasicTypes));
  std::string error;
  EXPECT_EQ(nullptr, ContentFilter::compile(layout, "no_such_field = 1", {}, &error));
  EXPECT_NE(std::string::npos, error.find("no_such_field")) << error;
  EXPECT_EQ(nullptr, ContentFilter::compile(layout, "int32_value = %1", {"1"}, &error));
  EXPECT_EQ(nullptr, ContentFilter::compile(layout, "int32_value = ", {}, &error));
  EXPECT_EQ(nullptr, ContentFilter::compile(layout, "(int32_value = 1", {}, &error));
  EXPECT_EQ(nullptr, ContentFilter::compile(layout, "int32_value = 1 1", {}, &error));
  EXPECT_EQ(nullptr, ContentFilter::compile(layout, "int32_value MATCH 'x'", {}, &error));
  EXPECT_EQ(nullptr, ContentFilter::compile(layout, "int32_value[0] = 1", {}, &error));
}
