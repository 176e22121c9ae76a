// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__JSON_WRITER_HPP_
#define DETAIL__JSON_WRITER_HPP_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rmw_introspect
{

/// Append `in` as a JSON string (also a valid YAML double-quoted scalar). Invalid UTF-8 bytes
/// become U+FFFD so that the document always decodes.
void append_json_string(std::string & out, std::string_view in);

/// Append a double written exactly: the shortest of %.15g..%.17g that reads back the same,
/// with ".0" added when it has neither '.' nor exponent; NaN and infinities as the strings
/// "nan", "inf", "-inf".
void append_exact_double(std::string & out, double d);

/// Append a double as %.3f (the capture's milliseconds).
void append_fixed_double(std::string & out, double d);

void append_integer(std::string & out, int64_t i);

/// Streams the capture's JSON layout into a string: objects one field a line, arrays of
/// containers one item a line, 2 more spaces per level; flat arrays (of scalars) on one line;
/// empty containers as [] and {}. Writes straight into the output: no tree, no temporaries.
/// The caller keeps the calls balanced (a key before each value inside an object).
class JsonWriter
{
public:
  /// The first value written sits at column `indent` (its contents at indent + 2).
  explicit JsonWriter(std::string & out, int indent = 0);

  JsonWriter & key(std::string_view name);
  void begin_object();
  void end_object();
  void begin_array();
  /// An array of scalars only, written on one line: [1, 2].
  void begin_flat_array();
  void end_array();
  void null();
  void boolean(bool b);
  void integer(int64_t i);
  void fixed(double d);  // append_fixed_double
  void real(double d);   // append_exact_double
  void string(std::string_view s);
  /// A value already rendered by a JsonWriter whose indent was value_indent().
  void raw(std::string_view text);

  /// The column the value written next starts at (its nesting level).
  int value_indent() const { return indent_ + 2 * static_cast<int>(levels_.size()); }

private:
  struct Level
  {
    bool object;
    bool flat;
    bool empty;
  };

  void before_value();
  void begin(bool object, bool flat);
  void end(char close);

  std::string & out_;
  int indent_;
  std::vector<Level> levels_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__JSON_WRITER_HPP_
