// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__TYPESUPPORT_HPP_
#define DETAIL__TYPESUPPORT_HPP_

#include <string>

#include "rosidl_runtime_c/message_type_support_struct.h"
#include "rosidl_runtime_c/service_type_support_struct.h"
#include "rosidl_runtime_c/type_hash.h"

#include "detail/type_description.hpp"

namespace rmw_introspect
{

extern const char * const kIntrospectionC;    // "rosidl_typesupport_introspection_c"
extern const char * const kIntrospectionCpp;  // "rosidl_typesupport_introspection_cpp"

/// What the recorder keeps about the type of an endpoint.
struct ResolvedType
{
  std::string name;         // "pkg/msg/X", "pkg/srv/X", "pkg/action/X_SendGoal", ...
  std::string type_hash;    // "RIHS01_<64 hex>", empty when the type support has none
  std::string typesupport;  // identifier of the handle the caller passed
  bool is_cpp = false;      // resolved through the C++ introspection type support
  const void * members = nullptr;  // introspection MessageMembers / ServiceMembers
  /// The type and every type it refers to (type_description.hpp); shared by the endpoints
  /// and the capture's `types` table.
  TypeDescriptionsPtr descriptions;
};

/// A message type as the introspection type support describes it: its MessageMembers, C
/// (rosidl_typesupport_introspection_c) or C++ (rosidl_typesupport_introspection_cpp).
struct MessageLayout
{
  const void * members = nullptr;
  bool is_cpp = false;
};

/// The layout of a resolved message type.
MessageLayout message_layout(const ResolvedType & type);
/// The request and response layouts of a resolved service type.
void service_layouts(const ResolvedType & type, MessageLayout * request, MessageLayout * response);

/// "pkg__msg" / "pkg::msg" / "pkg__action" + "X" -> "pkg/msg/X" ...
std::string type_name_from_namespace(const char * type_namespace, const char * type_name);

/// "RIHS01_" + 64 lowercase hex digits; empty for a NULL hash or an unknown version.
std::string format_type_hash(const rosidl_type_hash_t * hash);

/// The type support `identifier` reached from `handle` through its own dispatch function
/// (`handle` itself when it is that type support); nullptr when there is none. Any rcutils
/// error a failed lookup leaves behind is cleared.
const rosidl_message_type_support_t * lookup_message_type_support(
  const rosidl_message_type_support_t * handle, const char * identifier);

/// Resolve a message type support handle (C or C++, dispatching or introspection) through
/// the handle's own `func(handle, identifier)`. Any rcutils error a failed lookup leaves
/// behind is cleared. Returns false (and fills `error`) when neither introspection type
/// support can be reached. Fills `descriptions` (describe_message_type).
bool resolve_message_type(
  const rosidl_message_type_support_t * type_support, ResolvedType * out, std::string * error);

/// The same for a service type support handle; the name is the service type.
bool resolve_service_type(
  const rosidl_service_type_support_t * type_support, ResolvedType * out, std::string * error);

}  // namespace rmw_introspect

#endif  // DETAIL__TYPESUPPORT_HPP_
