// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__CDR_HPP_
#define DETAIL__CDR_HPP_

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "detail/typesupport.hpp"

namespace rmw_introspect
{

/// Serialize `message` (an instance of `layout`) as little-endian plain CDR (XCDR1) after the
/// 4-byte encapsulation header {0x00, 0x01, 0x00, 0x00}, the format rmw_fastrtps_cpp's
/// rmw_serialize produces. Only this process reads it back: wstrings are written as a uint32
/// count and 16-bit characters. `out` is replaced. False (and `error`) on a bound exceeded.
bool cdr_serialize(
  const MessageLayout & layout, const void * message, std::vector<uint8_t> * out,
  std::string * error);

/// Read CDR written by cdr_serialize (or any little-endian XCDR1 of the same type) into
/// `message`, an initialised instance of `layout` (C: __init()ed; C++: constructed). Strings
/// and sequences of `message` are resized as needed. False (and `error`) on truncated or
/// malformed input or a bound exceeded; `message` may then be partly filled.
bool cdr_deserialize(
  const MessageLayout & layout, const uint8_t * data, size_t size, void * message,
  std::string * error);

}  // namespace rmw_introspect

#endif  // DETAIL__CDR_HPP_
