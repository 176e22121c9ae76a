// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/dynamic_value.hpp"

namespace rmw_introspect
{

DynValue DynValue::boolean(bool v)
{
  DynValue x;
  x.kind = Kind::Bool;
  x.b = v;
  return x;
}

DynValue DynValue::integer(int64_t v)
{
  DynValue x;
  x.kind = Kind::Int;
  x.i = v;
  return x;
}

DynValue DynValue::uinteger(uint64_t v)
{
  DynValue x;
  x.kind = Kind::UInt;
  x.u = v;
  return x;
}

DynValue DynValue::real(double v)
{
  DynValue x;
  x.kind = Kind::Double;
  x.d = v;
  return x;
}

DynValue DynValue::string(std::string v)
{
  DynValue x;
  x.kind = Kind::String;
  x.s = std::move(v);
  return x;
}

DynValue DynValue::sequence(std::vector<DynValue> items)
{
  DynValue x;
  x.kind = Kind::Sequence;
  x.items = std::move(items);
  return x;
}

DynValue DynValue::structure()
{
  DynValue x;
  x.kind = Kind::Struct;
  return x;
}

DynValue & DynValue::set(const std::string & name, DynValue value)
{
  for (auto & f : fields) {
    if (f.first == name) {
      f.second = std::move(value);
      return *this;
    }
  }
  fields.emplace_back(name, std::move(value));
  return *this;
}

const DynValue * DynValue::field(const std::string & name) const
{
  if (kind != Kind::Struct) {
    return nullptr;
  }
  for (const auto & f : fields) {
    if (f.first == name) {
      return &f.second;
    }
  }
  return nullptr;
}

DynValue & DynValue::push(DynValue value)
{
  items.push_back(std::move(value));
  return *this;
}

bool DynValue::is_number() const
{
  return kind == Kind::Bool || kind == Kind::Int || kind == Kind::UInt || kind == Kind::Double;
}

bool DynValue::as_bool() const
{
  switch (kind) {
    case Kind::Bool: return b;
    case Kind::Int: return i != 0;
    case Kind::UInt: return u != 0;
    case Kind::Double: return d != 0.0;
    default: return false;
  }
}

int64_t DynValue::as_int() const
{
  switch (kind) {
    case Kind::Bool: return b ? 1 : 0;
    case Kind::Int: return i;
    case Kind::UInt: return static_cast<int64_t>(u);
    case Kind::Double: return static_cast<int64_t>(d);
    default: return 0;
  }
}

uint64_t DynValue::as_uint() const
{
  switch (kind) {
    case Kind::Bool: return b ? 1 : 0;
    case Kind::Int: return static_cast<uint64_t>(i);
    case Kind::UInt: return u;
    case Kind::Double: return static_cast<uint64_t>(d);
    default: return 0;
  }
}

double DynValue::as_double() const
{
  switch (kind) {
    case Kind::Bool: return b ? 1.0 : 0.0;
    case Kind::Int: return static_cast<double>(i);
    case Kind::UInt: return static_cast<double>(u);
    case Kind::Double: return d;
    default: return 0.0;
  }
}

DynValue string_sequence(const std::vector<std::string> & strings)
{
  DynValue seq = DynValue::sequence();
  seq.items.reserve(strings.size());
  for (const auto & s : strings) {
    seq.push(DynValue::string(s));
  }
  return seq;
}

}  // namespace rmw_introspect
