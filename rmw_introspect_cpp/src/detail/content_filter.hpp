// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__CONTENT_FILTER_HPP_
#define DETAIL__CONTENT_FILTER_HPP_

#include <memory>
#include <string>
#include <vector>

#include "detail/cdr.hpp"

namespace rmw_introspect
{

/// A content filter expression (the SQL subset of DDS ContentFilteredTopic that ROS 2 uses)
/// compiled against a message type: comparisons `=`, `<>`, `!=`, `<`, `<=`, `>`, `>=`, `LIKE`
/// (`%` and `_` wildcards), `BETWEEN .. AND ..` and `NOT BETWEEN`, combined with `AND`, `OR`,
/// `NOT` and parentheses. Operands are field paths (`a.b`, `a[2].b`), parameters `%0`..`%99`
/// (each parameter is itself a literal) and literals: integers, reals, 'strings', TRUE, FALSE.
/// A comparison with a float32 field compares in float32 precision (`x = 3.14` matches the
/// float 3.14f, as in Fast DDS).
class ContentFilter
{
public:
  ~ContentFilter();

  /// NULL (and `error`) when the expression does not parse, names an unknown field or a
  /// parameter that was not given.
  static std::unique_ptr<ContentFilter> compile(
    const MessageLayout & layout, const std::string & expression,
    const std::vector<std::string> & parameters, std::string * error);

  /// Whether `message`, an instance of the layout compiled against, passes the filter.
  bool matches(const void * message) const;

  struct Node;

private:
  ContentFilter() = default;
  MessageLayout layout_;
  std::unique_ptr<Node> root_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__CONTENT_FILTER_HPP_
