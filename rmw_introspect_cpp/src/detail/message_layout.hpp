// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__MESSAGE_LAYOUT_HPP_
#define DETAIL__MESSAGE_LAYOUT_HPP_

// What the introspection traits (introspection.hpp), the type descriptions
// (type_description.hpp) and the type supports (typesupport.hpp) share, below all three: the two
// introspection type supports, a message's layout, a field's array kind and the type support
// lookups (defined in typesupport.cpp and type_description.cpp).

#include <string>

#include "rosidl_runtime_c/message_type_support_struct.h"

namespace rmw_introspect
{

extern const char * const kIntrospectionC;    // "rosidl_typesupport_introspection_c"
extern const char * const kIntrospectionCpp;  // "rosidl_typesupport_introspection_cpp"

/// A message type as the introspection type support describes it: its MessageMembers, C
/// (rosidl_typesupport_introspection_c) or C++ (rosidl_typesupport_introspection_cpp).
struct MessageLayout
{
  const void * members = nullptr;
  bool is_cpp = false;
};

/// How a field repeats: not at all, `T[N]`, `T[<=N]` or `T[]`.
enum class FieldArray { None, Fixed, Bounded, Unbounded };

/// "pkg__msg" / "pkg::msg" / "pkg__action" + "X" -> "pkg/msg/X" ...
std::string type_name_from_namespace(const char * type_namespace, const char * type_name);

/// The type support `identifier` reached from `handle` through its own dispatch function
/// (`handle` itself when it is that type support); nullptr when there is none. Any rcutils
/// error a failed lookup leaves behind is cleared.
const rosidl_message_type_support_t * lookup_message_type_support(
  const rosidl_message_type_support_t * handle, const char * identifier);

}  // namespace rmw_introspect

#endif  // DETAIL__MESSAGE_LAYOUT_HPP_
