// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The C and the C++ introspection type supports seen through one set of traits, for the four
// walkers of messages and message types: CDR (cdr.cpp), content filters (content_filter.cpp),
// messages as values (message_walker.cpp) and type descriptions (type_description.cpp).
//
// A walker is a template over the traits (`C` or `Cpp`) and uses:
// - `dispatch`: the one switch over a member's type id (primitive, string, wstring, nested
//   message, unknown), calling the walker's visitor;
// - `array_of`, `element_count`, `resize`: the shape and length of an array member;
// - `for_each_element` / `with_element`: the one loop over an array member's elements (the
//   elements of a C++ bool sequence have no address and are handed over as a copy);
// - `contiguous_primitives`: the first element of a block of primitives, for bulk copies.
//
// No function here throws: the walkers run inside rmw_* entry points, called from C.
#ifndef DETAIL__INTROSPECTION_HPP_
#define DETAIL__INTROSPECTION_HPP_

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>

#include "rosidl_runtime_c/string.h"
#include "rosidl_runtime_c/string_functions.h"
#include "rosidl_runtime_c/u16string.h"
#include "rosidl_runtime_c/u16string_functions.h"
#include "rosidl_typesupport_introspection_c/field_types.h"
#include "rosidl_typesupport_introspection_c/message_introspection.h"
#include "rosidl_typesupport_introspection_c/service_introspection.h"
#include "rosidl_typesupport_introspection_cpp/field_types.hpp"
#include "rosidl_typesupport_introspection_cpp/message_introspection.hpp"
#include "rosidl_typesupport_introspection_cpp/service_introspection.hpp"

#include "detail/message_layout.hpp"

namespace rmw_introspect
{
namespace introspection
{

static_assert(sizeof(bool) == 1, "CDR booleans are one byte; so must C and C++ bool be");
static_assert(
  rosidl_typesupport_introspection_c__ROS_TYPE_MESSAGE ==
      rosidl_typesupport_introspection_cpp::ROS_TYPE_MESSAGE &&
    rosidl_typesupport_introspection_c__ROS_TYPE_WSTRING ==
      rosidl_typesupport_introspection_cpp::ROS_TYPE_WSTRING &&
    rosidl_typesupport_introspection_c__ROS_TYPE_FLOAT ==
      rosidl_typesupport_introspection_cpp::ROS_TYPE_FLOAT &&
    rosidl_typesupport_introspection_c__ROS_TYPE_INT64 ==
      rosidl_typesupport_introspection_cpp::ROS_TYPE_INT64,
  "the C and C++ introspection field type ids differ: the walkers use the C ones for both");

/// Bytes of one value of a primitive type id (bool: 1); 0 for strings, messages and unknown ids.
inline size_t primitive_size(uint8_t type_id)
{
  switch (type_id) {
    case rosidl_typesupport_introspection_c__ROS_TYPE_FLOAT: return 4;
    case rosidl_typesupport_introspection_c__ROS_TYPE_DOUBLE: return 8;
    case rosidl_typesupport_introspection_c__ROS_TYPE_LONG_DOUBLE: return sizeof(long double);
    case rosidl_typesupport_introspection_c__ROS_TYPE_CHAR: return 1;
    case rosidl_typesupport_introspection_c__ROS_TYPE_WCHAR: return 2;
    case rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN: return 1;
    case rosidl_typesupport_introspection_c__ROS_TYPE_OCTET: return 1;
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT8: return 1;
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT8: return 1;
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT16: return 2;
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT16: return 2;
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT32: return 4;
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT32: return 4;
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT64: return 8;
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT64: return 8;
    default: return 0;
  }
}

/// CDR alignment of a primitive of `size` bytes.
inline size_t alignment_of(size_t size)
{
  return std::min<size_t>(size, 8u);
}

// ------------------------------------------------------------------------------ the traits
// What differs between the two type supports: the structs, the string types and how a
// sequence is resized. Strings are read as (data, size) and written from (data, size);
// the write functions return false instead of throwing (C: out of memory).

/// rosidl_typesupport_introspection_c: rosidl_runtime_c strings and sequences.
struct C
{
  using Members = rosidl_typesupport_introspection_c__MessageMembers;
  using Member = rosidl_typesupport_introspection_c__MessageMember;
  using ServiceMembers = rosidl_typesupport_introspection_c__ServiceMembers;
  static constexpr bool kCpp = false;
  static const char * identifier() { return kIntrospectionC; }

  static void read_string(const void * field, const char ** data, size_t * size)
  {
    const auto * s = static_cast<const rosidl_runtime_c__String *>(field);
    *data = s->data != nullptr ? s->data : "";
    *size = s->data != nullptr ? s->size : 0u;
  }
  static bool write_string(void * field, const char * data, size_t size)
  {
    return rosidl_runtime_c__String__assignn(
      static_cast<rosidl_runtime_c__String *>(field), data, size);
  }
  static void read_u16string(const void * field, const uint16_t ** data, size_t * size)
  {
    static const uint16_t empty = 0;
    const auto * s = static_cast<const rosidl_runtime_c__U16String *>(field);
    *data = s->data != nullptr ? s->data : &empty;
    *size = s->data != nullptr ? s->size : 0u;
  }
  static bool write_u16string(void * field, const uint16_t * data, size_t size)
  {
    return rosidl_runtime_c__U16String__assignn(
      static_cast<rosidl_runtime_c__U16String *>(field), data, size);
  }
  /// The generated function finalises the sequence and initialises a new one of `size`
  /// elements; false when that allocation fails.
  static bool renew_sequence(const Member & m, void * field, size_t size)
  {
    return m.resize_function(field, size);
  }
};

/// rosidl_typesupport_introspection_cpp: std::string, std::u16string, std::vector,
/// rosidl_runtime_cpp::BoundedVector (whose resize throws std::length_error over its bound).
struct Cpp
{
  using Members = rosidl_typesupport_introspection_cpp::MessageMembers;
  using Member = rosidl_typesupport_introspection_cpp::MessageMember;
  using ServiceMembers = rosidl_typesupport_introspection_cpp::ServiceMembers;
  static constexpr bool kCpp = true;
  static const char * identifier() { return kIntrospectionCpp; }

  static void read_string(const void * field, const char ** data, size_t * size)
  {
    const auto * s = static_cast<const std::string *>(field);
    *data = s->data();
    *size = s->size();
  }
  static bool write_string(void * field, const char * data, size_t size)
  {
    try {
      static_cast<std::string *>(field)->assign(data, size);
    } catch (...) {
      return false;
    }
    return true;
  }
  static void read_u16string(const void * field, const uint16_t ** data, size_t * size)
  {
    const auto * s = static_cast<const std::u16string *>(field);
    *data = reinterpret_cast<const uint16_t *>(s->data());
    *size = s->size();
  }
  static bool write_u16string(void * field, const uint16_t * data, size_t size)
  {
    try {
      static_cast<std::u16string *>(field)->assign(reinterpret_cast<const char16_t *>(data), size);
    } catch (...) {
      return false;
    }
    return true;
  }
  /// Cleared first, then grown: every element is newly constructed, as with C. Any exception
  /// (std::bad_alloc, std::length_error, one of an element's constructor) is caught.
  static bool renew_sequence(const Member & m, void * field, size_t size)
  {
    try {
      m.resize_function(field, 0u);
      m.resize_function(field, size);
    } catch (...) {
      return false;
    }
    return true;
  }
};

// ------------------------------------------------------------------------- member shapes

/// How member `m` repeats: not at all, `T[N]`, `T[<=N]` or `T[]`.
template<typename T>
FieldArray array_of(const typename T::Member & m)
{
  if (!m.is_array_) {
    return FieldArray::None;
  }
  if (m.is_upper_bound_) {
    return FieldArray::Bounded;
  }
  return m.array_size_ > 0u ? FieldArray::Fixed : FieldArray::Unbounded;
}

/// A C++ sequence of bool: std::vector<bool> (and BoundedVector<bool>) has no element
/// addresses, so its elements go through fetch/assign. Every other array is contiguous.
template<typename T>
bool is_packed_bool_sequence(const typename T::Member & m)
{
  return T::kCpp && m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN &&
    m.is_array_ && array_of<T>(m) != FieldArray::Fixed;
}

/// The members of the nested message type of member `m` (type id MESSAGE), reached through
/// its type support handle (asking it for this type support if it is another); nullptr when
/// the type support gives none.
template<typename T>
const typename T::Members * nested_members(const typename T::Member & m)
{
  if (m.members_ == nullptr) {
    return nullptr;
  }
  const rosidl_message_type_support_t * handle =
    lookup_message_type_support(m.members_, T::identifier());
  return handle != nullptr ? static_cast<const typename T::Members *>(handle->data) : nullptr;
}

/// "pkg/msg/X" of a message type's members.
template<typename T>
std::string type_name_of(const typename T::Members * members)
{
  return type_name_from_namespace(members->message_namespace_, members->message_name_);
}

/// The member of `members` named `name`; nullptr when there is none.
template<typename T>
const typename T::Member * find_member(
  const typename T::Members * members, const std::string & name)
{
  for (uint32_t i = 0; members->members_ != nullptr && i < members->member_count_; ++i) {
    if (name == members->members_[i].name_) {
      return &members->members_[i];
    }
  }
  return nullptr;
}

// ------------------------------------------------------------------------- member dispatch

/// The one dispatch over a member's type: one value of member `m` (the member itself or one
/// element of an array member) at `field` goes to the visitor function for its type, whose
/// result is returned:
///   visitor.primitive(m, field, size)    numbers, bool, char, wchar, octet; `size` bytes
///   visitor.string(m, field)             T::read_string / T::write_string
///   visitor.wstring(m, field)            T::read_u16string / T::write_u16string
///   visitor.message(m, field, nested)    `nested`: nested_members<T>(m), maybe nullptr
///   visitor.unknown(m, field)            a type id neither type support defines
/// `field` is passed on as given: `const void *` to read, `void *` to write, nullptr to
/// describe the type alone.
template<typename T, typename Field, typename Visitor>
auto dispatch(const typename T::Member & m, Field field, Visitor && visitor)
{
  switch (m.type_id_) {
    case rosidl_typesupport_introspection_c__ROS_TYPE_STRING: return visitor.string(m, field);
    case rosidl_typesupport_introspection_c__ROS_TYPE_WSTRING: return visitor.wstring(m, field);
    case rosidl_typesupport_introspection_c__ROS_TYPE_MESSAGE:
      return visitor.message(m, field, nested_members<T>(m));
    default:
      {
        const size_t size = primitive_size(m.type_id_);
        if (size == 0u) {
          return visitor.unknown(m, field);
        }
        return visitor.primitive(m, field, size);
      }
  }
}

// ------------------------------------------------------------------------- array members

/// How many elements array member `m` holds at `field`: a fixed array its size, a sequence
/// its length. False when the type support gives no size function.
template<typename T>
bool element_count(const typename T::Member & m, const void * field, size_t * count)
{
  if (array_of<T>(m) == FieldArray::Fixed) {
    *count = m.array_size_;
    return true;
  }
  if (m.size_function == nullptr) {
    return false;
  }
  *count = m.size_function(field);
  return true;
}

/// Give sequence member `m` at `field` exactly `size` elements. The same for both type
/// supports:
/// - afterwards every element is newly initialised (its defaults; primitives unspecified):
///   nothing of before is kept, since C's resize function finalises the old sequence. The
///   caller writes the elements it wants.
/// - false, the member unchanged, for a member that is no sequence (a fixed array has no
///   resize function) or a `size` over a bounded sequence's bound (which C would accept and
///   C++ refuse by throwing).
/// - false when allocating fails (C: its function returns false; C++: any exception, caught);
///   the sequence is then empty or as C left it, still valid for the message's fini.
/// - never throws.
template<typename T>
bool resize(const typename T::Member & m, void * field, size_t size)
{
  const FieldArray array = array_of<T>(m);
  if (m.resize_function == nullptr ||
      (array != FieldArray::Bounded && array != FieldArray::Unbounded) ||
      (array == FieldArray::Bounded && size > m.array_size_))
  {
    return false;
  }
  return T::renew_sequence(m, field, size);
}

/// Element `index` of array member `m` at `field` (index < its element count), handed to
/// `visit(element, index)`, whose result is returned. `Field` is `const void` to read and
/// `void` to write. An element of a C++ bool sequence has no address: `visit` gets a bool
/// copied out of it, and, when writing, what `visit` left there is assigned back. False when
/// the type support gives no way to reach the element.
template<typename T, typename Field, typename Visit>
bool with_element(const typename T::Member & m, Field * field, size_t index, Visit && visit)
{
  static_assert(
    std::is_same<std::remove_const_t<Field>, void>::value,
    "pass the field as const void * or void *");
  constexpr bool kWrite = !std::is_const<Field>::value;
  if (is_packed_bool_sequence<T>(m)) {
    if (m.fetch_function == nullptr || (kWrite && m.assign_function == nullptr)) {
      return false;
    }
    bool value = false;
    m.fetch_function(field, index, &value);
    if (!visit(static_cast<Field *>(&value), index)) {
      return false;
    }
    if constexpr (kWrite) {
      m.assign_function(field, index, &value);
    }
    return true;
  }
  if constexpr (kWrite) {
    if (m.get_function == nullptr) {
      return false;
    }
    return visit(m.get_function(field, index), index);
  } else {
    if (m.get_const_function == nullptr) {
      return false;
    }
    return visit(m.get_const_function(field, index), index);
  }
}

/// The one loop over the elements of an array member: with_element for elements 0 ..
/// `count` - 1, stopping at the first false.
template<typename T, typename Field, typename Visit>
bool for_each_element(const typename T::Member & m, Field * field, size_t count, Visit && visit)
{
  for (size_t k = 0; k < count; ++k) {
    if (!with_element<T>(m, field, k, visit)) {
      return false;
    }
  }
  return true;
}

/// The first of `count` > 0 elements of array member `m` at `field` when they are primitives
/// in one block of memory (every array of primitives but a C++ bool sequence), for copying
/// all at once; nullptr otherwise (then use for_each_element).
template<typename T>
const void * contiguous_primitives(const typename T::Member & m, const void * field)
{
  if (primitive_size(m.type_id_) == 0u || is_packed_bool_sequence<T>(m) ||
      m.get_const_function == nullptr)
  {
    return nullptr;
  }
  return m.get_const_function(field, 0u);
}

template<typename T>
void * contiguous_primitives(const typename T::Member & m, void * field)
{
  if (primitive_size(m.type_id_) == 0u || is_packed_bool_sequence<T>(m) ||
      m.get_function == nullptr)
  {
    return nullptr;
  }
  return m.get_function(field, 0u);
}

/// `fn(traits, members)` with the traits of `layout`'s type support (a `C` or a `Cpp` value:
/// `using T = decltype(traits)`) and its members cast to them; returns fn's result.
template<typename Fn>
auto with_traits(const MessageLayout & layout, Fn && fn)
{
  return layout.is_cpp ? fn(Cpp{}, static_cast<const Cpp::Members *>(layout.members)) :
                         fn(C{}, static_cast<const C::Members *>(layout.members));
}

}  // namespace introspection
}  // namespace rmw_introspect

#endif  // DETAIL__INTROSPECTION_HPP_
