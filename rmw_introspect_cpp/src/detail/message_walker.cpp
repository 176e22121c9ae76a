// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/message_walker.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "detail/introspection.hpp"

namespace rmw_introspect
{

namespace
{

// The primitive field type ids (the same numbers in both type supports).
enum FieldType : uint8_t {
  kFloat = rosidl_typesupport_introspection_c__ROS_TYPE_FLOAT,
  kDouble = rosidl_typesupport_introspection_c__ROS_TYPE_DOUBLE,
  kLongDouble = rosidl_typesupport_introspection_c__ROS_TYPE_LONG_DOUBLE,
  kChar = rosidl_typesupport_introspection_c__ROS_TYPE_CHAR,
  kWChar = rosidl_typesupport_introspection_c__ROS_TYPE_WCHAR,
  kBoolean = rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN,
  kOctet = rosidl_typesupport_introspection_c__ROS_TYPE_OCTET,
  kUint8 = rosidl_typesupport_introspection_c__ROS_TYPE_UINT8,
  kInt8 = rosidl_typesupport_introspection_c__ROS_TYPE_INT8,
  kUint16 = rosidl_typesupport_introspection_c__ROS_TYPE_UINT16,
  kInt16 = rosidl_typesupport_introspection_c__ROS_TYPE_INT16,
  kUint32 = rosidl_typesupport_introspection_c__ROS_TYPE_UINT32,
  kInt32 = rosidl_typesupport_introspection_c__ROS_TYPE_INT32,
  kUint64 = rosidl_typesupport_introspection_c__ROS_TYPE_UINT64,
  kInt64 = rosidl_typesupport_introspection_c__ROS_TYPE_INT64,
};

// ------------------------------------------------------------------ UTF-8 <-> UTF-16
std::string utf16_to_utf8(const uint16_t * data, size_t n)
{
  std::string out;
  for (size_t k = 0; k < n; ++k) {
    uint32_t c = data[k];
    if (c >= 0xD800 && c <= 0xDBFF && k + 1 < n && data[k + 1] >= 0xDC00 && data[k + 1] <= 0xDFFF) {
      c = 0x10000 + ((c - 0xD800) << 10) + (data[k + 1] - 0xDC00);
      ++k;
    } else if (c >= 0xD800 && c <= 0xDFFF) {
      c = 0xFFFD;
    }
    if (c < 0x80) {
      out.push_back(static_cast<char>(c));
    } else if (c < 0x800) {
      out.push_back(static_cast<char>(0xC0 | (c >> 6)));
      out.push_back(static_cast<char>(0x80 | (c & 0x3F)));
    } else if (c < 0x10000) {
      out.push_back(static_cast<char>(0xE0 | (c >> 12)));
      out.push_back(static_cast<char>(0x80 | ((c >> 6) & 0x3F)));
      out.push_back(static_cast<char>(0x80 | (c & 0x3F)));
    } else {
      out.push_back(static_cast<char>(0xF0 | (c >> 18)));
      out.push_back(static_cast<char>(0x80 | ((c >> 12) & 0x3F)));
      out.push_back(static_cast<char>(0x80 | ((c >> 6) & 0x3F)));
      out.push_back(static_cast<char>(0x80 | (c & 0x3F)));
    }
  }
  return out;
}

std::u16string utf8_to_utf16(const std::string & in)
{
  std::u16string out;
  const auto * p = reinterpret_cast<const unsigned char *>(in.data());
  for (size_t k = 0; k < in.size();) {
    const size_t remaining = in.size() - k;
    uint32_t c = p[k];
    size_t len = 1;
    if (c >= 0xF0 && remaining >= 4) {
      c = ((c & 0x07) << 18) | ((p[k + 1] & 0x3Fu) << 12) | ((p[k + 2] & 0x3Fu) << 6) |
        (p[k + 3] & 0x3Fu);
      len = 4;
    } else if (c >= 0xE0 && c < 0xF0 && remaining >= 3) {
      c = ((c & 0x0F) << 12) | ((p[k + 1] & 0x3Fu) << 6) | (p[k + 2] & 0x3Fu);
      len = 3;
    } else if (c >= 0xC0 && c < 0xE0 && remaining >= 2) {
      c = ((c & 0x1F) << 6) | (p[k + 1] & 0x3Fu);
      len = 2;
    } else if (c >= 0x80) {
      c = 0xFFFD;
    }
    if (c >= 0x10000) {
      c -= 0x10000;
      out.push_back(static_cast<char16_t>(0xD800 + (c >> 10)));
      out.push_back(static_cast<char16_t>(0xDC00 + (c & 0x3FF)));
    } else {
      out.push_back(static_cast<char16_t>(c));
    }
    k += len;
  }
  return out;
}

using introspection::primitive_size;

// ------------------------------------------------------------------ primitives
template<typename T>
T load(const void * p)
{
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

template<typename T>
void store(void * p, T v)
{
  std::memcpy(p, &v, sizeof(T));
}

DynValue read_primitive(uint8_t type, const void * p)
{
  switch (type) {
    case kFloat: return DynValue::real(load<float>(p));
    case kDouble: return DynValue::real(load<double>(p));
    case kLongDouble: return DynValue::real(static_cast<double>(load<long double>(p)));
    case kBoolean: return DynValue::boolean(load<bool>(p));
    case kChar:
    case kOctet:
    case kUint8: return DynValue::uinteger(load<uint8_t>(p));
    case kInt8: return DynValue::integer(load<int8_t>(p));
    case kWChar:
    case kUint16: return DynValue::uinteger(load<uint16_t>(p));
    case kInt16: return DynValue::integer(load<int16_t>(p));
    case kUint32: return DynValue::uinteger(load<uint32_t>(p));
    case kInt32: return DynValue::integer(load<int32_t>(p));
    case kUint64: return DynValue::uinteger(load<uint64_t>(p));
    case kInt64: return DynValue::integer(load<int64_t>(p));
    default: return DynValue();
  }
}

// An integer value of `v` within [lo, hi] (hi as unsigned to cover uint64).
bool integer_in_range(
  const DynValue & v, int64_t lo, uint64_t hi, bool * negative, uint64_t * magnitude)
{
  switch (v.kind) {
    case DynValue::Kind::Bool:
      *negative = false;
      *magnitude = v.b ? 1 : 0;
      break;
    case DynValue::Kind::Int:
      *negative = v.i < 0;
      *magnitude = v.i < 0 ? static_cast<uint64_t>(-(v.i + 1)) + 1 : static_cast<uint64_t>(v.i);
      break;
    case DynValue::Kind::UInt:
      *negative = false;
      *magnitude = v.u;
      break;
    case DynValue::Kind::Double:
      if (!std::isfinite(v.d) || std::floor(v.d) != v.d || std::fabs(v.d) > 9.2e18) {
        return false;
      }
      *negative = v.d < 0;
      *magnitude = static_cast<uint64_t>(std::fabs(v.d));
      break;
    default: return false;
  }
  if (*negative) {
    const uint64_t lo_magnitude = lo < 0 ? static_cast<uint64_t>(-(lo + 1)) + 1 : 0;
    return *magnitude <= lo_magnitude;
  }
  return *magnitude <= hi;
}

template<typename T>
bool store_integer(void * p, const DynValue & v)
{
  bool negative = false;
  uint64_t magnitude = 0;
  if (!integer_in_range(
        v, static_cast<int64_t>(std::numeric_limits<T>::min()),
        static_cast<uint64_t>(std::numeric_limits<T>::max()), &negative, &magnitude))
  {
    return false;
  }
  const T value =
    negative ? static_cast<T>(-static_cast<int64_t>(magnitude - 1) - 1) : static_cast<T>(magnitude);
  store<T>(p, value);
  return true;
}

bool write_primitive(uint8_t type, const DynValue & v, void * p)
{
  if (!v.is_number()) {
    return false;
  }
  switch (type) {
    case kFloat: store<float>(p, static_cast<float>(v.as_double())); return true;
    case kDouble: store<double>(p, v.as_double()); return true;
    case kLongDouble: store<long double>(p, static_cast<long double>(v.as_double())); return true;
    case kBoolean:
      if (v.kind == DynValue::Kind::Double || v.as_uint() > 1) {
        return false;
      }
      store<bool>(p, v.as_bool());
      return true;
    case kChar:
    case kOctet:
    case kUint8: return store_integer<uint8_t>(p, v);
    case kInt8: return store_integer<int8_t>(p, v);
    case kWChar:
    case kUint16: return store_integer<uint16_t>(p, v);
    case kInt16: return store_integer<int16_t>(p, v);
    case kUint32: return store_integer<uint32_t>(p, v);
    case kInt32: return store_integer<int32_t>(p, v);
    case kUint64: return store_integer<uint64_t>(p, v);
    case kInt64: return store_integer<int64_t>(p, v);
    default: return false;
  }
}

// ------------------------------------------------------------------ the walker
template<typename T>
class Walker
{
public:
  using Members = typename T::Members;
  using Member = typename T::Member;

  explicit Walker(std::string * error)
  : error_(error)
  {
  }

  bool read_struct(const Members * members, const void * message, DynValue * out)
  {
    if (members == nullptr || message == nullptr) {
      return fail("", "no introspection members");
    }
    *out = DynValue::structure();
    out->fields.reserve(members->member_count_);
    for (uint32_t k = 0; k < members->member_count_; ++k) {
      const Member & m = members->members_[k];
      const void * field = static_cast<const char *>(message) + m.offset_;
      DynValue value;
      Scope scope(path_, m.name_);
      if (!(m.is_array_ ? read_array(m, field, &value) : read_single(m, field, &value))) {
        return false;
      }
      out->fields.emplace_back(m.name_, std::move(value));
    }
    return true;
  }

  bool write_struct(const Members * members, const DynValue & value, void * message)
  {
    if (members == nullptr || message == nullptr) {
      return fail("", "no introspection members");
    }
    if (value.kind == DynValue::Kind::Null) {
      return true;
    }
    if (value.kind != DynValue::Kind::Struct) {
      return fail("", "a message needs a struct value");
    }
    for (const auto & f : value.fields) {
      const Member * m = introspection::find_member<T>(members, f.first);
      if (m == nullptr) {
        return fail(f.first, "no such field in " + introspection::type_name_of<T>(members));
      }
      void * field = static_cast<char *>(message) + m->offset_;
      Scope scope(path_, f.first);
      if (!(m->is_array_ ? write_array(*m, f.second, field) : write_single(*m, f.second, field))) {
        return false;
      }
    }
    return true;
  }

private:
  // One value into a DynValue: the visitor of introspection::dispatch.
  struct Reader
  {
    Walker & walker;
    DynValue * out;

    bool primitive(const Member & m, const void * field, size_t)
    {
      *out = read_primitive(m.type_id_, field);
      return true;
    }
    bool string(const Member &, const void * field)
    {
      const char * data = nullptr;
      size_t size = 0;
      T::read_string(field, &data, &size);
      *out = DynValue::string(std::string(data, size));
      return true;
    }
    bool wstring(const Member &, const void * field)
    {
      const uint16_t * data = nullptr;
      size_t size = 0;
      T::read_u16string(field, &data, &size);
      *out = DynValue::string(utf16_to_utf8(data, size));
      return true;
    }
    bool message(const Member &, const void * field, const Members * nested)
    {
      return walker.read_struct(nested, field, out);
    }
    bool unknown(const Member & m, const void *)
    {
      return walker.fail("", "unknown field type " + std::to_string(m.type_id_));
    }
  };

  // One value from a DynValue: the visitor of introspection::dispatch.
  struct Writer
  {
    Walker & walker;
    const DynValue & value;

    bool primitive(const Member & m, void * field, size_t)
    {
      return write_primitive(m.type_id_, value, field) ||
        walker.fail("", "value of the wrong kind or out of range");
    }
    bool string(const Member & m, void * field)
    {
      return bounded_string(m) &&
        (T::write_string(field, value.s.data(), value.s.size()) ||
         walker.fail("", "cannot assign the string"));
    }
    bool wstring(const Member & m, void * field)
    {
      if (!bounded_string(m)) {
        return false;
      }
      const std::u16string w = utf8_to_utf16(value.s);
      return T::write_u16string(field, reinterpret_cast<const uint16_t *>(w.data()), w.size()) ||
        walker.fail("", "cannot assign the string");
    }
    bool message(const Member &, void * field, const Members * nested)
    {
      return walker.write_struct(nested, value, field);
    }
    bool unknown(const Member & m, void *)
    {
      return walker.fail("", "unknown field type " + std::to_string(m.type_id_));
    }

    bool bounded_string(const Member & m)
    {
      if (value.kind != DynValue::Kind::String) {
        return walker.fail("", "expects a string");
      }
      if (m.string_upper_bound_ > 0 && value.s.size() > m.string_upper_bound_) {
        return walker.fail(
          "", "string longer than its bound " + std::to_string(m.string_upper_bound_));
      }
      return true;
    }
  };

  bool read_single(const Member & m, const void * field, DynValue * out)
  {
    return introspection::dispatch<T>(m, field, Reader{*this, out});
  }

  bool write_single(const Member & m, const DynValue & value, void * field)
  {
    return introspection::dispatch<T>(m, field, Writer{*this, value});
  }

  bool read_array(const Member & m, const void * field, DynValue * out)
  {
    size_t n = 0;
    if (!introspection::element_count<T>(m, field, &n)) {
      return fail("", "array without a size function");
    }
    *out = DynValue::sequence();
    out->items.reserve(n);
    const bool named = primitive_size(m.type_id_) == 0;  // a primitive's read cannot fail
    return introspection::for_each_element<T>(
             m, field, n,
             [&](const void * element, size_t k) {
               DynValue item;
               if (named) {
                 Scope scope(path_, "[" + std::to_string(k) + "]");
                 if (!read_single(m, element, &item)) {
                   return false;
                 }
               } else if (!read_single(m, element, &item)) {
                 return false;
               }
               out->items.push_back(std::move(item));
               return true;
             }) ||
      fail("", "array without a way to reach its elements");
  }

  bool write_array(const Member & m, const DynValue & value, void * field)
  {
    if (value.kind != DynValue::Kind::Sequence) {
      return fail("", "expects a sequence");
    }
    const size_t n = value.items.size();
    const FieldArray array = introspection::array_of<T>(m);
    if (array != FieldArray::Unbounded && n > m.array_size_) {
      return fail(
        "",
        std::to_string(n) + " items for an array of " +
          (array == FieldArray::Bounded ? "at most " : "") + std::to_string(m.array_size_));
    }
    if (array != FieldArray::Fixed && !introspection::resize<T>(m, field, n)) {
      return fail("", "cannot resize the sequence");
    }
    return introspection::for_each_element<T>(
             m, field, n,
             [&](void * element, size_t k) {
               Scope scope(path_, "[" + std::to_string(k) + "]");
               return write_single(m, value.items[k], element);
             }) ||
      fail("", "array without a way to reach its elements");
  }

  // The error names the field path: "descriptors[2].name: expects a string". The first
  // failure is kept; the callers unwinding it only return false.
  bool fail(const std::string & where, const std::string & what)
  {
    if (error_ != nullptr && !failed_) {
      std::string path;
      for (const auto & part : path_) {
        path += (path.empty() || part[0] == '[') ? part : "." + part;
      }
      if (!where.empty()) {
        path += (path.empty() || where[0] == '[') ? where : "." + where;
      }
      *error_ = path.empty() ? what : path + ": " + what;
    }
    failed_ = true;
    return false;
  }

  // Descend into `part` (a field name or "[k]") for error paths.
  struct Scope
  {
    Scope(std::vector<std::string> & path, std::string part)
    : path_(path)
    {
      path_.push_back(std::move(part));
    }
    ~Scope() { path_.pop_back(); }
    Scope(const Scope &) = delete;
    Scope & operator=(const Scope &) = delete;
    std::vector<std::string> & path_;
  };

  std::string * error_;
  bool failed_ = false;
  std::vector<std::string> path_;
};

}  // namespace

bool service_message_layouts(
  const ResolvedType & service, MessageLayout * request, MessageLayout * response,
  std::string * error)
{
  if (service.members == nullptr || request == nullptr || response == nullptr) {
    if (error != nullptr) {
      *error = "no service members";
    }
    return false;
  }
  service_layouts(service, request, response);
  if (request->members == nullptr || response->members == nullptr) {
    if (error != nullptr) {
      *error = "service without request or response members";
    }
    return false;
  }
  return true;
}

std::string layout_type_name(const MessageLayout & layout)
{
  if (layout.members == nullptr) {
    return std::string();
  }
  return introspection::with_traits(layout, [](auto traits, const auto * members) {
    return introspection::type_name_of<decltype(traits)>(members);
  });
}

bool read_message(
  const MessageLayout & layout, const void * message, DynValue * out, std::string * error)
{
  if (out == nullptr) {
    if (error != nullptr) {
      *error = "no output value";
    }
    return false;
  }
  if (error != nullptr) {
    error->clear();
  }
  return introspection::with_traits(layout, [&](auto traits, const auto * members) {
    return Walker<decltype(traits)>(error).read_struct(members, message, out);
  });
}

bool write_message(
  const MessageLayout & layout, const DynValue & value, void * message, std::string * error)
{
  if (error != nullptr) {
    error->clear();
  }
  return introspection::with_traits(layout, [&](auto traits, const auto * members) {
    return Walker<decltype(traits)>(error).write_struct(members, value, message);
  });
}

}  // namespace rmw_introspect
