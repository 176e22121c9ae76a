// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Serialization: plain little-endian CDR through the introspection type supports (detail/cdr),
// the format rmw_fastrtps_cpp writes; rmw_get_serialized_message_size is not provided.

#include <cstring>
#include <string>
#include <vector>

#include "rmw/dynamic_message_type_support.h"
#include "rmw/rmw.h"
#include "rmw/serialized_message.h"

#include "detail/cdr.hpp"
#include "detail/common.hpp"
#include "detail/typesupport.hpp"

extern "C" {

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
  std::vector<uint8_t> data;
  if (!rmw_introspect::cdr_serialize(
        rmw_introspect::message_layout(type), ros_message, &data, &error))
  {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("cannot serialize: %s", error.c_str());
    return RMW_RET_ERROR;
  }
  if (serialized_message->buffer_capacity < data.size()) {
    const rmw_ret_t ret = rmw_serialized_message_resize(serialized_message, data.size());
    if (ret != RMW_RET_OK) {
      return ret;  // the message's allocator failed (error set)
    }
  }
  std::memcpy(serialized_message->buffer, data.data(), data.size());
  serialized_message->buffer_length = data.size();
  return RMW_RET_OK;
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
  if (!rmw_introspect::cdr_deserialize(
        rmw_introspect::message_layout(type), serialized_message->buffer,
        serialized_message->buffer_length, ros_message, &error))
  {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("cannot deserialize: %s", error.c_str());
    return RMW_RET_ERROR;
  }
  return RMW_RET_OK;
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
