// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__MESSAGE_WALKER_HPP_
#define DETAIL__MESSAGE_WALKER_HPP_

#include <string>

#include "detail/dynamic_value.hpp"
#include "detail/typesupport.hpp"

namespace rmw_introspect
{

// MessageLayout (typesupport.hpp): a message type's C or C++ introspection members.

/// service_layouts (typesupport.hpp), checked: false (and `error`) when the service type has
/// no members or they lack the request or the response.
bool service_message_layouts(
  const ResolvedType & service, MessageLayout * request, MessageLayout * response,
  std::string * error);

/// "pkg/srv/X_Request" ...; empty for an empty layout.
std::string layout_type_name(const MessageLayout & layout);

/// Read a whole message into a Struct value (fields in member order; arrays, bounded and
/// unbounded sequences as Sequence; signed integers Int; unsigned, octet, char and wchar UInt;
/// float, double and long double Double; string and wstring String in UTF-8).
bool read_message(
  const MessageLayout & layout, const void * message, DynValue * out, std::string * error);

/// Write `value` (a Struct; Null writes nothing) into `message`, which the caller has
/// initialized (its init function, or rclpy/rclcpp's own allocation). Only the fields
/// `value` names are assigned; sequences are resized to the value's length. False (and
/// `error` naming the field) for an unknown field, a value of the wrong kind, an integer out
/// of its field's range, or a string or sequence longer than its bound; the message may then
/// be partly written (still valid memory for its fini function).
bool write_message(
  const MessageLayout & layout, const DynValue & value, void * message, std::string * error);

}  // namespace rmw_introspect

#endif  // DETAIL__MESSAGE_WALKER_HPP_
