// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/message_walker.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <string>
#include <utility>
#include <vector>

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

namespace rmw_introspect
{

namespace
{

// The field type ids are the same numbers in both type supports.
enum FieldType : uint8_t
{
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
  kString = rosidl_typesupport_introspection_c__ROS_TYPE_STRING,
  kWString = rosidl_typesupport_introspection_c__ROS_TYPE_WSTRING,
  kMessage = rosidl_typesupport_introspection_c__ROS_TYPE_MESSAGE,
};
static_assert(
  kMessage == rosidl_typesupport_introspection_cpp::ROS_TYPE_MESSAGE &&
  kWString == rosidl_typesupport_introspection_cpp::ROS_TYPE_WSTRING &&
  kFloat == rosidl_typesupport_introspection_cpp::ROS_TYPE_FLOAT &&
  kInt64 == rosidl_typesupport_introspection_cpp::ROS_TYPE_INT64,
  "C and C++ introspection field type ids differ");

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
  for (size_t k = 0; k < in.size(); ) {
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

// ------------------------------------------------------------------ the two layouts
struct CLayout
{
  using Members = rosidl_typesupport_introspection_c__MessageMembers;
  using Member = rosidl_typesupport_introspection_c__MessageMember;
  static const char * identifier() {return kIntrospectionC;}

  static std::string read_string(const void * p)
  {
    const auto * s = static_cast<const rosidl_runtime_c__String *>(p);
    return s->data != nullptr ? std::string(s->data, s->size) : std::string();
  }
  static bool write_string(void * p, const std::string & v)
  {
    return rosidl_runtime_c__String__assignn(
      static_cast<rosidl_runtime_c__String *>(p), v.data(), v.size());
  }
  static std::string read_wstring(const void * p)
  {
    const auto * s = static_cast<const rosidl_runtime_c__U16String *>(p);
    return s->data != nullptr ? utf16_to_utf8(s->data, s->size) : std::string();
  }
  static bool write_wstring(void * p, const std::string & v)
  {
    const std::u16string w = utf8_to_utf16(v);
    return rosidl_runtime_c__U16String__assignn(
      static_cast<rosidl_runtime_c__U16String *>(p),
      reinterpret_cast<const uint16_t *>(w.data()), w.size());
  }
  static bool resize(const Member & m, void * p, size_t n)
  {
    return m.resize_function != nullptr && m.resize_function(p, n);
  }
};

struct CppLayout
{
  using Members = rosidl_typesupport_introspection_cpp::MessageMembers;
  using Member = rosidl_typesupport_introspection_cpp::MessageMember;
  static const char * identifier() {return kIntrospectionCpp;}

  static std::string read_string(const void * p) {return *static_cast<const std::string *>(p);}
  static bool write_string(void * p, const std::string & v)
  {
    *static_cast<std::string *>(p) = v;
    return true;
  }
  static std::string read_wstring(const void * p)
  {
    const auto & w = *static_cast<const std::u16string *>(p);
    return utf16_to_utf8(reinterpret_cast<const uint16_t *>(w.data()), w.size());
  }
  static bool write_wstring(void * p, const std::string & v)
  {
    *static_cast<std::u16string *>(p) = utf8_to_utf16(v);
    return true;
  }
  static bool resize(const Member & m, void * p, size_t n)
  {
    if (m.resize_function == nullptr) {
      return false;
    }
    try {
      m.resize_function(p, n);
    } catch (const std::exception &) {
      return false;  // std::array: a size other than its own
    }
    return true;
  }
};

// ------------------------------------------------------------------ primitives
size_t primitive_size(uint8_t type)
{
  switch (type) {
    case kFloat: return sizeof(float);
    case kDouble: return sizeof(double);
    case kLongDouble: return sizeof(long double);
    case kChar: case kOctet: case kUint8: case kInt8: return 1;
    case kBoolean: return sizeof(bool);
    case kWChar: case kUint16: case kInt16: return 2;
    case kUint32: case kInt32: return 4;
    case kUint64: case kInt64: return 8;
    default: return 0;
  }
}

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
    case kChar: case kOctet: case kUint8: return DynValue::uinteger(load<uint8_t>(p));
    case kInt8: return DynValue::integer(load<int8_t>(p));
    case kWChar: case kUint16: return DynValue::uinteger(load<uint16_t>(p));
    case kInt16: return DynValue::integer(load<int16_t>(p));
    case kUint32: return DynValue::uinteger(load<uint32_t>(p));
    case kInt32: return DynValue::integer(load<int32_t>(p));
    case kUint64: return DynValue::uinteger(load<uint64_t>(p));
    case kInt64: return DynValue::integer(load<int64_t>(p));
    default: return DynValue();
  }
}

// An integer value of `v` within [lo, hi] (hi as unsigned to cover uint64).
bool integer_in_range(const DynValue & v, int64_t lo, uint64_t hi, bool * negative, uint64_t * magnitude)
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
    default:
      return false;
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
  const T value = negative ?
    static_cast<T>(-static_cast<int64_t>(magnitude - 1) - 1) : static_cast<T>(magnitude);
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
    case kChar: case kOctet: case kUint8: return store_integer<uint8_t>(p, v);
    case kInt8: return store_integer<int8_t>(p, v);
    case kWChar: case kUint16: return store_integer<uint16_t>(p, v);
    case kInt16: return store_integer<int16_t>(p, v);
    case kUint32: return store_integer<uint32_t>(p, v);
    case kInt32: return store_integer<int32_t>(p, v);
    case kUint64: return store_integer<uint64_t>(p, v);
    case kInt64: return store_integer<int64_t>(p, v);
    default: return false;
  }
}

// ------------------------------------------------------------------ the walker
template<typename L>
class Walker
{
public:
  using Members = typename L::Members;
  using Member = typename L::Member;

  explicit Walker(std::string * error)
  : error_(error) {}

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
      const Member * m = find(members, f.first);
      if (m == nullptr) {
        return fail(f.first, "no such field in " + type_name_of(members));
      }
      void * field = static_cast<char *>(message) + m->offset_;
      Scope scope(path_, f.first);
      if (!(m->is_array_ ? write_array(*m, f.second, field) : write_single(*m, f.second, field))) {
        return false;
      }
    }
    return true;
  }

  static std::string type_name_of(const Members * members)
  {
    return type_name_from_namespace(members->message_namespace_, members->message_name_);
  }

private:
  static const Member * find(const Members * members, const std::string & name)
  {
    for (uint32_t k = 0; k < members->member_count_; ++k) {
      if (name == members->members_[k].name_) {
        return &members->members_[k];
      }
    }
    return nullptr;
  }

  static const Members * nested(const Member & m)
  {
    const rosidl_message_type_support_t * ts = m.members_;
    if (ts == nullptr) {
      return nullptr;
    }
    if (ts->typesupport_identifier == nullptr ||
      std::strcmp(ts->typesupport_identifier, L::identifier()) != 0)
    {
      ts = ts->func != nullptr ? ts->func(ts, L::identifier()) : nullptr;
    }
    return ts != nullptr ? static_cast<const Members *>(ts->data) : nullptr;
  }

  bool read_single(const Member & m, const void * field, DynValue * out)
  {
    switch (m.type_id_) {
      case kString: *out = DynValue::string(L::read_string(field)); return true;
      case kWString: *out = DynValue::string(L::read_wstring(field)); return true;
      case kMessage: return read_struct(nested(m), field, out);
      default:
        if (primitive_size(m.type_id_) == 0) {
          return fail("", "unknown field type " + std::to_string(m.type_id_));
        }
        *out = read_primitive(m.type_id_, field);
        return true;
    }
  }

  bool read_array(const Member & m, const void * field, DynValue * out)
  {
    if (m.size_function == nullptr) {
      return fail("", "array without a size function");
    }
    const size_t n = m.size_function(field);
    *out = DynValue::sequence();
    out->items.reserve(n);
    for (size_t k = 0; k < n; ++k) {
      DynValue item;
      if (m.type_id_ == kString || m.type_id_ == kWString || m.type_id_ == kMessage) {
        if (m.get_const_function == nullptr) {
          return fail("", "array without a get function");
        }
        Scope scope(path_, "[" + std::to_string(k) + "]");
        if (!read_single(m, m.get_const_function(field, k), &item)) {
          return false;
        }
      } else {
        if (primitive_size(m.type_id_) == 0) {
          return fail("", "unknown field type " + std::to_string(m.type_id_));
        }
        alignas(16) unsigned char buffer[16] = {};
        if (m.fetch_function != nullptr) {
          m.fetch_function(field, k, buffer);  // std::vector<bool> has no get function
        } else if (m.get_const_function != nullptr) {
          std::memcpy(buffer, m.get_const_function(field, k), primitive_size(m.type_id_));
        } else {
          return fail("", "array without a fetch function");
        }
        item = read_primitive(m.type_id_, buffer);
      }
      out->items.push_back(std::move(item));
    }
    return true;
  }

  bool write_single(const Member & m, const DynValue & value, void * field)
  {
    switch (m.type_id_) {
      case kString:
      case kWString:
        if (value.kind != DynValue::Kind::String) {
          return fail("", "expects a string");
        }
        if (m.string_upper_bound_ > 0 && value.s.size() > m.string_upper_bound_) {
          return fail("", "string longer than its bound " + std::to_string(m.string_upper_bound_));
        }
        if (!(m.type_id_ == kString ? L::write_string(field, value.s) : L::write_wstring(field, value.s))) {
          return fail("", "cannot assign the string");
        }
        return true;
      case kMessage:
        return write_struct(nested(m), value, field);
      default:
        if (primitive_size(m.type_id_) == 0) {
          return fail("", "unknown field type " + std::to_string(m.type_id_));
        }
        if (!write_primitive(m.type_id_, value, field)) {
          return fail("", "value of the wrong kind or out of range");
        }
        return true;
    }
  }

  bool write_array(const Member & m, const DynValue & value, void * field)
  {
    if (value.kind != DynValue::Kind::Sequence) {
      return fail("", "expects a sequence");
    }
    const size_t n = value.items.size();
    const bool is_sequence = m.array_size_ == 0 || m.is_upper_bound_;
    if (m.array_size_ > 0 && n > m.array_size_) {
      return fail(
        "", std::to_string(n) + " items for an array of " +
        (is_sequence ? "at most " : "") + std::to_string(m.array_size_));
    }
    if (is_sequence && !L::resize(m, field, n)) {
      return fail("", "cannot resize the sequence");
    }
    for (size_t k = 0; k < n; ++k) {
      const DynValue & item = value.items[k];
      if (m.type_id_ == kString || m.type_id_ == kWString || m.type_id_ == kMessage) {
        if (m.get_function == nullptr) {
          return fail("", "array without a get function");
        }
        Scope scope(path_, "[" + std::to_string(k) + "]");
        if (!write_single(m, item, m.get_function(field, k))) {
          return false;
        }
        continue;
      }
      alignas(16) unsigned char buffer[16] = {};
      if (primitive_size(m.type_id_) == 0 || !write_primitive(m.type_id_, item, buffer)) {
        return fail("[" + std::to_string(k) + "]", "value of the wrong kind or out of range");
      }
      if (m.assign_function != nullptr) {
        m.assign_function(field, k, buffer);  // std::vector<bool> has no get function
      } else if (m.get_function != nullptr) {
        std::memcpy(m.get_function(field, k), buffer, primitive_size(m.type_id_));
      } else {
        return fail("", "array without an assign function");
      }
    }
    return true;
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
    : path_(path) {path_.push_back(std::move(part));}
    ~Scope() {path_.pop_back();}
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
    if (error != nullptr) {*error = "no service members";}
    return false;
  }
  service_layouts(service, request, response);
  if (request->members == nullptr || response->members == nullptr) {
    if (error != nullptr) {*error = "service without request or response members";}
    return false;
  }
  return true;
}

std::string layout_type_name(const MessageLayout & layout)
{
  if (layout.members == nullptr) {
    return std::string();
  }
  return layout.is_cpp ?
         Walker<CppLayout>::type_name_of(static_cast<const CppLayout::Members *>(layout.members)) :
         Walker<CLayout>::type_name_of(static_cast<const CLayout::Members *>(layout.members));
}

bool read_message(
  const MessageLayout & layout, const void * message, DynValue * out, std::string * error)
{
  if (out == nullptr) {
    if (error != nullptr) {*error = "no output value";}
    return false;
  }
  if (error != nullptr) {error->clear();}
  if (layout.is_cpp) {
    return Walker<CppLayout>(error).read_struct(
      static_cast<const CppLayout::Members *>(layout.members), message, out);
  }
  return Walker<CLayout>(error).read_struct(
    static_cast<const CLayout::Members *>(layout.members), message, out);
}

bool write_message(
  const MessageLayout & layout, const DynValue & value, void * message, std::string * error)
{
  if (error != nullptr) {error->clear();}
  if (layout.is_cpp) {
    return Walker<CppLayout>(error).write_struct(
      static_cast<const CppLayout::Members *>(layout.members), value, message);
  }
  return Walker<CLayout>(error).write_struct(
    static_cast<const CLayout::Members *>(layout.members), value, message);
}

}  // namespace rmw_introspect
