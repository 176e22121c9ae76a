// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
//
// Type descriptions: fields from the introspection type supports (C or C++), constants from
// the definition sources the Jazzy type supports carry (`get_type_description_sources_func`).
// Neither introspection type support lists constants, and the REP-2011 TypeDescription holds
// fields only (constants and default values are not part of the type hash either), so the
// `.msg` / `.srv` / `.action` text is the one place a process has them.
#include "detail/type_description.hpp"

#include <dlfcn.h>

#include <cstring>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rosidl_runtime_c/type_description/type_source__struct.h"

#include "detail/introspection.hpp"
#include "detail/message_layout.hpp"

namespace rmw_introspect
{

const char * field_array_to_string(FieldArray array)
{
  switch (array) {
    case FieldArray::Fixed: return "fixed";
    case FieldArray::Bounded: return "bounded";
    case FieldArray::Unbounded: return "unbounded";
    default: return "none";
  }
}

namespace
{

using Sources = rosidl_runtime_c__type_description__TypeSource__Sequence;

std::string trim(const std::string & s)
{
  const size_t begin = s.find_first_not_of(' ');
  if (begin == std::string::npos) {
    return std::string();
  }
  const size_t end = s.find_last_not_of(' ');
  return s.substr(begin, end - begin + 1);
}

std::string primitive_name(uint8_t type_id)
{
  switch (type_id) {
    case rosidl_typesupport_introspection_c__ROS_TYPE_FLOAT: return "float32";
    case rosidl_typesupport_introspection_c__ROS_TYPE_DOUBLE: return "float64";
    case rosidl_typesupport_introspection_c__ROS_TYPE_LONG_DOUBLE: return "long_double";
    case rosidl_typesupport_introspection_c__ROS_TYPE_CHAR: return "char";
    case rosidl_typesupport_introspection_c__ROS_TYPE_WCHAR: return "wchar";
    case rosidl_typesupport_introspection_c__ROS_TYPE_BOOLEAN: return "bool";
    case rosidl_typesupport_introspection_c__ROS_TYPE_OCTET: return "byte";
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT8: return "uint8";
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT8: return "int8";
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT16: return "uint16";
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT16: return "int16";
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT32: return "uint32";
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT32: return "int32";
    case rosidl_typesupport_introspection_c__ROS_TYPE_UINT64: return "uint64";
    case rosidl_typesupport_introspection_c__ROS_TYPE_INT64: return "int64";
    case rosidl_typesupport_introspection_c__ROS_TYPE_STRING: return "string";
    case rosidl_typesupport_introspection_c__ROS_TYPE_WSTRING: return "wstring";
    default: return "?" + std::to_string(static_cast<int>(type_id));
  }
}

// The generated sources count the terminating NUL in `size` (Jazzy's rosidl_generator_c):
// stop at the first NUL.
std::string as_string(const rosidl_runtime_c__String & s)
{
  return s.data != nullptr ? std::string(s.data, strnlen(s.data, s.size)) : std::string();
}

/// "pkg/kind/Name" -> {"pkg", "kind", "Name"}; false for anything else.
bool split_type_name(
  const std::string & name, std::string * pkg, std::string * kind, std::string * leaf)
{
  const size_t first = name.find('/');
  const size_t last = name.rfind('/');
  if (first == std::string::npos || first == last || name.find('/', first + 1) != last) {
    return false;
  }
  *pkg = name.substr(0, first);
  *kind = name.substr(first + 1, last - first - 1);
  *leaf = name.substr(last + 1);
  return !pkg->empty() && !kind->empty() && !leaf->empty();
}

bool ends_with(const std::string & s, const std::string & suffix)
{
  return s.size() > suffix.size() &&
    s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// The sources of `pkg/kind/Name` from the package's rosidl_generator_c library, if the process
/// has it loaded (it does whenever one of the package's type supports is in use): reaches the
/// `.action` text, which no endpoint's own type support carries (an action's goal, result and
/// feedback are "implicit" types of the SendGoal / GetResult / FeedbackMessage supports).
/// The generated function ignores its type support argument (the generated code itself calls
/// the individual source functions with NULL).
bool sources_from_library(const std::string & type_name, const Sources ** out)
{
  std::string pkg, kind, leaf;
  if (!split_type_name(type_name, &pkg, &kind, &leaf)) {
    return false;
  }
  const std::string library = "lib" + pkg + "__rosidl_generator_c.so";
  void * handle = dlopen(library.c_str(), RTLD_LAZY | RTLD_NOLOAD);
  if (handle == nullptr) {
    return false;
  }
  const std::string symbol = pkg + "__" + kind + "__" + leaf + "__get_type_description_sources";
  using SourcesFn = const Sources * (*)(const void *);
  void * sym = dlsym(handle, symbol.c_str());
  const Sources * sources = nullptr;
  if (sym != nullptr) {
    SourcesFn fn;
    static_assert(sizeof(fn) == sizeof(sym), "function and object pointers differ in size");
    std::memcpy(&fn, &sym, sizeof(fn));
    sources = fn(nullptr);
  }
  dlclose(handle);  // NOLOAD took a reference; the library stays loaded by its users
  *out = sources;
  return sources != nullptr;
}

const rosidl_runtime_c__type_description__TypeSource * find_source(
  const Sources * sources, const std::string & type_name)
{
  if (sources == nullptr || sources->data == nullptr) {
    return nullptr;
  }
  for (size_t i = 0; i < sources->size; ++i) {
    if (as_string(sources->data[i].type_name) == type_name) {
      return &sources->data[i];
    }
  }
  return nullptr;
}

/// The definition source of `type_name`: in `sources`, else in its package's library (an
/// "implicit" entry in `sources` is final: the library holds the same).
const rosidl_runtime_c__type_description__TypeSource * find_definition(
  const Sources * sources, const std::string & type_name)
{
  const auto * found = find_source(sources, type_name);
  const Sources * own = nullptr;
  if (found == nullptr && sources_from_library(type_name, &own)) {
    found = find_source(own, type_name);
  }
  return found;
}

// Types rosidl generates for services and actions, which never have constants of their own.
const char * const kGeneratedSuffixes[] = {
  "_SendGoal_Request",   "_SendGoal_Response", "_SendGoal_Event",  "_GetResult_Request",
  "_GetResult_Response", "_GetResult_Event",   "_FeedbackMessage", "_Event",
};

// Parts of a .srv (request, response) and .action (goal, result, feedback) text.
struct Part
{
  const char * kind;
  const char * suffix;
  size_t index;
};
const Part kParts[] = {
  {"srv", "_Request", 0},   {"srv", "_Response", 1},    {"action", "_Goal", 0},
  {"action", "_Result", 1}, {"action", "_Feedback", 2},
};

/// Fill `type.constants` from the type's definition source; `constants_known` when found.
void find_constants(TypeDescription & type, const Sources * sources)
{
  std::string pkg, kind, leaf;
  if (!split_type_name(type.name, &pkg, &kind, &leaf)) {
    return;
  }
  const auto * own = find_definition(sources, type.name);
  if (own != nullptr && as_string(own->encoding) == "msg") {
    type.constants = parse_msg_constants(as_string(own->raw_file_contents));
    type.constants_known = true;
    return;
  }
  if (own != nullptr && as_string(own->encoding) != "implicit") {
    return;  // "idl", "dynamic": not read (constants unknown)
  }
  if (kind == "srv" || kind == "action") {
    for (const char * suffix : kGeneratedSuffixes) {
      if (ends_with(leaf, suffix)) {
        type.constants_known = true;  // generated: no constants
        return;
      }
    }
  }
  for (const Part & part : kParts) {
    if (kind != part.kind || !ends_with(leaf, part.suffix)) {
      continue;
    }
    const std::string parent =
      pkg + "/" + kind + "/" + leaf.substr(0, leaf.size() - std::strlen(part.suffix));
    const auto * source = find_definition(sources, parent);
    if (source != nullptr && as_string(source->encoding) == part.kind) {
      type.constants =
        parse_msg_constants(definition_part(as_string(source->raw_file_contents), part.index));
      type.constants_known = true;
    }
    return;
  }
}

const Sources * sources_of(const rosidl_message_type_support_t * handle)
{
  if (handle == nullptr || handle->get_type_description_sources_func == nullptr) {
    return nullptr;
  }
  return handle->get_type_description_sources_func(handle);
}

template<typename T>
class Walker
{
public:
  using MessageMembers = typename T::Members;
  using ServiceMembers = typename T::ServiceMembers;

  /// Describe a message and, depth first, the types of its fields; returns its name.
  std::string message(const MessageMembers * members, const Sources * sources)
  {
    if (members == nullptr) {
      return "?";
    }
    const std::string name = introspection::type_name_of<T>(members);
    if (!seen_.insert(name).second) {
      return name;
    }
    const size_t index = out_.size();
    out_.emplace_back();
    TypeDescription type;
    type.name = name;
    find_constants(type, sources);
    Nested nested;
    for (uint32_t i = 0; members->members_ != nullptr && i < members->member_count_; ++i) {
      const auto & member = members->members_[i];
      FieldDescription field;
      field.name = member.name_ != nullptr ? member.name_ : "";
      introspection::dispatch<T>(member, nullptr, FieldType{&field, &nested});
      field.array = introspection::array_of<T>(member);
      field.array_size = field.array == FieldArray::Fixed || field.array == FieldArray::Bounded ?
        member.array_size_ :
        0u;
      type.fields.push_back(std::move(field));
    }
    out_[index] = std::move(type);
    for (const auto & n : nested) {
      message(n.first, n.second);
    }
    return name;
  }

  void service(const rosidl_service_type_support_t * handle)
  {
    const auto * members = static_cast<const ServiceMembers *>(handle->data);
    if (members == nullptr) {
      return;
    }
    const Sources * sources = handle->get_type_description_sources_func != nullptr ?
      handle->get_type_description_sources_func(handle) :
      nullptr;
    TypeDescription type;
    type.name = type_name_from_namespace(members->service_namespace_, members->service_name_);
    type.is_service = true;
    type.constants_known = true;  // a service type has none; its messages have their own
    seen_.insert(type.name);
    out_.push_back(type);
    const size_t index = out_.size() - 1;
    const std::string request = message(members->request_members_, sources);
    const std::string response = message(members->response_members_, sources);
    out_[index].request = request;
    out_[index].response = response;
  }

  TypeDescriptionsPtr result() { return std::make_shared<const TypeDescriptions>(std::move(out_)); }

private:
  using Member = typename T::Member;
  using Nested = std::vector<std::pair<const MessageMembers *, const Sources *>>;

  // The `.msg` spelling of a field's (element) type, and nested types to describe next: the
  // visitor of introspection::dispatch.
  struct FieldType
  {
    FieldDescription * field;
    Nested * nested;

    void primitive(const Member & m, std::nullptr_t, size_t)
    {
      field->type = primitive_name(m.type_id_);
    }
    void string(const Member & m, std::nullptr_t)
    {
      field->type = "string";
      field->string_bound = m.string_upper_bound_;
    }
    void wstring(const Member & m, std::nullptr_t)
    {
      field->type = "wstring";
      field->string_bound = m.string_upper_bound_;
    }
    void message(const Member & m, std::nullptr_t, const MessageMembers * members)
    {
      field->type = members != nullptr ? introspection::type_name_of<T>(members) : std::string("?");
      if (members != nullptr) {
        nested->emplace_back(
          members, sources_of(lookup_message_type_support(m.members_, T::identifier())));
      }
    }
    void unknown(const Member & m, std::nullptr_t) { field->type = primitive_name(m.type_id_); }
  };

  TypeDescriptions out_;
  std::set<std::string> seen_;
};

}  // namespace

TypeDescriptionsPtr describe_message_type(
  const rosidl_message_type_support_t * introspection, bool is_cpp)
{
  if (introspection == nullptr || introspection->data == nullptr) {
    return nullptr;
  }
  const Sources * sources = sources_of(introspection);
  if (is_cpp) {
    Walker<introspection::Cpp> walker;
    walker.message(static_cast<const introspection::Cpp::Members *>(introspection->data), sources);
    return walker.result();
  }
  Walker<introspection::C> walker;
  walker.message(static_cast<const introspection::C::Members *>(introspection->data), sources);
  return walker.result();
}

TypeDescriptionsPtr describe_service_type(
  const rosidl_service_type_support_t * introspection, bool is_cpp)
{
  if (introspection == nullptr || introspection->data == nullptr) {
    return nullptr;
  }
  if (is_cpp) {
    Walker<introspection::Cpp> walker;
    walker.service(introspection);
    return walker.result();
  }
  Walker<introspection::C> walker;
  walker.service(introspection);
  return walker.result();
}

std::vector<ConstantDescription> parse_msg_constants(const std::string & text)
{
  std::vector<ConstantDescription> constants;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    for (char & c : line) {
      if (c == '\t' || c == '\r') {
        c = ' ';
      }
    }
    const size_t comment = line.find('#');
    if (comment != std::string::npos) {
      line.erase(comment);
    }
    line = trim(line);
    const size_t space = line.find(' ');
    if (line.empty() || space == std::string::npos) {
      continue;
    }
    std::string type = line.substr(0, space);
    const std::string rest = trim(line.substr(space + 1));
    const size_t equals = rest.find('=');
    if (equals == std::string::npos) {
      continue;  // a field
    }
    const std::string name = trim(rest.substr(0, equals));
    if (name.empty() || name.find(' ') != std::string::npos) {
      continue;  // not a constant rosidl would accept
    }
    if (type == "char") {
      type = "uint8";  // rosidl maps a .msg char to uint8, fields and constants alike
    }
    constants.push_back({name, type, trim(rest.substr(equals + 1))});
  }
  return constants;
}

std::string definition_part(const std::string & text, size_t index)
{
  std::istringstream in(text);
  std::string line;
  std::string part;
  size_t current = 0;
  while (std::getline(in, line)) {
    std::string bare = line;
    while (!bare.empty() && (bare.back() == ' ' || bare.back() == '\t' || bare.back() == '\r')) {
      bare.pop_back();
    }
    if (bare == "---") {
      ++current;
      continue;
    }
    if (current == index) {
      part += line;
      part += '\n';
    }
  }
  return part;
}

}  // namespace rmw_introspect
