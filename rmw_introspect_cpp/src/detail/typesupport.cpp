// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/typesupport.hpp"

#include <cstring>
#include <string>

#include "rcutils/error_handling.h"
#include "rosidl_typesupport_introspection_c/message_introspection.h"
#include "rosidl_typesupport_introspection_c/service_introspection.h"
#include "rosidl_typesupport_introspection_cpp/message_introspection.hpp"
#include "rosidl_typesupport_introspection_cpp/service_introspection.hpp"

namespace rmw_introspect
{

const char * const kIntrospectionC = "rosidl_typesupport_introspection_c";
const char * const kIntrospectionCpp = "rosidl_typesupport_introspection_cpp";

std::string type_name_from_namespace(const char * type_namespace, const char * type_name)
{
  std::string result;
  if (type_namespace != nullptr) {
    const std::string ns(type_namespace);
    for (size_t i = 0; i < ns.size();) {
      if (ns.compare(i, 2, "__") == 0 || ns.compare(i, 2, "::") == 0) {
        result.push_back('/');
        i += 2;
      } else {
        result.push_back(ns[i]);
        ++i;
      }
    }
  }
  if (!result.empty() && result.back() != '/') {
    result.push_back('/');
  }
  if (type_name != nullptr) {
    result += type_name;
  }
  return result;
}

std::string format_type_hash(const rosidl_type_hash_t * hash)
{
  if (hash == nullptr || hash->version != 1) {
    return std::string();
  }
  static const char digits[] = "0123456789abcdef";
  std::string out = "RIHS01_";
  out.reserve(7 + 2 * ROSIDL_TYPE_HASH_SIZE);
  for (size_t i = 0; i < ROSIDL_TYPE_HASH_SIZE; ++i) {
    out.push_back(digits[hash->value[i] >> 4]);
    out.push_back(digits[hash->value[i] & 0x0f]);
  }
  return out;
}

namespace
{

// Ask a handle for another type support through its own dispatch function; a miss in a
// dispatching handle (rosidl_typesupport_c/_cpp) sets an rcutils error: clear it, keeping
// any error that was already set before the lookup.
template<typename HandleT>
const HandleT * lookup(const HandleT * handle, const char * identifier)
{
  if (handle->typesupport_identifier != nullptr &&
      std::strcmp(handle->typesupport_identifier, identifier) == 0)
  {
    return handle;
  }
  if (handle->func == nullptr) {
    return nullptr;
  }
  const bool error_before = rcutils_error_is_set();
  const HandleT * found = handle->func(handle, identifier);
  if (found == nullptr && !error_before) {
    rcutils_reset_error();
  }
  return found;
}

// The type name of each of the four introspection member structs.
std::string name_of(const rosidl_typesupport_introspection_c__MessageMembers * m)
{
  return type_name_from_namespace(m->message_namespace_, m->message_name_);
}
std::string name_of(const rosidl_typesupport_introspection_cpp::MessageMembers * m)
{
  return type_name_from_namespace(m->message_namespace_, m->message_name_);
}
std::string name_of(const rosidl_typesupport_introspection_c__ServiceMembers * m)
{
  return type_name_from_namespace(m->service_namespace_, m->service_name_);
}
std::string name_of(const rosidl_typesupport_introspection_cpp::ServiceMembers * m)
{
  return type_name_from_namespace(m->service_namespace_, m->service_name_);
}

// Messages and services resolve alike: the C introspection type support first (what rclpy and
// rcl hand over), then the C++ one; the hash from the handle given, else from the one found.
template<typename MembersC, typename MembersCpp, typename HandleT>
bool resolve(
  const HandleT * type_support, ResolvedType * out, std::string * error, const HandleT ** found)
{
  if (type_support == nullptr || out == nullptr) {
    if (error) {
      *error = "type support is null";
    }
    return false;
  }
  ResolvedType resolved;
  resolved.typesupport =
    type_support->typesupport_identifier ? type_support->typesupport_identifier : "";
  const void * members = nullptr;
  if ((*found = lookup(type_support, kIntrospectionC)) != nullptr) {
    const auto * m = static_cast<const MembersC *>((*found)->data);
    members = m;
    if (m != nullptr) {
      resolved.name = name_of(m);
    }
  } else if ((*found = lookup(type_support, kIntrospectionCpp)) != nullptr) {
    const auto * m = static_cast<const MembersCpp *>((*found)->data);
    members = m;
    resolved.is_cpp = true;
    if (m != nullptr) {
      resolved.name = name_of(m);
    }
  } else {
    if (error) {
      *error = "type support not from this implementation";
    }
    return false;
  }
  if (members == nullptr) {
    if (error) {
      *error = "introspection type support has no members";
    }
    return false;
  }
  resolved.members = members;
  if (type_support->get_type_hash_func != nullptr) {
    resolved.type_hash = format_type_hash(type_support->get_type_hash_func(type_support));
  } else if ((*found)->get_type_hash_func != nullptr) {
    resolved.type_hash = format_type_hash((*found)->get_type_hash_func(*found));
  }
  *out = std::move(resolved);
  return true;
}

}  // namespace

const rosidl_message_type_support_t * lookup_message_type_support(
  const rosidl_message_type_support_t * handle, const char * identifier)
{
  return handle != nullptr && identifier != nullptr ? lookup(handle, identifier) : nullptr;
}

bool resolve_message_type(
  const rosidl_message_type_support_t * type_support, ResolvedType * out, std::string * error)
{
  const rosidl_message_type_support_t * found = nullptr;
  if (!resolve<
        rosidl_typesupport_introspection_c__MessageMembers,
        rosidl_typesupport_introspection_cpp::MessageMembers>(type_support, out, error, &found))
  {
    return false;
  }
  out->descriptions = describe_message_type(found, out->is_cpp);
  return true;
}

bool resolve_service_type(
  const rosidl_service_type_support_t * type_support, ResolvedType * out, std::string * error)
{
  const rosidl_service_type_support_t * found = nullptr;
  if (!resolve<
        rosidl_typesupport_introspection_c__ServiceMembers,
        rosidl_typesupport_introspection_cpp::ServiceMembers>(type_support, out, error, &found))
  {
    return false;
  }
  out->descriptions = describe_service_type(found, out->is_cpp);
  return true;
}

MessageLayout message_layout(const ResolvedType & type)
{
  MessageLayout layout;
  layout.members = type.members;
  layout.is_cpp = type.is_cpp;
  return layout;
}

void service_layouts(const ResolvedType & type, MessageLayout * request, MessageLayout * response)
{
  request->is_cpp = response->is_cpp = type.is_cpp;
  if (type.members == nullptr) {
    request->members = response->members = nullptr;
  } else if (type.is_cpp) {
    const auto * m =
      static_cast<const rosidl_typesupport_introspection_cpp::ServiceMembers *>(type.members);
    request->members = m->request_members_;
    response->members = m->response_members_;
  } else {
    const auto * m =
      static_cast<const rosidl_typesupport_introspection_c__ServiceMembers *>(type.members);
    request->members = m->request_members_;
    response->members = m->response_members_;
  }
}

}  // namespace rmw_introspect
