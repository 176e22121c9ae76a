// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__TYPESUPPORT_HPP_
#define DETAIL__TYPESUPPORT_HPP_

#include <string>

#include "rosidl_runtime_c/message_type_support_struct.h"
#include "rosidl_runtime_c/service_type_support_struct.h"
#include "rosidl_runtime_c/type_hash.h"

#include "detail/message_layout.hpp"
#include "detail/type_description.hpp"

namespace rmw_introspect
{

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

/// The layout of a resolved message type.
MessageLayout message_layout(const ResolvedType & type);
/// The request and response layouts of a resolved service type.
void service_layouts(const ResolvedType & type, MessageLayout * request, MessageLayout * response);

/// "RIHS01_" + 64 lowercase hex digits; empty for a NULL hash or an unknown version.
std::string format_type_hash(const rosidl_type_hash_t * hash);

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
