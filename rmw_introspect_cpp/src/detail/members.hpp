// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Messages of an introspection layout in memory: made, finalised and freed, and whether a type
// is plain (fixed size). The traits of the two type supports are in introspection.hpp.
#ifndef DETAIL__MEMBERS_HPP_
#define DETAIL__MEMBERS_HPP_

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>

#include "rosidl_runtime_c/message_initialization.h"
#include "rosidl_runtime_cpp/message_initialization.hpp"

#include "detail/introspection.hpp"

namespace rmw_introspect
{
namespace members
{

/// A plain type (rmw_fastrtps_cpp's "plain"/bounded-size notion): fixed size, made of
/// primitives, fixed arrays and plain messages only - no string, no sequence.
template<typename T>
bool is_plain(const typename T::Members * members)
{
  // Per member: a primitive is plain, a string never, a message when its type is.
  struct Plain
  {
    bool primitive(const typename T::Member &, std::nullptr_t, size_t) { return true; }
    bool string(const typename T::Member &, std::nullptr_t) { return false; }
    bool wstring(const typename T::Member &, std::nullptr_t) { return false; }
    bool message(const typename T::Member &, std::nullptr_t, const typename T::Members * nested)
    {
      return nested != nullptr && is_plain<T>(nested);
    }
    bool unknown(const typename T::Member &, std::nullptr_t) { return false; }
  };
  for (uint32_t i = 0; i < members->member_count_; ++i) {
    const typename T::Member & m = members->members_[i];
    const FieldArray array = introspection::array_of<T>(m);
    if ((array != FieldArray::None && array != FieldArray::Fixed) ||
        !introspection::dispatch<T>(m, nullptr, Plain{}))
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
    static_cast<const introspection::Cpp::Members *>(members_ptr)->size_of_ :
    static_cast<const introspection::C::Members *>(members_ptr)->size_of_;
  void * memory = ::operator new(
    std::max<size_t>(size, 1u), std::align_val_t(alignof(std::max_align_t)), std::nothrow);
  if (memory == nullptr) {
    return nullptr;
  }
  std::memset(memory, 0, std::max<size_t>(size, 1u));
  if (is_cpp) {
    static_cast<const introspection::Cpp::Members *>(members_ptr)
      ->init_function(memory, rosidl_runtime_cpp::MessageInitialization::ALL);
  } else {
    static_cast<const introspection::C::Members *>(members_ptr)
      ->init_function(memory, ROSIDL_RUNTIME_C_MSG_INIT_ALL);
  }
  return memory;
}

inline void destroy_message(const void * members_ptr, bool is_cpp, void * message)
{
  if (message == nullptr) {
    return;
  }
  if (is_cpp) {
    static_cast<const introspection::Cpp::Members *>(members_ptr)->fini_function(message);
  } else {
    static_cast<const introspection::C::Members *>(members_ptr)->fini_function(message);
  }
  ::operator delete(message, std::align_val_t(alignof(std::max_align_t)));
}

}  // namespace members
}  // namespace rmw_introspect

#endif  // DETAIL__MEMBERS_HPP_
