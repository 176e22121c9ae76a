// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__TYPE_DESCRIPTION_HPP_
#define DETAIL__TYPE_DESCRIPTION_HPP_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rosidl_runtime_c/message_type_support_struct.h"
#include "rosidl_runtime_c/service_type_support_struct.h"

#include "detail/message_layout.hpp"

namespace rmw_introspect
{

const char * field_array_to_string(FieldArray array);  // "fixed", "bounded", "unbounded"

/// One field of a message type, as its introspection type support lists it.
struct FieldDescription
{
  std::string name;
  /// `.msg` spelling of the element type: bool, byte, char, wchar, float32, float64,
  /// long_double, int8 ... uint64, string, wstring, or the nested type's "pkg/msg/X".
  /// A `.msg` `char` is an IDL uint8 and shows as uint8 (as in the type hash).
  std::string type;
  FieldArray array = FieldArray::None;
  uint64_t array_size = 0;    // Fixed: the size; Bounded: the bound
  uint64_t string_bound = 0;  // string / wstring elements: the bound; 0 = unbounded
};

/// One constant of a message type, from the type's definition source (`TYPE NAME=VALUE`).
struct ConstantDescription
{
  std::string name;
  std::string type;   // as written, except `char` -> uint8 (like fields)
  std::string value;  // the text after `=`, as written
};

/// A message type (fields, constants) or a service type (its request and response types).
struct TypeDescription
{
  std::string name;          // "pkg/msg/X", "pkg/srv/X", "pkg/action/X_Goal", ...
  bool is_service = false;
  std::vector<FieldDescription> fields;  // messages: in declaration (= wire) order
  /// A definition source of the type was found (`.msg`, or the part of a `.srv`/`.action`),
  /// so `constants` is complete; false: constants unknown (e.g. a type defined in `.idl`).
  bool constants_known = false;
  std::vector<ConstantDescription> constants;
  std::string request;       // services: the request message type
  std::string response;      // services: the response message type
};

/// An endpoint type's description: its own type first, then every type it refers to
/// (nested field types, request and response), each once, in order of first reference.
using TypeDescriptions = std::vector<TypeDescription>;
using TypeDescriptionsPtr = std::shared_ptr<const TypeDescriptions>;

/// Walk an introspection message type support (`data` = C or C++ MessageMembers).
/// Never fails: what cannot be read is left out (a nested type without members is named
/// "?"). Returns nullptr for a NULL handle.
TypeDescriptionsPtr describe_message_type(
  const rosidl_message_type_support_t * introspection, bool is_cpp);

/// The same for an introspection service type support (`data` = C or C++ ServiceMembers):
/// the service type, then its request and response messages and their nested types.
TypeDescriptionsPtr describe_service_type(
  const rosidl_service_type_support_t * introspection, bool is_cpp);

/// The constants of a `.msg` text: `TYPE NAME=VALUE` lines, comments cut at `#` and tabs
/// read as spaces like rosidl_adapter does.
std::vector<ConstantDescription> parse_msg_constants(const std::string & text);

/// Part `index` of a `.srv` (request, response) or `.action` (goal, result, feedback) text,
/// parts separated by `---` lines; empty when the text has fewer parts.
std::string definition_part(const std::string & text, size_t index);

}  // namespace rmw_introspect

#endif  // DETAIL__TYPE_DESCRIPTION_HPP_
