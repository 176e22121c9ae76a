// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Plain little-endian CDR over the introspection type supports (C and C++), enough for
// rmw_serialize / rmw_deserialize and for handing messages from a publisher to the
// subscriptions of the same process (each side with its own type support, C or C++).
#include "detail/cdr.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "detail/members.hpp"

namespace rmw_introspect
{

namespace
{

using members::alignment_of;
using members::CppTypes;
using members::CTypes;
using members::is_fixed_array;
using members::is_packed_bool_sequence;
using members::primitive_size;

constexpr uint8_t kEncapsulation[4] = {0x00, 0x01, 0x00, 0x00};  // CDR_LE, no options
constexpr size_t kHeader = sizeof(kEncapsulation);

bool fail(std::string * error, const std::string & message)
{
  if (error != nullptr) {
    *error = message;
  }
  return false;
}

class Writer
{
public:
  explicit Writer(std::vector<uint8_t> * out)
  : out_(out) {}

  void align(size_t alignment)
  {
    const size_t position = out_->size() - kHeader;
    const size_t padding = (alignment - position % alignment) % alignment;
    out_->insert(out_->end(), padding, 0u);
  }
  void put(const void * data, size_t size)
  {
    const auto * bytes = static_cast<const uint8_t *>(data);
    out_->insert(out_->end(), bytes, bytes + size);
  }
  void primitive(const void * data, size_t size)
  {
    align(alignment_of(size));
    put(data, size);
  }
  void u32(uint32_t value)
  {
    primitive(&value, sizeof(value));
  }

private:
  std::vector<uint8_t> * out_;
};

template<typename Types>
bool write_message(
  const typename Types::Members * members, const uint8_t * base, Writer & w, std::string * error);

template<typename Types>
bool write_value(
  const typename Types::Member & m, const void * field, Writer & w, std::string * error)
{
  switch (m.type_id_) {
    case rosidl_typesupport_introspection_c__ROS_TYPE_STRING: {
        const char * data = nullptr;
        size_t size = 0;
        Types::read_string(field, &data, &size);
        if (m.string_upper_bound_ > 0u && size > m.string_upper_bound_) {
          return fail(error, std::string("string field '") + m.name_ + "' exceeds its bound");
        }
        w.u32(static_cast<uint32_t>(size + 1u));
        w.put(data, size);
        const uint8_t nul = 0u;
        w.put(&nul, 1u);
        return true;
      }
    case rosidl_typesupport_introspection_c__ROS_TYPE_WSTRING: {
        const uint16_t * data = nullptr;
        size_t size = 0;
        Types::read_u16string(field, &data, &size);
        if (m.string_upper_bound_ > 0u && size > m.string_upper_bound_) {
          return fail(error, std::string("wstring field '") + m.name_ + "' exceeds its bound");
        }
        w.u32(static_cast<uint32_t>(size));
        if (size > 0u) {
          w.align(2u);
          w.put(data, size * 2u);
        }
        return true;
      }
    case rosidl_typesupport_introspection_c__ROS_TYPE_MESSAGE: {
        if (m.members_ == nullptr || m.members_->data == nullptr) {
          return fail(error, std::string("field '") + m.name_ + "' has no type support");
        }
        return write_message<Types>(
          static_cast<const typename Types::Members *>(m.members_->data),
          static_cast<const uint8_t *>(field), w, error);
      }
    case rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN: {
        const uint8_t value = *static_cast<const bool *>(field) ? 1u : 0u;
        w.put(&value, 1u);
        return true;
      }
    default: {
        const size_t size = primitive_size(m.type_id_);
        if (size == 0u) {
          return fail(error, std::string("field '") + m.name_ + "' has an unknown type");
        }
        w.primitive(field, size);
        return true;
      }
  }
}

template<typename Types>
bool write_message(
  const typename Types::Members * members, const uint8_t * base, Writer & w, std::string * error)
{
  for (uint32_t i = 0; i < members->member_count_; ++i) {
    const typename Types::Member & m = members->members_[i];
    const void * field = base + m.offset_;
    if (!m.is_array_) {
      if (!write_value<Types>(m, field, w, error)) {
        return false;
      }
      continue;
    }
    const bool fixed = is_fixed_array<Types>(m);
    size_t count = 0;
    if (fixed) {
      count = m.array_size_;
    } else if (m.size_function != nullptr) {
      count = m.size_function(field);
    } else {
      return fail(error, std::string("sequence field '") + m.name_ + "' has no size function");
    }
    if (m.is_upper_bound_ && count > m.array_size_) {
      return fail(error, std::string("sequence field '") + m.name_ + "' exceeds its bound");
    }
    if (!fixed) {
      w.u32(static_cast<uint32_t>(count));
    }
    if (count == 0u) {
      continue;
    }
    const size_t size = primitive_size(m.type_id_);
    if (size > 0u && is_packed_bool_sequence<Types>(m)) {
      for (size_t k = 0; k < count; ++k) {
        bool value = false;
        m.fetch_function(field, k, &value);
        const uint8_t byte = value ? 1u : 0u;
        w.put(&byte, 1u);
      }
    } else if (size > 0u) {
      // Contiguous elements, each aligned once the first is.
      w.align(alignment_of(size));
      if (m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN) {
        const auto * values = static_cast<const bool *>(m.get_const_function(field, 0));
        for (size_t k = 0; k < count; ++k) {
          const uint8_t byte = values[k] ? 1u : 0u;
          w.put(&byte, 1u);
        }
      } else {
        w.put(m.get_const_function(field, 0), count * size);
      }
    } else {
      for (size_t k = 0; k < count; ++k) {
        if (!write_value<Types>(m, m.get_const_function(field, k), w, error)) {
          return false;
        }
      }
    }
  }
  return true;
}

class Reader
{
public:
  Reader(const uint8_t * data, size_t size)
  : data_(data), size_(size), position_(kHeader) {}

  size_t remaining() const {return size_ - position_;}

  bool align(size_t alignment)
  {
    const size_t body = position_ - kHeader;
    const size_t padding = (alignment - body % alignment) % alignment;
    if (padding > remaining()) {
      return false;
    }
    position_ += padding;
    return true;
  }
  const uint8_t * take(size_t size)
  {
    if (size > remaining()) {
      return nullptr;
    }
    const uint8_t * at = data_ + position_;
    position_ += size;
    return at;
  }
  bool primitive(void * out, size_t size)
  {
    if (!align(alignment_of(size))) {
      return false;
    }
    const uint8_t * at = take(size);
    if (at == nullptr) {
      return false;
    }
    std::memcpy(out, at, size);
    return true;
  }
  bool u32(uint32_t * value)
  {
    return primitive(value, sizeof(*value));
  }

private:
  const uint8_t * data_;
  size_t size_;
  size_t position_;
};

bool truncated(std::string * error, const char * field)
{
  return fail(error, std::string("serialized message ends inside field '") + field + "'");
}

template<typename Types>
bool read_message(
  const typename Types::Members * members, uint8_t * base, Reader & r, std::string * error);

template<typename Types>
bool read_value(const typename Types::Member & m, void * field, Reader & r, std::string * error)
{
  switch (m.type_id_) {
    case rosidl_typesupport_introspection_c__ROS_TYPE_STRING: {
        uint32_t length = 0;
        if (!r.u32(&length)) {
          return truncated(error, m.name_);
        }
        const uint8_t * bytes = r.take(length);
        if (bytes == nullptr) {
          return truncated(error, m.name_);
        }
        const size_t size = length > 0u ? length - 1u : 0u;  // without the terminating NUL
        if (m.string_upper_bound_ > 0u && size > m.string_upper_bound_) {
          return fail(error, std::string("string field '") + m.name_ + "' exceeds its bound");
        }
        if (!Types::write_string(field, reinterpret_cast<const char *>(bytes), size)) {
          return fail(error, std::string("cannot store string field '") + m.name_ + "'");
        }
        return true;
      }
    case rosidl_typesupport_introspection_c__ROS_TYPE_WSTRING: {
        uint32_t count = 0;
        if (!r.u32(&count)) {
          return truncated(error, m.name_);
        }
        if (m.string_upper_bound_ > 0u && count > m.string_upper_bound_) {
          return fail(error, std::string("wstring field '") + m.name_ + "' exceeds its bound");
        }
        std::vector<uint16_t> chars(count);
        if (count > 0u) {
          if (!r.align(2u)) {
            return truncated(error, m.name_);
          }
          const uint8_t * bytes = r.take(static_cast<size_t>(count) * 2u);
          if (bytes == nullptr) {
            return truncated(error, m.name_);
          }
          std::memcpy(chars.data(), bytes, static_cast<size_t>(count) * 2u);
        }
        if (!Types::write_u16string(field, chars.data(), count)) {
          return fail(error, std::string("cannot store wstring field '") + m.name_ + "'");
        }
        return true;
      }
    case rosidl_typesupport_introspection_c__ROS_TYPE_MESSAGE: {
        if (m.members_ == nullptr || m.members_->data == nullptr) {
          return fail(error, std::string("field '") + m.name_ + "' has no type support");
        }
        return read_message<Types>(
          static_cast<const typename Types::Members *>(m.members_->data),
          static_cast<uint8_t *>(field), r, error);
      }
    case rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN: {
        const uint8_t * byte = r.take(1u);
        if (byte == nullptr) {
          return truncated(error, m.name_);
        }
        *static_cast<bool *>(field) = *byte != 0u;
        return true;
      }
    default: {
        const size_t size = primitive_size(m.type_id_);
        if (size == 0u) {
          return fail(error, std::string("field '") + m.name_ + "' has an unknown type");
        }
        if (!r.primitive(field, size)) {
          return truncated(error, m.name_);
        }
        return true;
      }
  }
}

template<typename Types>
bool read_message(
  const typename Types::Members * members, uint8_t * base, Reader & r, std::string * error)
{
  for (uint32_t i = 0; i < members->member_count_; ++i) {
    const typename Types::Member & m = members->members_[i];
    void * field = base + m.offset_;
    if (!m.is_array_) {
      if (!read_value<Types>(m, field, r, error)) {
        return false;
      }
      continue;
    }
    const bool fixed = is_fixed_array<Types>(m);
    size_t count = m.array_size_;
    if (!fixed) {
      uint32_t length = 0;
      if (!r.u32(&length)) {
        return truncated(error, m.name_);
      }
      count = length;
      if (m.is_upper_bound_ && count > m.array_size_) {
        return fail(error, std::string("sequence field '") + m.name_ + "' exceeds its bound");
      }
      // Every element takes at least one byte: refuse lengths the input cannot hold before
      // resizing anything.
      if (count > r.remaining()) {
        return truncated(error, m.name_);
      }
      if (!Types::resize(m, field, count)) {
        return fail(error, std::string("cannot resize sequence field '") + m.name_ + "'");
      }
    }
    if (count == 0u) {
      continue;
    }
    const size_t size = primitive_size(m.type_id_);
    if (size > 0u && is_packed_bool_sequence<Types>(m)) {
      for (size_t k = 0; k < count; ++k) {
        const uint8_t * byte = r.take(1u);
        if (byte == nullptr) {
          return truncated(error, m.name_);
        }
        const bool value = *byte != 0u;
        m.assign_function(field, k, &value);
      }
    } else if (size > 0u) {
      if (!r.align(alignment_of(size))) {
        return truncated(error, m.name_);
      }
      const uint8_t * bytes = r.take(count * size);
      if (bytes == nullptr) {
        return truncated(error, m.name_);
      }
      void * first = m.get_function(field, 0);
      if (m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN) {
        auto * values = static_cast<bool *>(first);
        for (size_t k = 0; k < count; ++k) {
          values[k] = bytes[k] != 0u;
        }
      } else {
        std::memcpy(first, bytes, count * size);
      }
    } else {
      for (size_t k = 0; k < count; ++k) {
        if (!read_value<Types>(m, m.get_function(field, k), r, error)) {
          return false;
        }
      }
    }
  }
  return true;
}

}  // namespace

bool cdr_serialize(
  const MessageLayout & layout, const void * message, std::vector<uint8_t> * out,
  std::string * error)
{
  if (layout.members == nullptr || message == nullptr || out == nullptr) {
    return fail(error, "cdr_serialize: null argument");
  }
  out->assign(kEncapsulation, kEncapsulation + kHeader);
  Writer w(out);
  const auto * base = static_cast<const uint8_t *>(message);
  return layout.is_cpp ?
         write_message<CppTypes>(
    static_cast<const CppTypes::Members *>(layout.members), base, w, error) :
         write_message<CTypes>(static_cast<const CTypes::Members *>(layout.members), base, w, error);
}

bool cdr_deserialize(
  const MessageLayout & layout, const uint8_t * data, size_t size, void * message,
  std::string * error)
{
  if (layout.members == nullptr || message == nullptr || (data == nullptr && size > 0u)) {
    return fail(error, "cdr_deserialize: null argument");
  }
  if (size < kHeader) {
    return fail(error, "serialized message is shorter than its encapsulation header");
  }
  if (data[1] != kEncapsulation[1]) {
    return fail(error, "serialized message is not little-endian plain CDR");
  }
  Reader r(data, size);
  auto * base = static_cast<uint8_t *>(message);
  return layout.is_cpp ?
         read_message<CppTypes>(static_cast<const CppTypes::Members *>(layout.members), base, r, error) :
         read_message<CTypes>(static_cast<const CTypes::Members *>(layout.members), base, r, error);
}

}  // namespace rmw_introspect
