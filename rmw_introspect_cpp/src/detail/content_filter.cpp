// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/content_filter.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "detail/introspection.hpp"

namespace rmw_introspect
{

namespace
{

// ----------------------------------------------------------------------------- values

struct Value
{
  enum class Kind { kNone, kInt, kUInt, kReal, kBool, kString };
  Kind kind = Kind::kNone;
  int64_t i = 0;
  uint64_t u = 0;
  double d = 0.0;
  bool b = false;
  bool is_float32 = false;  // read from a float32 field: compare in float precision
  std::string s;

  bool numeric() const { return kind == Kind::kInt || kind == Kind::kUInt || kind == Kind::kReal; }
  double as_double() const
  {
    switch (kind) {
      case Kind::kInt: return static_cast<double>(i);
      case Kind::kUInt: return static_cast<double>(u);
      case Kind::kReal: return d;
      case Kind::kBool: return b ? 1.0 : 0.0;
      default: return 0.0;
    }
  }
};

/// A literal as written in an expression or a parameter; false when it is none.
bool parse_literal(const std::string & text, Value * out)
{
  if (text.size() >= 2 && (text.front() == '\'' || text.front() == '"') &&
      text.back() == text.front())
  {
    out->kind = Value::Kind::kString;
    out->s = text.substr(1, text.size() - 2);
    return true;
  }
  std::string upper;
  for (char c : text) {
    upper.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  }
  if (upper == "TRUE" || upper == "FALSE") {
    out->kind = Value::Kind::kBool;
    out->b = upper == "TRUE";
    return true;
  }
  if (text.empty()) {
    return false;
  }
  const char * begin = text.c_str();
  char * end = nullptr;
  const bool negative = text[0] == '-';
  const bool looks_real = text.find_first_of(".eE") != std::string::npos &&
    upper.rfind("0X", negative ? 1 : 0) == std::string::npos;
  if (!looks_real) {
    errno = 0;
    if (negative) {
      const long long v = std::strtoll(begin, &end, 0);
      if (errno == 0 && end != begin && *end == '\0') {
        out->kind = Value::Kind::kInt;
        out->i = v;
        return true;
      }
    } else {
      const unsigned long long v = std::strtoull(begin, &end, 0);
      if (errno == 0 && end != begin && *end == '\0') {
        out->kind = Value::Kind::kUInt;
        out->u = v;
        return true;
      }
    }
  }
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end != begin && *end == '\0') {
    out->kind = Value::Kind::kReal;
    out->d = v;
    return true;
  }
  return false;
}

/// -1, 0, 1; or 2 when the two cannot be compared.
int compare(const Value & a, const Value & b)
{
  if (a.kind == Value::Kind::kString || b.kind == Value::Kind::kString) {
    if (a.kind != b.kind) {
      return 2;
    }
    const int c = a.s.compare(b.s);
    return c < 0 ? -1 : (c > 0 ? 1 : 0);
  }
  if (a.kind == Value::Kind::kBool || b.kind == Value::Kind::kBool) {
    if (a.kind == Value::Kind::kNone || b.kind == Value::Kind::kNone) {
      return 2;
    }
    const double x = a.as_double();
    const double y = b.as_double();
    return x < y ? -1 : (x > y ? 1 : 0);
  }
  if (!a.numeric() || !b.numeric()) {
    return 2;
  }
  if (a.kind == Value::Kind::kReal || b.kind == Value::Kind::kReal) {
    if (a.is_float32 || b.is_float32) {
      const float x = static_cast<float>(a.as_double());
      const float y = static_cast<float>(b.as_double());
      return x < y ? -1 : (x > y ? 1 : 0);
    }
    const double x = a.as_double();
    const double y = b.as_double();
    return x < y ? -1 : (x > y ? 1 : 0);
  }
  // Integers, signed or not, compared exactly.
  const bool a_negative = a.kind == Value::Kind::kInt && a.i < 0;
  const bool b_negative = b.kind == Value::Kind::kInt && b.i < 0;
  if (a_negative != b_negative) {
    return a_negative ? -1 : 1;
  }
  if (a_negative) {
    return a.i < b.i ? -1 : (a.i > b.i ? 1 : 0);
  }
  const uint64_t x = a.kind == Value::Kind::kInt ? static_cast<uint64_t>(a.i) : a.u;
  const uint64_t y = b.kind == Value::Kind::kInt ? static_cast<uint64_t>(b.i) : b.u;
  return x < y ? -1 : (x > y ? 1 : 0);
}

bool like(const std::string & text, const std::string & pattern)
{
  // Iterative wildcard matching: '%' any run, '_' any one character.
  size_t t = 0, p = 0, star = std::string::npos, mark = 0;
  while (t < text.size()) {
    if (p < pattern.size() && (pattern[p] == '_' || pattern[p] == text[t])) {
      ++t;
      ++p;
    } else if (p < pattern.size() && pattern[p] == '%') {
      star = p++;
      mark = t;
    } else if (star != std::string::npos) {
      p = star + 1;
      t = ++mark;
    } else {
      return false;
    }
  }
  while (p < pattern.size() && pattern[p] == '%') {
    ++p;
  }
  return p == pattern.size();
}

// ----------------------------------------------------------------------------- fields

struct Step
{
  const void * member = nullptr;  // T::Member of the layout's traits
  long index = -1;                // element of an array member, or -1
};

// A primitive field's value (to_value is the visitor of introspection::dispatch).
bool primitive_value(uint8_t type_id, const void * field, Value * out)
{
  switch (type_id) {
    case rosidl_typesupport_introspection_c__ROS_TYPE_FLOAT:
      out->kind = Value::Kind::kReal;
      out->d = *static_cast<const float *>(field);
      out->is_float32 = true;
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_DOUBLE:
      out->kind = Value::Kind::kReal;
      out->d = *static_cast<const double *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_LONG_DOUBLE:
      out->kind = Value::Kind::kReal;
      out->d = static_cast<double>(*static_cast<const long double *>(field));
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN:
      out->kind = Value::Kind::kBool;
      out->b = *static_cast<const bool *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_CHAR:
    case rosidl_typesupport_introspection_c__ROS_TYPE_OCTET:
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT8:
      out->kind = Value::Kind::kUInt;
      out->u = *static_cast<const uint8_t *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT8:
      out->kind = Value::Kind::kInt;
      out->i = *static_cast<const int8_t *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_WCHAR:
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT16:
      out->kind = Value::Kind::kUInt;
      out->u = *static_cast<const uint16_t *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT16:
      out->kind = Value::Kind::kInt;
      out->i = *static_cast<const int16_t *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT32:
      out->kind = Value::Kind::kUInt;
      out->u = *static_cast<const uint32_t *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT32:
      out->kind = Value::Kind::kInt;
      out->i = *static_cast<const int32_t *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT64:
      out->kind = Value::Kind::kUInt;
      out->u = *static_cast<const uint64_t *>(field);
      return true;
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT64:
      out->kind = Value::Kind::kInt;
      out->i = *static_cast<const int64_t *>(field);
      return true;
    default: return false;
  }
}

// A field's value; wstrings and whole messages are not comparable.
template<typename T>
struct ToValue
{
  using Member = typename T::Member;
  Value * out;

  bool primitive(const Member & m, const void * field, size_t)
  {
    return primitive_value(m.type_id_, field, out);
  }
  bool string(const Member &, const void * field)
  {
    const char * data = nullptr;
    size_t size = 0;
    T::read_string(field, &data, &size);
    out->kind = Value::Kind::kString;
    out->s.assign(data, size);
    return true;
  }
  bool wstring(const Member &, const void *) { return false; }
  bool message(const Member &, const void *, const typename T::Members *) { return false; }
  bool unknown(const Member &, const void *) { return false; }
};

template<typename T>
bool read_field(const std::vector<Step> & steps, const void * message, Value * out)
{
  const auto * base = static_cast<const uint8_t *>(message);
  for (size_t k = 0; k < steps.size(); ++k) {
    const auto & m = *static_cast<const typename T::Member *>(steps[k].member);
    const bool last = k + 1 == steps.size();
    const void * field = base + m.offset_;
    if (!m.is_array_) {
      if (last) {
        return introspection::dispatch<T>(m, field, ToValue<T>{out});
      }
      base = static_cast<const uint8_t *>(field);
      continue;
    }
    const size_t index = static_cast<size_t>(steps[k].index);
    size_t count = 0;
    if (!introspection::element_count<T>(m, field, &count) || index >= count) {
      return false;  // no such element: the comparison is false
    }
    // The element's address, or for the last step its value (a C++ bool sequence's element
    // has no lasting address).
    const bool reached =
      introspection::with_element<T>(m, field, index, [&](const void * element, size_t) {
        if (last) {
          return introspection::dispatch<T>(m, element, ToValue<T>{out});
        }
        base = static_cast<const uint8_t *>(element);
        return true;
      });
    if (!reached || last) {
      return reached;
    }
  }
  return false;
}

template<typename T>
bool resolve_path(
  const typename T::Members * members, const std::string & path, std::vector<Step> * steps,
  std::string * error)
{
  size_t start = 0;
  while (true) {
    const size_t dot = path.find('.', start);
    std::string part =
      path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    long index = -1;
    const size_t bracket = part.find('[');
    if (bracket != std::string::npos) {
      if (part.back() != ']') {
        *error = "bad field reference '" + path + "'";
        return false;
      }
      const std::string digits = part.substr(bracket + 1, part.size() - bracket - 2);
      char * end = nullptr;
      index = std::strtol(digits.c_str(), &end, 10);
      if (digits.empty() || *end != '\0' || index < 0) {
        *error = "bad index in field reference '" + path + "'";
        return false;
      }
      part = part.substr(0, bracket);
    }
    if (members == nullptr) {
      *error = "field reference '" + path + "' goes into a field that is not a message";
      return false;
    }
    const typename T::Member * found = introspection::find_member<T>(members, part);
    if (found == nullptr) {
      *error = "unknown field '" + part + "' in '" + path + "'";
      return false;
    }
    if (found->is_array_ != (index >= 0)) {
      *error = found->is_array_ ? "field '" + part + "' is an array: give an index" :
                                  "field '" + part + "' is not an array";
      return false;
    }
    steps->push_back(Step{found, index});
    const bool last = dot == std::string::npos;
    const bool is_message = found->type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_MESSAGE;
    if (last) {
      if (is_message || found->type_id_ == rosidl_typesupport_introspection_c__ROS_TYPE_WSTRING) {
        *error = "field '" + path + "' cannot be compared";
        return false;
      }
      return true;
    }
    members = is_message ? introspection::nested_members<T>(*found) : nullptr;
    start = dot + 1;
  }
}

// ----------------------------------------------------------------------------- lexer

struct Token
{
  enum class Kind {
    kEnd,
    kIdent,
    kParam,
    kLiteral,
    kLParen,
    kRParen,
    kOp,
    kAnd,
    kOr,
    kNot,
    kBetween,
    kLike,
    kMatch
  };
  Kind kind = Kind::kEnd;
  std::string text;
};

bool lex(const std::string & in, std::vector<Token> * tokens, std::string * error)
{
  size_t i = 0;
  auto operand_expected = [&]() {
    if (tokens->empty()) {
      return true;
    }
    const Token::Kind k = tokens->back().kind;
    return k != Token::Kind::kIdent && k != Token::Kind::kParam && k != Token::Kind::kLiteral &&
      k != Token::Kind::kRParen;
  };
  while (i < in.size()) {
    const char c = in[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
      continue;
    }
    Token t;
    if (c == '(' || c == ')') {
      t.kind = c == '(' ? Token::Kind::kLParen : Token::Kind::kRParen;
      ++i;
    } else if (c == '\'' || c == '"') {
      const size_t close = in.find(c, i + 1);
      if (close == std::string::npos) {
        *error = "unterminated string in filter expression";
        return false;
      }
      t.kind = Token::Kind::kLiteral;
      t.text = in.substr(i, close - i + 1);
      i = close + 1;
    } else if (c == '%') {
      size_t j = i + 1;
      while (j < in.size() && std::isdigit(static_cast<unsigned char>(in[j]))) {
        ++j;
      }
      if (j == i + 1) {
        *error = "'%' without a parameter number in filter expression";
        return false;
      }
      t.kind = Token::Kind::kParam;
      t.text = in.substr(i + 1, j - i - 1);
      i = j;
    } else if (std::isdigit(static_cast<unsigned char>(c)) ||
               ((c == '-' || c == '+' || c == '.') && operand_expected() && i + 1 < in.size() &&
                (std::isdigit(static_cast<unsigned char>(in[i + 1])) || in[i + 1] == '.')))
    {
      size_t j = i + 1;
      while (j < in.size() &&
             (std::isalnum(static_cast<unsigned char>(in[j])) || in[j] == '.' ||
              ((in[j] == '-' || in[j] == '+') && (in[j - 1] == 'e' || in[j - 1] == 'E'))))
      {
        ++j;
      }
      t.kind = Token::Kind::kLiteral;
      t.text = in.substr(i, j - i);
      i = j;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      size_t j = i;
      while (j < in.size() &&
             (std::isalnum(static_cast<unsigned char>(in[j])) || in[j] == '_' || in[j] == '.' ||
              in[j] == '[' || in[j] == ']'))
      {
        ++j;
      }
      t.text = in.substr(i, j - i);
      i = j;
      std::string upper;
      for (char ch : t.text) {
        upper.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
      }
      if (upper == "AND") {
        t.kind = Token::Kind::kAnd;
      } else if (upper == "OR") {
        t.kind = Token::Kind::kOr;
      } else if (upper == "NOT") {
        t.kind = Token::Kind::kNot;
      } else if (upper == "BETWEEN") {
        t.kind = Token::Kind::kBetween;
      } else if (upper == "LIKE") {
        t.kind = Token::Kind::kLike;
      } else if (upper == "MATCH") {
        t.kind = Token::Kind::kMatch;
      } else if (upper == "TRUE" || upper == "FALSE") {
        t.kind = Token::Kind::kLiteral;
      } else {
        t.kind = Token::Kind::kIdent;
      }
    } else {
      static const char * const ops[] = {"<>", "!=", "<=", ">=", "==", "=", "<", ">"};
      bool matched = false;
      for (const char * op : ops) {
        const size_t n = std::strlen(op);
        if (in.compare(i, n, op) == 0) {
          t.kind = Token::Kind::kOp;
          t.text = op;
          i += n;
          matched = true;
          break;
        }
      }
      if (!matched) {
        *error = std::string("unexpected character '") + c + "' in filter expression";
        return false;
      }
    }
    tokens->push_back(std::move(t));
  }
  tokens->push_back(Token{});
  return true;
}

}  // namespace

// ----------------------------------------------------------------------------- tree

struct ContentFilter::Node
{
  enum class Kind { kAnd, kOr, kNot, kCompare, kBetween, kLike };
  struct Operand
  {
    bool is_field = false;
    std::vector<Step> steps;
    Value constant;
  };
  Kind kind = Kind::kCompare;
  std::string op;           // kCompare
  bool negate = false;      // kBetween, kLike
  std::unique_ptr<Node> left, right;  // kAnd, kOr, kNot (left)
  Operand a, b, c;          // kCompare (a op b), kBetween (a between b and c), kLike (a like b)
};

namespace
{

using Node = ContentFilter::Node;

class Parser
{
public:
  Parser(
    const MessageLayout & layout, const std::vector<Token> & tokens,
    const std::vector<std::string> & parameters, std::string * error)
  : layout_(layout), tokens_(tokens), parameters_(parameters), error_(error)
  {
  }

  std::unique_ptr<Node> parse()
  {
    auto node = parse_or();
    if (node && peek().kind != Token::Kind::kEnd) {
      *error_ = "unexpected '" + peek().text + "' in filter expression";
      return nullptr;
    }
    return node;
  }

private:
  const Token & peek() const { return tokens_[pos_]; }
  const Token & next() { return tokens_[pos_ < tokens_.size() - 1 ? pos_++ : pos_]; }
  bool accept(Token::Kind kind)
  {
    if (peek().kind == kind) {
      next();
      return true;
    }
    return false;
  }

  std::unique_ptr<Node> parse_or()
  {
    auto left = parse_and();
    while (left && accept(Token::Kind::kOr)) {
      auto node = std::make_unique<Node>();
      node->kind = Node::Kind::kOr;
      node->left = std::move(left);
      node->right = parse_and();
      if (!node->right) {
        return nullptr;
      }
      left = std::move(node);
    }
    return left;
  }

  std::unique_ptr<Node> parse_and()
  {
    auto left = parse_unary();
    while (left && accept(Token::Kind::kAnd)) {
      auto node = std::make_unique<Node>();
      node->kind = Node::Kind::kAnd;
      node->left = std::move(left);
      node->right = parse_unary();
      if (!node->right) {
        return nullptr;
      }
      left = std::move(node);
    }
    return left;
  }

  std::unique_ptr<Node> parse_unary()
  {
    if (accept(Token::Kind::kNot)) {
      auto node = std::make_unique<Node>();
      node->kind = Node::Kind::kNot;
      node->left = parse_unary();
      return node->left ? std::move(node) : nullptr;
    }
    if (accept(Token::Kind::kLParen)) {
      auto inner = parse_or();
      if (!inner) {
        return nullptr;
      }
      if (!accept(Token::Kind::kRParen)) {
        *error_ = "missing ')' in filter expression";
        return nullptr;
      }
      return inner;
    }
    return parse_predicate();
  }

  std::unique_ptr<Node> parse_predicate()
  {
    auto node = std::make_unique<Node>();
    if (!parse_operand(&node->a)) {
      return nullptr;
    }
    const bool negate = accept(Token::Kind::kNot);
    if (accept(Token::Kind::kBetween)) {
      node->kind = Node::Kind::kBetween;
      node->negate = negate;
      if (!parse_operand(&node->b)) {
        return nullptr;
      }
      if (!accept(Token::Kind::kAnd)) {
        *error_ = "BETWEEN without AND in filter expression";
        return nullptr;
      }
      return parse_operand(&node->c) ? std::move(node) : nullptr;
    }
    if (accept(Token::Kind::kLike)) {
      node->kind = Node::Kind::kLike;
      node->negate = negate;
      return parse_operand(&node->b) ? std::move(node) : nullptr;
    }
    if (negate || peek().kind != Token::Kind::kOp) {
      *error_ = peek().kind == Token::Kind::kMatch ?
        "MATCH is not supported in filter expressions" :
        "expected a comparison in filter expression";
      return nullptr;
    }
    node->kind = Node::Kind::kCompare;
    node->op = next().text;
    return parse_operand(&node->b) ? std::move(node) : nullptr;
  }

  bool parse_operand(Node::Operand * out)
  {
    const Token & t = next();
    switch (t.kind) {
      case Token::Kind::kIdent:
        out->is_field = true;
        return introspection::with_traits(layout_, [&](auto traits, const auto * members) {
          return resolve_path<decltype(traits)>(members, t.text, &out->steps, error_);
        });
      case Token::Kind::kParam:
        {
          const size_t n = std::strtoul(t.text.c_str(), nullptr, 10);
          if (n >= parameters_.size()) {
            *error_ = "filter expression uses %" + t.text + " but has " +
              std::to_string(parameters_.size()) + " parameter(s)";
            return false;
          }
          if (!parse_literal(parameters_[n], &out->constant)) {
            // Not a literal: take the parameter as the string it is.
            out->constant.kind = Value::Kind::kString;
            out->constant.s = parameters_[n];
          }
          return true;
        }
      case Token::Kind::kLiteral:
        if (!parse_literal(t.text, &out->constant)) {
          *error_ = "bad literal '" + t.text + "' in filter expression";
          return false;
        }
        return true;
      default:
        *error_ = t.kind == Token::Kind::kEnd ? std::string("filter expression ends too early") :
                                                "unexpected '" + t.text + "' in filter expression";
        return false;
    }
  }

  const MessageLayout & layout_;
  const std::vector<Token> & tokens_;
  const std::vector<std::string> & parameters_;
  std::string * error_;
  size_t pos_ = 0;
};

bool operand_value(
  const MessageLayout & layout, const Node::Operand & operand, const void * message, Value * out)
{
  if (!operand.is_field) {
    *out = operand.constant;
    return true;
  }
  return introspection::with_traits(layout, [&](auto traits, const auto *) {
    return read_field<decltype(traits)>(operand.steps, message, out);
  });
}

bool evaluate(const MessageLayout & layout, const Node & node, const void * message)
{
  switch (node.kind) {
    case Node::Kind::kAnd:
      return evaluate(layout, *node.left, message) && evaluate(layout, *node.right, message);
    case Node::Kind::kOr:
      return evaluate(layout, *node.left, message) || evaluate(layout, *node.right, message);
    case Node::Kind::kNot: return !evaluate(layout, *node.left, message);
    default: break;
  }
  Value a, b;
  if (!operand_value(layout, node.a, message, &a) || !operand_value(layout, node.b, message, &b)) {
    return false;
  }
  if (node.kind == Node::Kind::kLike) {
    if (a.kind != Value::Kind::kString || b.kind != Value::Kind::kString) {
      return false;
    }
    return like(a.s, b.s) != node.negate;
  }
  if (node.kind == Node::Kind::kBetween) {
    Value c;
    if (!operand_value(layout, node.c, message, &c)) {
      return false;
    }
    const int low = compare(a, b);
    const int high = compare(a, c);
    if (low == 2 || high == 2) {
      return false;
    }
    return (low >= 0 && high <= 0) != node.negate;
  }
  const int c = compare(a, b);
  if (c == 2) {
    return false;
  }
  const std::string & op = node.op;
  if (op == "=" || op == "==") {
    return c == 0;
  }
  if (op == "<>" || op == "!=") {
    return c != 0;
  }
  if (op == "<") {
    return c < 0;
  }
  if (op == "<=") {
    return c <= 0;
  }
  if (op == ">") {
    return c > 0;
  }
  if (op == ">=") {
    return c >= 0;
  }
  return false;
}

}  // namespace

ContentFilter::~ContentFilter() = default;

std::unique_ptr<ContentFilter> ContentFilter::compile(
  const MessageLayout & layout, const std::string & expression,
  const std::vector<std::string> & parameters, std::string * error)
{
  std::string ignored;
  if (error == nullptr) {
    error = &ignored;
  }
  if (layout.members == nullptr) {
    *error = "no message type to filter";
    return nullptr;
  }
  std::vector<Token> tokens;
  if (!lex(expression, &tokens, error)) {
    return nullptr;
  }
  Parser parser(layout, tokens, parameters, error);
  std::unique_ptr<Node> root = parser.parse();
  if (!root) {
    return nullptr;
  }
  std::unique_ptr<ContentFilter> filter(new ContentFilter());
  filter->layout_ = layout;
  filter->root_ = std::move(root);
  return filter;
}

bool ContentFilter::matches(const void * message) const
{
  return evaluate(layout_, *root_, message);
}

}  // namespace rmw_introspect
