// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Serialization: not provided (nothing is ever put on a wire); arguments are still checked.

#include <string>

#include "rmw/dynamic_message_type_support.h"
#include "rmw/rmw.h"

#include "detail/common.hpp"
#include "detail/typesupport.hpp"

extern "C"
{

rmw_ret_t rmw_get_serialized_message_size(
  const rosidl_message_type_support_t * type_support,
  const rosidl_runtime_c__Sequence__bound * message_bounds, size_t * size)
{
  // Unsupported whatever the arguments, like rmw_fastrtps_cpp: test_rmw_implementation asks
  // with NULL arguments to find out whether the function is implemented.
  (void)type_support;
  (void)message_bounds;
  (void)size;
  RMW_SET_ERROR_MSG("rmw_get_serialized_message_size is not supported");
  return RMW_RET_UNSUPPORTED;
}

rmw_ret_t rmw_serialize(
  const void * ros_message, const rosidl_message_type_support_t * type_support,
  rmw_serialized_message_t * serialized_message)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(type_support, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(serialized_message, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::ResolvedType type;
  std::string error;
  if (!rmw_introspect::resolve_message_type(type_support, &type, &error)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("%s", error.c_str());
    return RMW_RET_ERROR;
  }
  RMW_SET_ERROR_MSG("rmw_introspect_cpp records entities only: serialization is not supported");
  return RMW_RET_UNSUPPORTED;
}

rmw_ret_t rmw_deserialize(
  const rmw_serialized_message_t * serialized_message,
  const rosidl_message_type_support_t * type_support, void * ros_message)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(serialized_message, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(type_support, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(ros_message, RMW_RET_INVALID_ARGUMENT);
  rmw_introspect::ResolvedType type;
  std::string error;
  if (!rmw_introspect::resolve_message_type(type_support, &type, &error)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("%s", error.c_str());
    return RMW_RET_ERROR;
  }
  RMW_SET_ERROR_MSG("rmw_introspect_cpp records entities only: deserialization is not supported");
  return RMW_RET_UNSUPPORTED;
}

rmw_ret_t rmw_serialization_support_init(
  const char * serialization_lib_name, rcutils_allocator_t * allocator,
  rosidl_dynamic_typesupport_serialization_support_t * serialization_support)
{
  RMW_CHECK_ARGUMENT_FOR_NULL(serialization_lib_name, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(allocator, RMW_RET_INVALID_ARGUMENT);
  RMW_CHECK_ARGUMENT_FOR_NULL(serialization_support, RMW_RET_INVALID_ARGUMENT);
  RMW_SET_ERROR_MSG("dynamic type support is not supported by rmw_introspect_cpp");
  return RMW_RET_UNSUPPORTED;
}

}  // extern "C"
