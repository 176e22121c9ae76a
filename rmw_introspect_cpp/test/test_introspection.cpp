// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The traits of the C and C++ introspection type supports (detail/introspection.hpp): the one
// member dispatch, the array helpers and the element loop, and the one behaviour of `resize`
// for both type supports, on real test_msgs types and on members whose functions fail.

#include <gtest/gtest.h>

#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "rosidl_runtime_c/primitives_sequence_functions.h"
#include "rosidl_typesupport_cpp/message_type_support.hpp"
#include "test_msgs/msg/arrays.h"
#include "test_msgs/msg/arrays.hpp"
#include "test_msgs/msg/basic_types.h"
#include "test_msgs/msg/bounded_sequences.h"
#include "test_msgs/msg/bounded_sequences.hpp"
#include "test_msgs/msg/nested.h"
#include "test_msgs/msg/strings.h"
#include "test_msgs/msg/unbounded_sequences.h"
#include "test_msgs/msg/unbounded_sequences.hpp"
#include "test_msgs/msg/w_strings.h"

#include "detail/cdr.hpp"
#include "detail/dynamic_value.hpp"
#include "detail/introspection.hpp"
#include "detail/message_walker.hpp"
#include "detail/typesupport.hpp"

namespace ri = rmw_introspect::introspection;
using rmw_introspect::FieldArray;
using rmw_introspect::MessageLayout;

namespace
{

template<typename T>
const typename T::Members * members_of(const rosidl_message_type_support_t * ts)
{
  rmw_introspect::ResolvedType type;
  std::string error;
  EXPECT_TRUE(rmw_introspect::resolve_message_type(ts, &type, &error)) << error;
  EXPECT_EQ(T::kCpp, type.is_cpp);
  return static_cast<const typename T::Members *>(type.members);
}

template<typename Msg>
const ri::Cpp::Members * cpp_members()
{
  return members_of<ri::Cpp>(rosidl_typesupport_cpp::get_message_type_support_handle<Msg>());
}

template<typename T>
const typename T::Member & member(const typename T::Members * members, const std::string & name)
{
  const typename T::Member * m = ri::find_member<T>(members, name);
  EXPECT_NE(nullptr, m) << name;
  return *m;
}

// Counts what the dispatch called, per kind.
template<typename T>
struct Kinds
{
  std::vector<std::string> * seen;
  bool primitive(const typename T::Member &, std::nullptr_t, size_t size)
  {
    seen->push_back("primitive" + std::to_string(size));
    return true;
  }
  bool string(const typename T::Member &, std::nullptr_t)
  {
    seen->push_back("string");
    return true;
  }
  bool wstring(const typename T::Member &, std::nullptr_t)
  {
    seen->push_back("wstring");
    return true;
  }
  bool message(const typename T::Member &, std::nullptr_t, const typename T::Members * nested)
  {
    seen->push_back("message " + (nested ? ri::type_name_of<T>(nested) : std::string("?")));
    return true;
  }
  bool unknown(const typename T::Member &, std::nullptr_t)
  {
    seen->push_back("unknown");
    return false;
  }
};

template<typename T>
std::string kind_of(const typename T::Member & m)
{
  std::vector<std::string> seen;
  ri::dispatch<T>(m, nullptr, Kinds<T>{&seen});
  EXPECT_EQ(1u, seen.size());
  return seen.empty() ? std::string() : seen[0];
}

// Sequence members whose resize function fails in the ways a C++ one can.
void resize_throws_bad_alloc(void *, size_t size)
{
  if (size > 0u) {
    throw std::bad_alloc();
  }
}
void resize_throws_anything(void *, size_t size)
{
  if (size > 0u) {
    throw 42;
  }
}

}  // namespace

TEST(IntrospectionDispatch, reaches_each_kind_with_the_field_types_own_size)
{
  const auto * c_nested = members_of<ri::C>(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, Nested));
  EXPECT_EQ(
    "message test_msgs/msg/BasicTypes",
    kind_of<ri::C>(member<ri::C>(c_nested, "basic_types_value")));
  const auto * c_basic = members_of<ri::C>(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BasicTypes));
  EXPECT_EQ("primitive1", kind_of<ri::C>(member<ri::C>(c_basic, "bool_value")));
  EXPECT_EQ("primitive2", kind_of<ri::C>(member<ri::C>(c_basic, "uint16_value")));
  EXPECT_EQ("primitive4", kind_of<ri::C>(member<ri::C>(c_basic, "float32_value")));
  EXPECT_EQ("primitive8", kind_of<ri::C>(member<ri::C>(c_basic, "int64_value")));
  const auto * c_strings = members_of<ri::C>(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, Strings));
  EXPECT_EQ("string", kind_of<ri::C>(member<ri::C>(c_strings, "bounded_string_value")));
  const auto * c_wstrings =
    members_of<ri::C>(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, WStrings));
  EXPECT_EQ("wstring", kind_of<ri::C>(member<ri::C>(c_wstrings, "wstring_value")));
  // An array member dispatches on its element type.
  const auto * cpp_arrays = cpp_members<test_msgs::msg::Arrays>();
  EXPECT_EQ(
    "message test_msgs/msg/BasicTypes",
    kind_of<ri::Cpp>(member<ri::Cpp>(cpp_arrays, "basic_types_values")));
  EXPECT_EQ("string", kind_of<ri::Cpp>(member<ri::Cpp>(cpp_arrays, "string_values")));

  // A type id neither type support defines, and a nested type without a type support.
  ri::Cpp::Member odd = member<ri::Cpp>(cpp_arrays, "int32_values");
  odd.type_id_ = 200;
  EXPECT_EQ("unknown", kind_of<ri::Cpp>(odd));
  ri::Cpp::Member lost = member<ri::Cpp>(cpp_arrays, "basic_types_values");
  lost.members_ = nullptr;
  EXPECT_EQ("message ?", kind_of<ri::Cpp>(lost));
}

TEST(IntrospectionArrays, shapes_counts_and_blocks)
{
  const auto * c = members_of<ri::C>(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BoundedSequences));
  EXPECT_EQ(FieldArray::Bounded, ri::array_of<ri::C>(member<ri::C>(c, "int32_values")));
  EXPECT_EQ(FieldArray::None, ri::array_of<ri::C>(member<ri::C>(c, "alignment_check")));
  const auto * cpp = cpp_members<test_msgs::msg::Arrays>();
  EXPECT_EQ(FieldArray::Fixed, ri::array_of<ri::Cpp>(member<ri::Cpp>(cpp, "bool_values")));
  const auto * seqs = cpp_members<test_msgs::msg::UnboundedSequences>();
  const auto & bools = member<ri::Cpp>(seqs, "bool_values");
  EXPECT_EQ(FieldArray::Unbounded, ri::array_of<ri::Cpp>(bools));

  test_msgs::msg::UnboundedSequences msg;
  msg.bool_values = {true, false, true};
  msg.int32_values = {4, 5};
  size_t count = 0;
  ASSERT_TRUE(ri::element_count<ri::Cpp>(bools, &msg.bool_values, &count));
  EXPECT_EQ(3u, count);
  test_msgs::msg::Arrays arrays;
  ASSERT_TRUE(
    ri::element_count<ri::Cpp>(member<ri::Cpp>(cpp, "int32_values"), &arrays.int32_values, &count));
  EXPECT_EQ(3u, count);
  ri::Cpp::Member no_size = member<ri::Cpp>(seqs, "int32_values");
  no_size.size_function = nullptr;
  EXPECT_FALSE(ri::element_count<ri::Cpp>(no_size, &msg.int32_values, &count));

  // A block of primitives, except a C++ bool sequence (std::vector<bool> packs its bits).
  const auto & ints = member<ri::Cpp>(seqs, "int32_values");
  const void * ints_field = &msg.int32_values;
  const void * bools_field = &msg.bool_values;
  const void * strings_field = &msg.string_values;
  EXPECT_EQ(msg.int32_values.data(), ri::contiguous_primitives<ri::Cpp>(ints, ints_field));
  EXPECT_EQ(nullptr, ri::contiguous_primitives<ri::Cpp>(bools, bools_field));
  EXPECT_EQ(
    nullptr,
    ri::contiguous_primitives<ri::Cpp>(member<ri::Cpp>(seqs, "string_values"), strings_field));
}

TEST(IntrospectionArrays, the_element_loop_reads_and_writes_cpp_bool_sequences_through_copies)
{
  const auto * seqs = cpp_members<test_msgs::msg::UnboundedSequences>();
  const auto & bools = member<ri::Cpp>(seqs, "bool_values");
  test_msgs::msg::UnboundedSequences msg;
  msg.bool_values = {true, false, true};
  std::vector<bool> read;
  const void * field = &msg.bool_values;
  EXPECT_TRUE(ri::for_each_element<ri::Cpp>(bools, field, 3u, [&](const void * element, size_t) {
    read.push_back(*static_cast<const bool *>(element));
    return true;
  }));
  EXPECT_EQ((std::vector<bool>{true, false, true}), read);
  EXPECT_TRUE(
    ri::for_each_element<ri::Cpp>(
      bools, static_cast<void *>(&msg.bool_values), 3u, [](void * element, size_t k) {
        *static_cast<bool *>(element) = k == 1u;
        return true;
      }));
  EXPECT_EQ((std::vector<bool>{false, true, false}), msg.bool_values);

  // The loop stops at the first false.
  size_t visited = 0;
  EXPECT_FALSE(ri::for_each_element<ri::Cpp>(bools, field, 3u, [&](const void *, size_t k) {
    ++visited;
    return k == 0u;
  }));
  EXPECT_EQ(2u, visited);
  // No way to reach the elements: false, the visitor never called.
  ri::Cpp::Member unreachable = member<ri::Cpp>(seqs, "int32_values");
  unreachable.get_const_function = nullptr;
  msg.int32_values = {1};
  EXPECT_FALSE(
    ri::with_element<ri::Cpp>(
      unreachable, static_cast<const void *>(&msg.int32_values), 0u, [&](const void *, size_t) {
        ADD_FAILURE() << "visited an element it cannot reach";
        return true;
      }));
}

// ------------------------------------------------------------------------------ resize
// One behaviour for both type supports (see introspection.hpp).

TEST(IntrospectionResize, renews_every_element_in_c_and_cpp_alike)
{
  // C: the generated function finalises the sequence and initialises a new one.
  const auto * c =
    members_of<ri::C>(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, UnboundedSequences));
  test_msgs__msg__UnboundedSequences c_msg;
  ASSERT_TRUE(test_msgs__msg__UnboundedSequences__init(&c_msg));
  ASSERT_TRUE(test_msgs__msg__BasicTypes__Sequence__init(&c_msg.basic_types_values, 1));
  c_msg.basic_types_values.data[0].int32_value = 5;
  ASSERT_TRUE(
    ri::resize<ri::C>(member<ri::C>(c, "basic_types_values"), &c_msg.basic_types_values, 2));
  ASSERT_EQ(2u, c_msg.basic_types_values.size);
  EXPECT_EQ(0, c_msg.basic_types_values.data[0].int32_value);
  test_msgs__msg__UnboundedSequences__fini(&c_msg);

  // C++: the same, although std::vector::resize alone would keep the first element.
  const auto * cpp = cpp_members<test_msgs::msg::UnboundedSequences>();
  test_msgs::msg::UnboundedSequences cpp_msg;
  cpp_msg.basic_types_values.resize(1);
  cpp_msg.basic_types_values[0].int32_value = 5;
  ASSERT_TRUE(
    ri::resize<ri::Cpp>(
      member<ri::Cpp>(cpp, "basic_types_values"), &cpp_msg.basic_types_values, 2));
  ASSERT_EQ(2u, cpp_msg.basic_types_values.size());
  EXPECT_EQ(0, cpp_msg.basic_types_values[0].int32_value);
}

TEST(IntrospectionResize, refuses_a_bound_or_a_fixed_array_leaving_the_member_as_it_was)
{
  // C would take a fourth element of a sequence bounded to 3; C++ would throw.
  const auto * c = members_of<ri::C>(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, BoundedSequences));
  test_msgs__msg__BoundedSequences c_msg;
  ASSERT_TRUE(test_msgs__msg__BoundedSequences__init(&c_msg));
  ASSERT_TRUE(rosidl_runtime_c__int32__Sequence__init(&c_msg.int32_values, 2));
  EXPECT_FALSE(ri::resize<ri::C>(member<ri::C>(c, "int32_values"), &c_msg.int32_values, 4));
  EXPECT_EQ(2u, c_msg.int32_values.size);
  EXPECT_TRUE(ri::resize<ri::C>(member<ri::C>(c, "int32_values"), &c_msg.int32_values, 3));
  EXPECT_EQ(3u, c_msg.int32_values.size);
  test_msgs__msg__BoundedSequences__fini(&c_msg);

  const auto * cpp = cpp_members<test_msgs::msg::BoundedSequences>();
  test_msgs::msg::BoundedSequences cpp_msg;
  cpp_msg.int32_values.push_back(7);
  EXPECT_FALSE(ri::resize<ri::Cpp>(member<ri::Cpp>(cpp, "int32_values"), &cpp_msg.int32_values, 4));
  ASSERT_EQ(1u, cpp_msg.int32_values.size());
  EXPECT_EQ(7, cpp_msg.int32_values[0]);

  const auto * arrays = cpp_members<test_msgs::msg::Arrays>();
  test_msgs::msg::Arrays fixed;
  EXPECT_FALSE(
    ri::resize<ri::Cpp>(member<ri::Cpp>(arrays, "int32_values"), &fixed.int32_values, 3));
  const auto * c_arrays = members_of<ri::C>(ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, msg, Arrays));
  test_msgs__msg__Arrays c_fixed;
  ASSERT_TRUE(test_msgs__msg__Arrays__init(&c_fixed));
  EXPECT_FALSE(
    ri::resize<ri::C>(member<ri::C>(c_arrays, "int32_values"), &c_fixed.int32_values, 3));
  test_msgs__msg__Arrays__fini(&c_fixed);
}

TEST(IntrospectionResize, never_lets_an_exception_of_a_cpp_resize_out)
{
  const auto * cpp = cpp_members<test_msgs::msg::UnboundedSequences>();
  test_msgs::msg::UnboundedSequences msg;
  ri::Cpp::Member m = member<ri::Cpp>(cpp, "int32_values");
  m.resize_function = resize_throws_bad_alloc;
  EXPECT_FALSE(ri::resize<ri::Cpp>(m, &msg.int32_values, 3));
  m.resize_function = resize_throws_anything;
  EXPECT_FALSE(ri::resize<ri::Cpp>(m, &msg.int32_values, 3));
}

// The walkers turn a failed resize into their error, naming the field, instead of throwing.
TEST(IntrospectionResize, the_walkers_report_a_failed_resize_as_an_error)
{
  const auto * real = cpp_members<test_msgs::msg::UnboundedSequences>();
  std::vector<ri::Cpp::Member> members(real->members_, real->members_ + real->member_count_);
  for (auto & m : members) {
    if (std::string(m.name_) == "int32_values") {
      m.resize_function = resize_throws_bad_alloc;
    }
  }
  ri::Cpp::Members failing = *real;
  failing.members_ = members.data();
  const MessageLayout layout{&failing, true};

  test_msgs::msg::UnboundedSequences in;
  in.int32_values = {1, 2, 3};
  std::vector<uint8_t> bytes;
  std::string error;
  ASSERT_TRUE(rmw_introspect::cdr_serialize(layout, &in, &bytes, &error)) << error;
  test_msgs::msg::UnboundedSequences out;
  EXPECT_FALSE(rmw_introspect::cdr_deserialize(layout, bytes.data(), bytes.size(), &out, &error));
  EXPECT_EQ("cannot resize sequence field 'int32_values'", error);

  rmw_introspect::DynValue value = rmw_introspect::DynValue::structure();
  value.set(
    "int32_values", rmw_introspect::DynValue::sequence({rmw_introspect::DynValue::integer(1)}));
  EXPECT_FALSE(rmw_introspect::write_message(layout, value, &out, &error));
  EXPECT_EQ("int32_values: cannot resize the sequence", error);
}
