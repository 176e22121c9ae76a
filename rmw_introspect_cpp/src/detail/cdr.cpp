// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// Plain little-endian CDR over the introspection type supports (C and C++), enough for
// rmw_serialize / rmw_deserialize and for handing messages from a publisher to the
// subscriptions of the same process (each side with its own type support, C or C++).
#include "detail/cdr.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "detail/introspection.hpp"

namespace rmw_introspect
{

namespace
{

using introspection::alignment_of;
using introspection::primitive_size;

constexpr uint8_t kEncapsulation[4] = {0x00, 0x01, 0x00, 0x00};  // CDR_LE, no options
constexpr size_t kHeader = sizeof(kEncapsulation);

bool fail(std::string * error, const std::string & message)
{
  if (error != nullptr) {
    *error = message;
  }
  return false;
}

// A failure the element loop reports without a message of its own (an element it cannot
// reach): keep the message of a failure inside an element when there was one.
bool fail_once(std::string * error, const std::string & message)
{
  if (error != nullptr && error->empty()) {
    *error = message;
  }
  return false;
}

class Writer
{
public:
  explicit Writer(std::vector<uint8_t> * out)
  : out_(out)
  {
  }

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
  void u32(uint32_t value) { primitive(&value, sizeof(value)); }

private:
  std::vector<uint8_t> * out_;
};

template<typename T>
bool write_message(
  const typename T::Members * members, const uint8_t * base, Writer & w, std::string * error);

// One value (a member or an element) into the stream: the visitor of introspection::dispatch.
template<typename T>
struct ValueWriter
{
  using Member = typename T::Member;
  Writer & w;
  std::string * error;

  bool primitive(const Member & m, const void * field, size_t size)
  {
    if (m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN) {
      const uint8_t value = *static_cast<const bool *>(field) ? 1u : 0u;
      w.put(&value, 1u);
      return true;
    }
    w.primitive(field, size);
    return true;
  }
  bool string(const Member & m, const void * field)
  {
    const char * data = nullptr;
    size_t size = 0;
    T::read_string(field, &data, &size);
    if (m.string_upper_bound_ > 0u && size > m.string_upper_bound_) {
      return fail(error, std::string("string field '") + m.name_ + "' exceeds its bound");
    }
    w.u32(static_cast<uint32_t>(size + 1u));
    w.put(data, size);
    const uint8_t nul = 0u;
    w.put(&nul, 1u);
    return true;
  }
  bool wstring(const Member & m, const void * field)
  {
    const uint16_t * data = nullptr;
    size_t size = 0;
    T::read_u16string(field, &data, &size);
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
  bool message(const Member & m, const void * field, const typename T::Members * nested)
  {
    if (nested == nullptr) {
      return fail(error, std::string("field '") + m.name_ + "' has no type support");
    }
    return write_message<T>(nested, static_cast<const uint8_t *>(field), w, error);
  }
  bool unknown(const Member & m, const void *)
  {
    return fail(error, std::string("field '") + m.name_ + "' has an unknown type");
  }
};

template<typename T>
bool write_array(const typename T::Member & m, const void * field, Writer & w, std::string * error)
{
  size_t count = 0;
  if (!introspection::element_count<T>(m, field, &count)) {
    return fail(error, std::string("sequence field '") + m.name_ + "' has no size function");
  }
  const FieldArray array = introspection::array_of<T>(m);
  if (array == FieldArray::Bounded && count > m.array_size_) {
    return fail(error, std::string("sequence field '") + m.name_ + "' exceeds its bound");
  }
  if (array != FieldArray::Fixed) {
    w.u32(static_cast<uint32_t>(count));
  }
  if (count == 0u) {
    return true;
  }
  const size_t size = primitive_size(m.type_id_);
  const void * block = m.type_id_ != rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN ?
    introspection::contiguous_primitives<T>(m, field) :
    nullptr;
  if (block != nullptr) {
    // Contiguous elements, each aligned once the first is.
    w.align(alignment_of(size));
    w.put(block, count * size);
    return true;
  }
  ValueWriter<T> writer{w, error};
  const bool written = introspection::for_each_element<T>(
    m, field, count,
    [&](const void * element, size_t) { return introspection::dispatch<T>(m, element, writer); });
  return written || fail_once(error, std::string("cannot read sequence field '") + m.name_ + "'");
}

template<typename T>
bool write_message(
  const typename T::Members * members, const uint8_t * base, Writer & w, std::string * error)
{
  ValueWriter<T> writer{w, error};
  for (uint32_t i = 0; i < members->member_count_; ++i) {
    const typename T::Member & m = members->members_[i];
    const void * field = base + m.offset_;
    if (!(m.is_array_ ? write_array<T>(m, field, w, error) :
                        introspection::dispatch<T>(m, field, writer)))
    {
      return false;
    }
  }
  return true;
}

class Reader
{
public:
  Reader(const uint8_t * data, size_t size)
  : data_(data), size_(size), position_(kHeader)
  {
  }

  size_t remaining() const { return size_ - position_; }

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
  bool u32(uint32_t * value) { return primitive(value, sizeof(*value)); }

private:
  const uint8_t * data_;
  size_t size_;
  size_t position_;
};

bool truncated(std::string * error, const char * field)
{
  return fail(error, std::string("serialized message ends inside field '") + field + "'");
}

template<typename T>
bool read_message(
  const typename T::Members * members, uint8_t * base, Reader & r, std::string * error);

// One value (a member or an element) from the stream: the visitor of introspection::dispatch.
template<typename T>
struct ValueReader
{
  using Member = typename T::Member;
  Reader & r;
  std::string * error;

  bool primitive(const Member & m, void * field, size_t size)
  {
    if (m.type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN) {
      const uint8_t * byte = r.take(1u);
      if (byte == nullptr) {
        return truncated(error, m.name_);
      }
      *static_cast<bool *>(field) = *byte != 0u;
      return true;
    }
    return r.primitive(field, size) || truncated(error, m.name_);
  }
  bool string(const Member & m, void * field)
  {
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
    if (!T::write_string(field, reinterpret_cast<const char *>(bytes), size)) {
      return fail(error, std::string("cannot store string field '") + m.name_ + "'");
    }
    return true;
  }
  bool wstring(const Member & m, void * field)
  {
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
    if (!T::write_u16string(field, chars.data(), count)) {
      return fail(error, std::string("cannot store wstring field '") + m.name_ + "'");
    }
    return true;
  }
  bool message(const Member & m, void * field, const typename T::Members * nested)
  {
    if (nested == nullptr) {
      return fail(error, std::string("field '") + m.name_ + "' has no type support");
    }
    return read_message<T>(nested, static_cast<uint8_t *>(field), r, error);
  }
  bool unknown(const Member & m, void *)
  {
    return fail(error, std::string("field '") + m.name_ + "' has an unknown type");
  }
};

template<typename T>
bool read_array(const typename T::Member & m, void * field, Reader & r, std::string * error)
{
  size_t count = m.array_size_;
  if (introspection::array_of<T>(m) != FieldArray::Fixed) {
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
    if (!introspection::resize<T>(m, field, count)) {
      return fail(error, std::string("cannot resize sequence field '") + m.name_ + "'");
    }
  }
  if (count == 0u) {
    return true;
  }
  const size_t size = primitive_size(m.type_id_);
  void * block = m.type_id_ != rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN ?
    introspection::contiguous_primitives<T>(m, field) :
    nullptr;
  if (block != nullptr) {
    if (!r.align(alignment_of(size))) {
      return truncated(error, m.name_);
    }
    const uint8_t * bytes = r.take(count * size);
    if (bytes == nullptr) {
      return truncated(error, m.name_);
    }
    std::memcpy(block, bytes, count * size);
    return true;
  }
  ValueReader<T> reader{r, error};
  const bool read = introspection::for_each_element<T>(
    m, field, count,
    [&](void * element, size_t) { return introspection::dispatch<T>(m, element, reader); });
  return read || fail_once(error, std::string("cannot store sequence field '") + m.name_ + "'");
}

template<typename T>
bool read_message(
  const typename T::Members * members, uint8_t * base, Reader & r, std::string * error)
{
  ValueReader<T> reader{r, error};
  for (uint32_t i = 0; i < members->member_count_; ++i) {
    const typename T::Member & m = members->members_[i];
    void * field = base + m.offset_;
    if (!(m.is_array_ ? read_array<T>(m, field, r, error) :
                        introspection::dispatch<T>(m, field, reader)))
    {
      return false;
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
  if (error != nullptr) {
    error->clear();
  }
  out->assign(kEncapsulation, kEncapsulation + kHeader);
  Writer w(out);
  const auto * base = static_cast<const uint8_t *>(message);
  return introspection::with_traits(layout, [&](auto traits, const auto * members) {
    return write_message<decltype(traits)>(members, base, w, error);
  });
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
  if (error != nullptr) {
    error->clear();
  }
  Reader r(data, size);
  auto * base = static_cast<uint8_t *>(message);
  return introspection::with_traits(layout, [&](auto traits, const auto * members) {
    return read_message<decltype(traits)>(members, base, r, error);
  });
}

}  // namespace rmw_introspect
