// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Type support resolution with the real C and C++ (dispatching and introspection) type
// supports of std_msgs and test_msgs.

#include <gtest/gtest.h>

#include <string>

#include "rcutils/error_handling.h"
#include "rosidl_typesupport_cpp/message_type_support.hpp"
#include "rosidl_typesupport_cpp/service_type_support.hpp"
#include "rosidl_typesupport_introspection_cpp/message_type_support_decl.hpp"
#include "std_msgs/msg/detail/string__rosidl_typesupport_introspection_c.h"
#include "std_msgs/msg/string.h"
#include "std_msgs/msg/string.hpp"
#include "test_msgs/action/fibonacci.h"
#include "test_msgs/action/fibonacci.hpp"
#include "test_msgs/srv/basic_types.h"
#include "test_msgs/srv/basic_types.hpp"

#include "detail/typesupport.hpp"

using rmw_introspect::ResolvedType;

namespace
{
const char kStringHash[] =
  "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18";
const char kBasicTypesHash[] =
  "RIHS01_da348697437c103cc9a9322ac1bdbdcf8eb11a85de22f7f2492ca1df416e1a5f";
const char kFeedbackMessageHash[] =
  "RIHS01_37487bae8cea358366b97003c1ef1ca7ce7c08df36f9e8cca496624226aee64e";
}  // namespace

TEST(TypeName, from_namespaces)
{
  using rmw_introspect::type_name_from_namespace;
  EXPECT_EQ("std_msgs/msg/String", type_name_from_namespace("std_msgs__msg", "String"));
  EXPECT_EQ("std_msgs/msg/String", type_name_from_namespace("std_msgs::msg", "String"));
  EXPECT_EQ(
    "test_msgs/action/Fibonacci_FeedbackMessage",
    type_name_from_namespace("test_msgs__action", "Fibonacci_FeedbackMessage"));
  EXPECT_EQ("pkg/srv/X", type_name_from_namespace("pkg__srv", "X"));
  EXPECT_EQ("X", type_name_from_namespace("", "X"));
}

TEST(TypeHash, formatting)
{
  rosidl_type_hash_t hash = rosidl_get_zero_initialized_type_hash();
  hash.version = 1;
  for (size_t i = 0; i < ROSIDL_TYPE_HASH_SIZE; ++i) {
    hash.value[i] = static_cast<uint8_t>(i * 8 + 1);
  }
  const std::string s = rmw_introspect::format_type_hash(&hash);
  EXPECT_EQ(71u, s.size());
  EXPECT_EQ("RIHS01_0109111921", s.substr(0, 17));
  EXPECT_EQ("", rmw_introspect::format_type_hash(nullptr));
  hash.version = 0;  // unset
  EXPECT_EQ("", rmw_introspect::format_type_hash(&hash));
}

TEST(ResolveMessage, c_dispatching_handle)
{
  rcutils_reset_error();
  ResolvedType type;
  std::string error;
  ASSERT_TRUE(
    rmw_introspect::resolve_message_type(
      ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, String), &type, &error))
    << error;
  EXPECT_EQ("std_msgs/msg/String", type.name);
  EXPECT_EQ(kStringHash, type.type_hash);
  EXPECT_EQ("rosidl_typesupport_c", type.typesupport);
  EXPECT_FALSE(type.is_cpp);
  EXPECT_FALSE(rcutils_error_is_set());
}

TEST(ResolveMessage, cpp_dispatching_handle)
{
  rcutils_reset_error();
  ResolvedType type;
  std::string error;
  // The C++ dispatcher does not know the C introspection identifier: the miss sets an
  // rcutils error that the resolver must clear.
  ASSERT_TRUE(
    rmw_introspect::resolve_message_type(
      rosidl_typesupport_cpp::get_message_type_support_handle<std_msgs::msg::String>(), &type,
      &error))
    << error;
  EXPECT_EQ("std_msgs/msg/String", type.name);
  EXPECT_EQ(kStringHash, type.type_hash);
  EXPECT_EQ("rosidl_typesupport_cpp", type.typesupport);
  EXPECT_TRUE(type.is_cpp);
  EXPECT_FALSE(rcutils_error_is_set()) << rcutils_get_error_string().str;
}

TEST(ResolveMessage, introspection_handles_directly)
{
  ResolvedType type;
  std::string error;
  const rosidl_message_type_support_t * c_ts = ROSIDL_TYPESUPPORT_INTERFACE__MESSAGE_SYMBOL_NAME(
    rosidl_typesupport_introspection_c, std_msgs, msg, String)();
  ASSERT_TRUE(rmw_introspect::resolve_message_type(c_ts, &type, &error)) << error;
  EXPECT_EQ("std_msgs/msg/String", type.name);
  EXPECT_EQ("rosidl_typesupport_introspection_c", type.typesupport);
  EXPECT_EQ(kStringHash, type.type_hash);
  const rosidl_message_type_support_t * cpp_ts =
    rosidl_typesupport_introspection_cpp::get_message_type_support_handle<std_msgs::msg::String>();
  ASSERT_TRUE(rmw_introspect::resolve_message_type(cpp_ts, &type, &error)) << error;
  EXPECT_EQ("std_msgs/msg/String", type.name);
  EXPECT_EQ("rosidl_typesupport_introspection_cpp", type.typesupport);
  EXPECT_TRUE(type.is_cpp);
  EXPECT_EQ(kStringHash, type.type_hash);
}

TEST(ResolveMessage, action_messages_keep_their_namespace)
{
  ResolvedType type;
  std::string error;
  ASSERT_TRUE(
    rmw_introspect::resolve_message_type(
      ROSIDL_GET_MSG_TYPE_SUPPORT(test_msgs, action, Fibonacci_FeedbackMessage), &type, &error));
  EXPECT_EQ("test_msgs/action/Fibonacci_FeedbackMessage", type.name);
  EXPECT_EQ(kFeedbackMessageHash, type.type_hash);
  ASSERT_TRUE(
    rmw_introspect::resolve_message_type(
      rosidl_typesupport_cpp::get_message_type_support_handle<
        test_msgs::action::Fibonacci_FeedbackMessage>(),
      &type, &error));
  EXPECT_EQ("test_msgs/action/Fibonacci_FeedbackMessage", type.name);
  EXPECT_EQ(kFeedbackMessageHash, type.type_hash);
}

TEST(ResolveService, c_and_cpp)
{
  rcutils_reset_error();
  ResolvedType type;
  std::string error;
  ASSERT_TRUE(
    rmw_introspect::resolve_service_type(
      ROSIDL_GET_SRV_TYPE_SUPPORT(test_msgs, srv, BasicTypes), &type, &error))
    << error;
  EXPECT_EQ("test_msgs/srv/BasicTypes", type.name);
  EXPECT_EQ(kBasicTypesHash, type.type_hash);
  EXPECT_EQ("rosidl_typesupport_c", type.typesupport);
  ASSERT_TRUE(
    rmw_introspect::resolve_service_type(
      rosidl_typesupport_cpp::get_service_type_support_handle<test_msgs::srv::BasicTypes>(), &type,
      &error))
    << error;
  EXPECT_EQ("test_msgs/srv/BasicTypes", type.name);
  EXPECT_EQ(kBasicTypesHash, type.type_hash);
  EXPECT_EQ("rosidl_typesupport_cpp", type.typesupport);
  ASSERT_TRUE(
    rmw_introspect::resolve_service_type(
      ROSIDL_GET_SRV_TYPE_SUPPORT(test_msgs, action, Fibonacci_SendGoal), &type, &error));
  EXPECT_EQ("test_msgs/action/Fibonacci_SendGoal", type.name);
  EXPECT_FALSE(rcutils_error_is_set()) << rcutils_get_error_string().str;
}

TEST(ResolveMessage, unknown_type_support_fails_cleanly)
{
  rcutils_reset_error();
  rosidl_message_type_support_t bogus = *ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, String);
  bogus.typesupport_identifier = "bogus";
  bogus.func = nullptr;
  ResolvedType type;
  std::string error;
  EXPECT_FALSE(rmw_introspect::resolve_message_type(&bogus, &type, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(rmw_introspect::resolve_message_type(nullptr, &type, &error));
  // A dispatching handle asked through its own func for nothing it knows: still fails
  // cleanly, and leaves no error behind.
  rosidl_message_type_support_t wrong = *ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, String);
  wrong.typesupport_identifier = "bogus";
  const rosidl_message_type_support_t * fast = wrong.func(&wrong, "no_such_typesupport");
  EXPECT_EQ(nullptr, fast);
  rcutils_reset_error();
}
