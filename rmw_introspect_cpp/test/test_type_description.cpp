// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Type descriptions through the real C and C++ introspection type supports of test_msgs,
// std_msgs and action_msgs: fields (nested types, fixed arrays, bounded and unbounded
// sequences, bounded strings), constants from the definition sources, services and actions.

#include <gtest/gtest.h>

#include <string>
#include <vector>

// Only the type support declarations (extern "C" functions of the C and C++ dispatching
// type supports), not the message headers: this file compiles in seconds.
#include "action_msgs/srv/detail/cancel_goal__type_support.h"
#include "action_msgs/srv/detail/cancel_goal__type_support.hpp"
#include "rcutils/error_handling.h"
#include "rosidl_typesupport_interface/macros.h"
#include "std_msgs/msg/detail/string__type_support.h"
#include "test_msgs/action/detail/fibonacci__type_support.h"
#include "test_msgs/action/detail/fibonacci__type_support.hpp"
#include "test_msgs/msg/detail/arrays__type_support.h"
#include "test_msgs/msg/detail/arrays__type_support.hpp"
#include "test_msgs/msg/detail/bounded_sequences__type_support.h"
#include "test_msgs/msg/detail/bounded_sequences__type_support.hpp"
#include "test_msgs/msg/detail/constants__type_support.h"
#include "test_msgs/msg/detail/constants__type_support.hpp"
#include "test_msgs/msg/detail/multi_nested__type_support.h"
#include "test_msgs/msg/detail/multi_nested__type_support.hpp"
#include "test_msgs/msg/detail/nested__type_support.h"
#include "test_msgs/msg/detail/nested__type_support.hpp"
#include "test_msgs/msg/detail/strings__type_support.h"
#include "test_msgs/msg/detail/strings__type_support.hpp"
#include "test_msgs/msg/detail/unbounded_sequences__type_support.h"
#include "test_msgs/msg/detail/unbounded_sequences__type_support.hpp"
#include "test_msgs/msg/detail/w_strings__type_support.h"
#include "test_msgs/msg/detail/w_strings__type_support.hpp"
#include "test_msgs/srv/detail/basic_types__type_support.h"
#include "test_msgs/srv/detail/basic_types__type_support.hpp"

#include "detail/type_description.hpp"
#include "detail/typesupport.hpp"

using rmw_introspect::ConstantDescription;
using rmw_introspect::FieldArray;
using rmw_introspect::FieldDescription;
using rmw_introspect::ResolvedType;
using rmw_introspect::TypeDescription;
using rmw_introspect::TypeDescriptions;

namespace
{

// A field in .msg spelling: "string<=22[<=3] name".
std::string spec(const FieldDescription & f)
{
  std::string s = f.type;
  if (f.string_bound > 0) {
    s += "<=" + std::to_string(f.string_bound);
  }
  switch (f.array) {
    case FieldArray::Fixed: s += "[" + std::to_string(f.array_size) + "]"; break;
    case FieldArray::Bounded: s += "[<=" + std::to_string(f.array_size) + "]"; break;
    case FieldArray::Unbounded: s += "[]"; break;
    default: break;
  }
  return s + " " + f.name;
}

std::vector<std::string> specs(const TypeDescription & type)
{
  std::vector<std::string> out;
  for (const auto & f : type.fields) {
    out.push_back(spec(f));
  }
  return out;
}

std::vector<std::string> names(const TypeDescriptions & types)
{
  std::vector<std::string> out;
  for (const auto & t : types) {
    out.push_back(t.name);
  }
  return out;
}

const TypeDescription & find(const TypeDescriptions & types, const std::string & name)
{
  for (const auto & t : types) {
    if (t.name == name) {
      return t;
    }
  }
  ADD_FAILURE() << "no description of " << name;
  static const TypeDescription none;
  return none;
}

TypeDescriptions describe_message(const rosidl_message_type_support_t * handle, bool expect_cpp)
{
  ResolvedType type;
  std::string error;
  EXPECT_TRUE(rmw_introspect::resolve_message_type(handle, &type, &error)) << error;
  EXPECT_EQ(expect_cpp, type.is_cpp);
  EXPECT_TRUE(type.descriptions) << "no descriptions";
  return type.descriptions ? *type.descriptions : TypeDescriptions();
}

TypeDescriptions describe_service(const rosidl_service_type_support_t * handle, bool expect_cpp)
{
  ResolvedType type;
  std::string error;
  EXPECT_TRUE(rmw_introspect::resolve_service_type(handle, &type, &error)) << error;
  EXPECT_EQ(expect_cpp, type.is_cpp);
  EXPECT_TRUE(type.descriptions) << "no descriptions";
  return type.descriptions ? *type.descriptions : TypeDescriptions();
}

// The C++ dispatching type supports (what rclcpp hands over), by their extern "C" symbols.
#define CPP_MSG(pkg, sub, name) \
  ROSIDL_TYPESUPPORT_INTERFACE__MESSAGE_SYMBOL_NAME(rosidl_typesupport_cpp, pkg, sub, name)()
#define CPP_SRV(pkg, sub, name) \
  ROSIDL_TYPESUPPORT_INTERFACE__SERVICE_SYMBOL_NAME(rosidl_typesupport_cpp, pkg, sub, name)()
#define C_MSG(pkg, sub, name) \
  ROSIDL_TYPESUPPORT_INTERFACE__MESSAGE_SYMBOL_NAME(rosidl_typesupport_c, pkg, sub, name)()
#define C_SRV(pkg, sub, name) \
  ROSIDL_TYPESUPPORT_INTERFACE__SERVICE_SYMBOL_NAME(rosidl_typesupport_c, pkg, sub, name)()

TypeDescriptions describe_cpp(const rosidl_message_type_support_t * handle)
{
  return describe_message(handle, true);
}

TypeDescriptions describe_cpp_service(const rosidl_service_type_support_t * handle)
{
  return describe_service(handle, true);
}

void expect_same(const TypeDescriptions & c, const TypeDescriptions & cpp)
{
  ASSERT_EQ(names(c), names(cpp));
  for (size_t i = 0; i < c.size(); ++i) {
    SCOPED_TRACE(c[i].name);
    EXPECT_EQ(c[i].is_service, cpp[i].is_service);
    EXPECT_EQ(specs(c[i]), specs(cpp[i]));
    EXPECT_EQ(c[i].constants_known, cpp[i].constants_known);
    ASSERT_EQ(c[i].constants.size(), cpp[i].constants.size());
    for (size_t k = 0; k < c[i].constants.size(); ++k) {
      EXPECT_EQ(c[i].constants[k].name, cpp[i].constants[k].name);
      EXPECT_EQ(c[i].constants[k].type, cpp[i].constants[k].type);
      EXPECT_EQ(c[i].constants[k].value, cpp[i].constants[k].value);
    }
    EXPECT_EQ(c[i].request, cpp[i].request);
    EXPECT_EQ(c[i].response, cpp[i].response);
  }
}

const char * const kPrimitives[] = {"bool",   "byte",  "uint8", "float32", "float64",
                                    "int8",   "uint8", "int16", "uint16",  "int32",
                                    "uint32", "int64", "uint64"};
const char * const kPrimitiveFieldStems[] = {"bool",   "byte",  "char",  "float32", "float64",
                                             "int8",   "uint8", "int16", "uint16",  "int32",
                                             "uint32", "int64", "uint64"};

// The 32 fields Arrays, BoundedSequences, UnboundedSequences share, with `suffix` as the
// array part ("[3]", "[<=3]", "[]").
std::vector<std::string> array_fields(const std::string & suffix, bool with_strings = true)
{
  std::vector<std::string> out;
  for (size_t i = 0; i < 13; ++i) {
    out.push_back(std::string(kPrimitives[i]) + suffix + " " + kPrimitiveFieldStems[i] + "_values");
  }
  if (with_strings) {
    out.push_back("string" + suffix + " string_values");
  }
  out.push_back("test_msgs/msg/BasicTypes" + suffix + " basic_types_values");
  out.push_back("test_msgs/msg/Constants" + suffix + " constants_values");
  out.push_back("test_msgs/msg/Defaults" + suffix + " defaults_values");
  for (size_t i = 0; i < 13; ++i) {
    out.push_back(
      std::string(kPrimitives[i]) + suffix + " " + kPrimitiveFieldStems[i] + "_values_default");
  }
  if (with_strings) {
    out.push_back("string" + suffix + " string_values_default");
  }
  out.push_back("int32 alignment_check");
  return out;
}

}  // namespace

TEST(TypeDescription, fixed_arrays_and_nested_types_c)
{
  const TypeDescriptions types = describe_message(C_MSG(test_msgs, msg, Arrays), false);
  // its own type first, then the nested types in order of first reference, each once
  EXPECT_EQ(
    (std::vector<std::string>{
      "test_msgs/msg/Arrays", "test_msgs/msg/BasicTypes", "test_msgs/msg/Constants",
      "test_msgs/msg/Defaults"}),
    names(types));
  EXPECT_EQ(array_fields("[3]"), specs(types[0]));
  EXPECT_TRUE(types[0].constants_known);
  EXPECT_TRUE(types[0].constants.empty());
  EXPECT_FALSE(types[0].is_service);
  const TypeDescription & basic = find(types, "test_msgs/msg/BasicTypes");
  EXPECT_EQ("bool bool_value", specs(basic).front());
  EXPECT_EQ("uint8 char_value", specs(basic)[2]);  // a .msg char is an IDL uint8
  EXPECT_EQ("byte byte_value", specs(basic)[1]);
}

TEST(TypeDescription, fixed_arrays_and_nested_types_cpp)
{
  const TypeDescriptions types = describe_cpp(CPP_MSG(test_msgs, msg, Arrays));
  EXPECT_EQ(array_fields("[3]"), specs(types.at(0)));
  expect_same(describe_message(C_MSG(test_msgs, msg, Arrays), false), types);
}

TEST(TypeDescription, bounded_and_unbounded_sequences)
{
  const TypeDescriptions bounded_c =
    describe_message(C_MSG(test_msgs, msg, BoundedSequences), false);
  EXPECT_EQ(array_fields("[<=3]"), specs(bounded_c.at(0)));
  EXPECT_EQ(FieldArray::Bounded, bounded_c.at(0).fields.at(0).array);
  EXPECT_EQ(3u, bounded_c.at(0).fields.at(0).array_size);
  expect_same(bounded_c, describe_cpp(CPP_MSG(test_msgs, msg, BoundedSequences)));

  const TypeDescriptions unbounded_c =
    describe_message(C_MSG(test_msgs, msg, UnboundedSequences), false);
  EXPECT_EQ(array_fields("[]"), specs(unbounded_c.at(0)));
  EXPECT_EQ(FieldArray::Unbounded, unbounded_c.at(0).fields.at(0).array);
  EXPECT_EQ(0u, unbounded_c.at(0).fields.at(0).array_size);
  expect_same(unbounded_c, describe_cpp(CPP_MSG(test_msgs, msg, UnboundedSequences)));
}

TEST(TypeDescription, bounded_strings_and_string_constants)
{
  const TypeDescriptions c = describe_message(C_MSG(test_msgs, msg, Strings), false);
  ASSERT_EQ(1u, c.size());
  EXPECT_EQ(
    (std::vector<std::string>{
      "string string_value", "string string_value_default1", "string string_value_default2",
      "string string_value_default3", "string string_value_default4",
      "string string_value_default5", "string<=22 bounded_string_value",
      "string<=22 bounded_string_value_default1", "string<=22 bounded_string_value_default2",
      "string<=22 bounded_string_value_default3", "string<=22 bounded_string_value_default4",
      "string<=22 bounded_string_value_default5"}),
    specs(c[0]));
  ASSERT_TRUE(c[0].constants_known);
  ASSERT_EQ(1u, c[0].constants.size());
  EXPECT_EQ("STRING_CONST", c[0].constants[0].name);
  EXPECT_EQ("string", c[0].constants[0].type);
  EXPECT_EQ("\"Hello world!\"", c[0].constants[0].value);
  expect_same(c, describe_cpp(CPP_MSG(test_msgs, msg, Strings)));

  const TypeDescriptions w = describe_message(C_MSG(test_msgs, msg, WStrings), false);
  EXPECT_EQ(
    (std::vector<std::string>{
      "wstring wstring_value", "wstring wstring_value_default1", "wstring wstring_value_default2",
      "wstring wstring_value_default3", "wstring[3] array_of_wstrings",
      "wstring[<=3] bounded_sequence_of_wstrings", "wstring[] unbounded_sequence_of_wstrings"}),
    specs(w.at(0)));
  expect_same(w, describe_cpp(CPP_MSG(test_msgs, msg, WStrings)));
}

TEST(TypeDescription, constants_of_every_primitive_type)
{
  const TypeDescriptions c = describe_message(C_MSG(test_msgs, msg, Constants), false);
  ASSERT_EQ(1u, c.size());
  // no fields of its own: rosidl adds a placeholder member (it is in the type hash too)
  EXPECT_EQ((std::vector<std::string>{"uint8 structure_needs_at_least_one_member"}), specs(c[0]));
  ASSERT_TRUE(c[0].constants_known);
  std::vector<std::string> constants;
  for (const ConstantDescription & k : c[0].constants) {
    constants.push_back(k.type + " " + k.name + "=" + k.value);
  }
  EXPECT_EQ(
    (std::vector<std::string>{
      "bool BOOL_CONST=true", "byte BYTE_CONST=50", "uint8 CHAR_CONST=100",
      "float32 FLOAT32_CONST=1.125", "float64 FLOAT64_CONST=1.125", "int8 INT8_CONST=-50",
      "uint8 UINT8_CONST=200", "int16 INT16_CONST=-1000", "uint16 UINT16_CONST=2000",
      "int32 INT32_CONST=-30000", "uint32 UINT32_CONST=60000", "int64 INT64_CONST=-40000000",
      "uint64 UINT64_CONST=50000000"}),
    constants);
  expect_same(c, describe_cpp(CPP_MSG(test_msgs, msg, Constants)));
}

TEST(TypeDescription, nested_and_multi_nested)
{
  const TypeDescriptions nested = describe_cpp(CPP_MSG(test_msgs, msg, Nested));
  EXPECT_EQ(
    (std::vector<std::string>{"test_msgs/msg/Nested", "test_msgs/msg/BasicTypes"}), names(nested));
  EXPECT_EQ(
    (std::vector<std::string>{"test_msgs/msg/BasicTypes basic_types_value"}), specs(nested[0]));
  expect_same(describe_message(C_MSG(test_msgs, msg, Nested), false), nested);

  const TypeDescriptions multi = describe_cpp(CPP_MSG(test_msgs, msg, MultiNested));
  EXPECT_EQ(
    (std::vector<std::string>{
      "test_msgs/msg/Arrays[3] array_of_arrays",
      "test_msgs/msg/BoundedSequences[3] array_of_bounded_sequences",
      "test_msgs/msg/UnboundedSequences[3] array_of_unbounded_sequences",
      "test_msgs/msg/Arrays[<=3] bounded_sequence_of_arrays",
      "test_msgs/msg/BoundedSequences[<=3] bounded_sequence_of_bounded_sequences",
      "test_msgs/msg/UnboundedSequences[<=3] bounded_sequence_of_unbounded_sequences",
      "test_msgs/msg/Arrays[] unbounded_sequence_of_arrays",
      "test_msgs/msg/BoundedSequences[] unbounded_sequence_of_bounded_sequences",
      "test_msgs/msg/UnboundedSequences[] unbounded_sequence_of_unbounded_sequences"}),
    specs(multi.at(0)));
  // every type reached, two levels deep, described once
  EXPECT_EQ(
    (std::vector<std::string>{
      "test_msgs/msg/MultiNested", "test_msgs/msg/Arrays", "test_msgs/msg/BasicTypes",
      "test_msgs/msg/Constants", "test_msgs/msg/Defaults", "test_msgs/msg/BoundedSequences",
      "test_msgs/msg/UnboundedSequences"}),
    names(multi));
  EXPECT_EQ(array_fields("[<=3]"), specs(find(multi, "test_msgs/msg/BoundedSequences")));
  EXPECT_EQ(13u, find(multi, "test_msgs/msg/Constants").constants.size());
  expect_same(describe_message(C_MSG(test_msgs, msg, MultiNested), false), multi);
}

TEST(TypeDescription, services_describe_request_and_response)
{
  const TypeDescriptions c = describe_service(C_SRV(test_msgs, srv, BasicTypes), false);
  EXPECT_EQ(
    (std::vector<std::string>{
      "test_msgs/srv/BasicTypes", "test_msgs/srv/BasicTypes_Request",
      "test_msgs/srv/BasicTypes_Response"}),
    names(c));
  EXPECT_TRUE(c[0].is_service);
  EXPECT_TRUE(c[0].fields.empty());
  EXPECT_EQ("test_msgs/srv/BasicTypes_Request", c[0].request);
  EXPECT_EQ("test_msgs/srv/BasicTypes_Response", c[0].response);
  EXPECT_EQ(14u, c[1].fields.size());
  EXPECT_EQ("string string_value", spec(c[1].fields.back()));
  EXPECT_TRUE(c[1].constants_known);  // from the .srv text: none
  EXPECT_TRUE(c[1].constants.empty());
  expect_same(c, describe_cpp_service(CPP_SRV(test_msgs, srv, BasicTypes)));
}

TEST(TypeDescription, service_constants_come_from_their_part_of_the_srv_text)
{
  const TypeDescriptions c = describe_service(C_SRV(action_msgs, srv, CancelGoal), false);
  const TypeDescription & request = find(c, "action_msgs/srv/CancelGoal_Request");
  const TypeDescription & response = find(c, "action_msgs/srv/CancelGoal_Response");
  EXPECT_EQ((std::vector<std::string>{"action_msgs/msg/GoalInfo goal_info"}), specs(request));
  ASSERT_TRUE(request.constants_known);
  EXPECT_TRUE(request.constants.empty());
  ASSERT_TRUE(response.constants_known);
  std::vector<std::string> constants;
  for (const auto & k : response.constants) {
    constants.push_back(k.type + " " + k.name + "=" + k.value);
  }
  EXPECT_EQ(
    (std::vector<std::string>{
      "int8 ERROR_NONE=0", "int8 ERROR_REJECTED=1", "int8 ERROR_UNKNOWN_GOAL_ID=2",
      "int8 ERROR_GOAL_TERMINATED=3"}),
    constants);
  EXPECT_EQ(
    (std::vector<std::string>{"int8 return_code", "action_msgs/msg/GoalInfo[] goals_canceling"}),
    specs(response));
  // nested types of both parts: GoalInfo, then what it nests
  const TypeDescription & goal_info = find(c, "action_msgs/msg/GoalInfo");
  EXPECT_EQ(
    (std::vector<std::string>{
      "unique_identifier_msgs/msg/UUID goal_id", "builtin_interfaces/msg/Time stamp"}),
    specs(goal_info));
  EXPECT_EQ(
    (std::vector<std::string>{"uint8[16] uuid"}),
    specs(find(c, "unique_identifier_msgs/msg/UUID")));
  expect_same(c, describe_cpp_service(CPP_SRV(action_msgs, srv, CancelGoal)));
}

TEST(TypeDescription, action_parts_reach_the_action_text)
{
  // The goal of an action is an "implicit" type of the SendGoal type support: its constants
  // come from the .action text, found in test_msgs' generator library.
  const TypeDescriptions c = describe_service(C_SRV(test_msgs, action, Fibonacci_SendGoal), false);
  EXPECT_EQ(
    (std::vector<std::string>{
      "test_msgs/action/Fibonacci_SendGoal", "test_msgs/action/Fibonacci_SendGoal_Request",
      "unique_identifier_msgs/msg/UUID", "test_msgs/action/Fibonacci_Goal",
      "test_msgs/action/Fibonacci_SendGoal_Response", "builtin_interfaces/msg/Time"}),
    names(c));
  EXPECT_EQ(
    (std::vector<std::string>{
      "unique_identifier_msgs/msg/UUID goal_id", "test_msgs/action/Fibonacci_Goal goal"}),
    specs(find(c, "test_msgs/action/Fibonacci_SendGoal_Request")));
  const TypeDescription & goal = find(c, "test_msgs/action/Fibonacci_Goal");
  EXPECT_EQ((std::vector<std::string>{"int32 order"}), specs(goal));
  EXPECT_TRUE(goal.constants_known);
  EXPECT_TRUE(find(c, "test_msgs/action/Fibonacci_SendGoal_Request").constants_known);
  expect_same(c, describe_cpp_service(CPP_SRV(test_msgs, action, Fibonacci_SendGoal)));

  const TypeDescriptions feedback =
    describe_message(C_MSG(test_msgs, action, Fibonacci_FeedbackMessage), false);
  EXPECT_EQ(
    (std::vector<std::string>{"int32[] sequence"}),
    specs(find(feedback, "test_msgs/action/Fibonacci_Feedback")));
  EXPECT_TRUE(find(feedback, "test_msgs/action/Fibonacci_Feedback").constants_known);
  expect_same(feedback, describe_cpp(CPP_MSG(test_msgs, action, Fibonacci_FeedbackMessage)));
  EXPECT_FALSE(rcutils_error_is_set()) << rcutils_get_error_string().str;
}

TEST(TypeDescription, null_handles)
{
  EXPECT_EQ(nullptr, rmw_introspect::describe_message_type(nullptr, false));
  EXPECT_EQ(nullptr, rmw_introspect::describe_service_type(nullptr, true));
  rosidl_message_type_support_t empty = *C_MSG(std_msgs, msg, String);
  empty.data = nullptr;
  EXPECT_EQ(nullptr, rmw_introspect::describe_message_type(&empty, false));
}

TEST(ParseConstants, msg_lines)
{
  const std::string text =
    "# a file comment\n"
    "int32 FOO=1   # trailing comment\n"
    "int32 foo_field\n"
    "\tstring\tGREETING = \"hi there\"\n"
    "char LETTER=65\n"
    "float64 x 1.5\n"
    "bool BROKEN NAME=1\n"
    "\n";
  const auto constants = rmw_introspect::parse_msg_constants(text);
  ASSERT_EQ(3u, constants.size());
  EXPECT_EQ("FOO", constants[0].name);
  EXPECT_EQ("int32", constants[0].type);
  EXPECT_EQ("1", constants[0].value);
  EXPECT_EQ("GREETING", constants[1].name);
  EXPECT_EQ("string", constants[1].type);
  EXPECT_EQ("\"hi there\"", constants[1].value);
  EXPECT_EQ("uint8", constants[2].type);
  EXPECT_TRUE(rmw_introspect::parse_msg_constants("").empty());
}

TEST(ParseConstants, definition_parts)
{
  const std::string srv = "int8 A=1\nint8 a\n---\nint8 B=2\n---  \nint8 C=3";
  EXPECT_EQ("int8 A=1\nint8 a\n", rmw_introspect::definition_part(srv, 0));
  EXPECT_EQ("int8 B=2\n", rmw_introspect::definition_part(srv, 1));
  EXPECT_EQ("int8 C=3\n", rmw_introspect::definition_part(srv, 2));
  EXPECT_EQ("", rmw_introspect::definition_part(srv, 3));
  EXPECT_EQ("", rmw_introspect::definition_part("", 0));
}
