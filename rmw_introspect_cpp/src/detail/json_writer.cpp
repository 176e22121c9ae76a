// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/json_writer.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rmw_introspect
{

namespace
{

// Length of the valid UTF-8 sequence starting at p[k] (a byte >= 0x80), 0 if invalid.
size_t utf8_sequence(const unsigned char * p, size_t k, size_t n)
{
  const unsigned char c = p[k];
  size_t len = 0;
  if ((c & 0xE0) == 0xC0 && c >= 0xC2) {
    len = 2;
  } else if ((c & 0xF0) == 0xE0) {
    len = 3;
  } else if ((c & 0xF8) == 0xF0 && c <= 0xF4) {
    len = 4;
  }
  if (len == 0 || k + len > n) {
    return 0;
  }
  for (size_t j = 1; j < len; ++j) {
    if ((p[k + j] & 0xC0) != 0x80) {
      return 0;
    }
  }
  return len;
}

}  // namespace

void append_json_string(std::string & out, std::string_view in)
{
  static const char kHex[] = "0123456789abcdef";
  out.push_back('"');
  const auto * p = reinterpret_cast<const unsigned char *>(in.data());
  const size_t n = in.size();
  size_t plain = 0;  // start of the bytes copied as they are, not appended yet
  size_t k = 0;
  while (k < n) {
    const unsigned char c = p[k];
    if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\') {
      ++k;
      continue;
    }
    if (c >= 0x80) {
      const size_t len = utf8_sequence(p, k, n);
      if (len != 0) {
        k += len;
        continue;
      }
    }
    out.append(in.data() + plain, k - plain);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c >= 0x80) {
          out += "\\ufffd";
        } else {  // other control characters and DEL
          out += "\\u00";
          out.push_back(kHex[c >> 4]);
          out.push_back(kHex[c & 0xf]);
        }
    }
    plain = ++k;
  }
  out.append(in.data() + plain, n - plain);
  out.push_back('"');
}

void append_exact_double(std::string & out, double d)
{
  if (std::isnan(d)) {
    out += "\"nan\"";
    return;
  }
  if (std::isinf(d)) {
    out += d > 0 ? "\"inf\"" : "\"-inf\"";
    return;
  }
  char buf[64];
  int len = 0;
  for (int precision = 15; precision <= 17; ++precision) {
    len = std::snprintf(buf, sizeof(buf), "%.*g", precision, d);
    if (std::strtod(buf, nullptr) == d) {
      break;
    }
  }
  out.append(buf, static_cast<size_t>(len));
  if (std::strpbrk(buf, ".e") == nullptr) {
    out += ".0";  // stays a floating point number for the reader
  }
}

void append_fixed_double(std::string & out, double d)
{
  char buf[64];
  const int len = std::snprintf(buf, sizeof(buf), "%.3f", d);
  out.append(buf, static_cast<size_t>(len));
}

void append_integer(std::string & out, int64_t i)
{
  char buf[24];
  const auto result = std::to_chars(buf, buf + sizeof(buf), i);
  out.append(buf, static_cast<size_t>(result.ptr - buf));
}

JsonWriter::JsonWriter(std::string & out, int indent)
: out_(out), indent_(indent)
{
  levels_.reserve(8);
}

JsonWriter & JsonWriter::key(std::string_view name)
{
  Level & top = levels_.back();
  out_ += top.empty ? "\n" : ",\n";
  top.empty = false;
  out_.append(static_cast<size_t>(value_indent()), ' ');
  append_json_string(out_, name);
  out_ += ": ";
  return *this;
}

void JsonWriter::before_value()
{
  if (levels_.empty() || levels_.back().object) {
    return;  // the document itself, or an object's value: key() wrote what goes before it
  }
  Level & top = levels_.back();
  if (top.flat) {
    if (!top.empty) {
      out_ += ", ";
    }
  } else {
    out_ += top.empty ? "\n" : ",\n";
    out_.append(static_cast<size_t>(value_indent()), ' ');
  }
  top.empty = false;
}

void JsonWriter::begin(bool object, bool flat)
{
  before_value();
  out_.push_back(object ? '{' : '[');
  levels_.push_back(Level{object, flat, true});
}

void JsonWriter::end(char close)
{
  const Level top = levels_.back();
  levels_.pop_back();
  if (!top.empty && !top.flat) {
    out_.push_back('\n');
    out_.append(static_cast<size_t>(value_indent()), ' ');
  }
  out_.push_back(close);
}

void JsonWriter::begin_object()
{
  begin(true, false);
}
void JsonWriter::end_object()
{
  end('}');
}
void JsonWriter::begin_array()
{
  begin(false, false);
}
void JsonWriter::begin_flat_array()
{
  begin(false, true);
}
void JsonWriter::end_array()
{
  end(']');
}

void JsonWriter::null()
{
  before_value();
  out_ += "null";
}

void JsonWriter::boolean(bool b)
{
  before_value();
  out_ += b ? "true" : "false";
}

void JsonWriter::integer(int64_t i)
{
  before_value();
  append_integer(out_, i);
}

void JsonWriter::fixed(double d)
{
  before_value();
  append_fixed_double(out_, d);
}

void JsonWriter::real(double d)
{
  before_value();
  append_exact_double(out_, d);
}

void JsonWriter::string(std::string_view s)
{
  before_value();
  append_json_string(out_, s);
}

void JsonWriter::raw(std::string_view text)
{
  before_value();
  out_.append(text.data(), text.size());
}

}  // namespace rmw_introspect
