// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// What the C and the C++ introspection type supports share and where they differ, for the code
// that walks messages through them (CDR, content filters).
#ifndef DETAIL__MEMBERS_HPP_
#define DETAIL__MEMBERS_HPP_

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>
#include <string>

#include "rosidl_runtime_c/message_initialization.h"
#include "rosidl_runtime_c/string.h"
#include "rosidl_runtime_c/string_functions.h"
#include "rosidl_runtime_c/u16string.h"
#include "rosidl_runtime_c/u16string_functions.h"
#include "rosidl_typesupport_introspection_c/field_types.h"
#include "rosidl_typesupport_introspection_c/message_introspection.h"
#include "rosidl_runtime_cpp/message_initialization.hpp"
#include "rosidl_typesupport_introspection_cpp/message_introspection.hpp"

namespace rmw_introspect
{
namespace members
{

static_assert(sizeof(bool) == 1, "CDR booleans are one byte; so must C and C++ bool be");

/// Bytes of one element of a primitive type id; 0 for strings and nested messages.
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

inline size_t alignment_of(size_t size)
{
  return std::min<size_t>(size, 8u);
}

// What differs between the C and the C++ introspection type supports.
struct CTypes
{
  using Members = rosidl_typesupport_introspection_c__MessageMembers;
  using Member = rosidl_typesupport_introspection_c__MessageMember;
  static constexpr bool kCpp = false;

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
  static bool resize(const Member & member, void * field, size_t size)
  {
    return member.resize_function != nullptr && member.resize_function(field, size);
  }
};

struct CppTypes
{
  using Members = rosidl_typesupport_introspection_cpp::MessageMembers;
  using Member = rosidl_typesupport_introspection_cpp::MessageMember;
  static constexpr bool kCpp = true;

  static void read_string(const void * field, const char ** data, size_t * size)
  {
    const auto * s = static_cast<const std::string *>(field);
    *data = s->data();
    *size = s->size();
  }
  static bool write_string(void * field, const char * data, size_t size)
  {
    static_cast<std::string *>(field)->assign(data, size);
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
    static_cast<std::u16string *>(field)->assign(reinterpret_cast<const char16_t *>(data), size);
    return true;
  }
  static bool resize(const Member & member, void * field, size_t size)
  {
    if (member.resize_function == nullptr) {
      return false;
    }
    member.resize_function(field, size);
    return true;
  }
};

// std::vector<bool> (and rosidl's BoundedVector<bool>) has no element addresses: its
// elements go through fetch/assign. Every other array of primitives is contiguous.
template<typename Types>
inline bool is_packed_bool_sequence(const typename Types::Member & m)
{
  return Types::kCpp && m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN &&
         !(m.array_size_ > 0u && !m.is_upper_bound_);
}

template<typename Types>
inline bool is_fixed_array(const typename Types::Member & m)
{
  return m.is_array_ && m.array_size_ > 0u && !m.is_upper_bound_;
}

/// A plain type (rmw_fastrtps_cpp's "plain"/bounded-size notion): fixed size, made of
/// primitives, fixed arrays and plain messages only - no string, no sequence.
template<typename Types>
bool is_plain(const typename Types::Members * members)
{
  for (uint32_t i = 0; i < members->member_count_; ++i) {
    const typename Types::Member & m = members->members_[i];
    if (m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_STRING ||
      m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_WSTRING ||
      (m.is_array_ && !is_fixed_array<Types>(m)))
    {
      return false;
    }
    if (m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_MESSAGE &&
      (m.members_ == nullptr || m.members_->data == nullptr ||
      !is_plain<Types>(static_cast<const typename Types::Members *>(m.members_->data))))
    {
      return false;
    }
  }
  return true;
}

/// A new, initialised message of a type (C: zeroed, then __init()ed, as the generated
/// __create() does: a C __init() sets only the fields with a default value, strings and
/// sequences, and leaves other numbers and fixed arrays as the memory was; C++: constructed,
/// which zeroes them); NULL when out of memory. destroy_message finalises and frees it.
inline void * create_message(const void * members_ptr, bool is_cpp)
{
  const size_t size = is_cpp ?
    static_cast<const CppTypes::Members *>(members_ptr)->size_of_ :
    static_cast<const CTypes::Members *>(members_ptr)->size_of_;
  void * memory = ::operator new(std::max<size_t>(size, 1u),
      std::align_val_t(alignof(std::max_align_t)), std::nothrow);
  if (memory == nullptr) {
    return nullptr;
  }
  std::memset(memory, 0, std::max<size_t>(size, 1u));
  if (is_cpp) {
    static_cast<const CppTypes::Members *>(members_ptr)->init_function(
      memory, rosidl_runtime_cpp::MessageInitialization::ALL);
  } else {
    static_cast<const CTypes::Members *>(members_ptr)->init_function(
      memory, ROSIDL_RUNTIME_C_MSG_INIT_ALL);
  }
  return memory;
}

inline void destroy_message(const void * members_ptr, bool is_cpp, void * message)
{
  if (message == nullptr) {
    return;
  }
  if (is_cpp) {
    static_cast<const CppTypes::Members *>(members_ptr)->fini_function(message);
  } else {
    static_cast<const CTypes::Members *>(members_ptr)->fini_function(message);
  }
  ::operator delete(message, std::align_val_t(alignof(std::max_align_t)));
}

}  // namespace members
}  // namespace rmw_introspect

#endif  // DETAIL__MEMBERS_HPP_
