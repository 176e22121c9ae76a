// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__DYNAMIC_VALUE_HPP_
#define DETAIL__DYNAMIC_VALUE_HPP_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rmw_introspect
{

/// The content of a ROS message as a tree, independent of its C or C++ memory layout: what
/// the message walker reads from a message and writes into one (message_walker.hpp).
/// Structs keep their fields in member order; arrays and sequences are Sequence values.
struct DynValue
{
  enum class Kind { Null, Bool, Int, UInt, Double, String, Sequence, Struct };
  Kind kind = Kind::Null;
  bool b = false;
  int64_t i = 0;
  uint64_t u = 0;
  double d = 0.0;
  std::string s;
  std::vector<DynValue> items;                           // Sequence
  std::vector<std::pair<std::string, DynValue>> fields;  // Struct

  static DynValue boolean(bool v);
  static DynValue integer(int64_t v);
  static DynValue uinteger(uint64_t v);
  static DynValue real(double v);
  static DynValue string(std::string v);
  static DynValue sequence(std::vector<DynValue> items = {});
  static DynValue structure();

  /// Struct: add (or replace) a field; returns *this for chaining.
  DynValue & set(const std::string & name, DynValue value);
  /// Struct: the field `name`, or NULL (also when this is not a struct).
  const DynValue * field(const std::string & name) const;
  /// Sequence: append.
  DynValue & push(DynValue value);

  /// Conversions that accept every numeric kind (false/0 for anything else).
  bool as_bool() const;
  int64_t as_int() const;
  uint64_t as_uint() const;
  double as_double() const;
  bool is_number() const;
};

/// A sequence of strings (request fields such as GetParameters.names).
DynValue string_sequence(const std::vector<std::string> & strings);

}  // namespace rmw_introspect

#endif  // DETAIL__DYNAMIC_VALUE_HPP_
