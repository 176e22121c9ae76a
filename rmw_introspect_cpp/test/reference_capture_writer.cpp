// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The capture renderer as it was before JSON was streamed and the types cached (a Value tree
// built per capture, then printed), kept verbatim as the reference the new output must equal
// byte for byte. Test code only.

#include "reference_capture_writer.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "detail/qos.hpp"

namespace rmwi_reference
{

using namespace rmw_introspect;  // NOLINT(build/namespaces): the code below, unchanged

namespace
{

// A minimal ordered document tree, emitted as JSON or YAML.
struct Value
{
  enum class Kind { Null, Bool, Int, Double, Real, String, Array, Object };
  Kind kind = Kind::Null;
  bool b = false;
  int64_t i = 0;
  double d = 0.0;
  std::string s;
  std::vector<Value> items;                           // Array
  std::vector<std::pair<std::string, Value>> fields;  // Object

  static Value null() { return Value(); }
  static Value boolean(bool v)
  {
    Value x;
    x.kind = Kind::Bool;
    x.b = v;
    return x;
  }
  static Value integer(int64_t v)
  {
    Value x;
    x.kind = Kind::Int;
    x.i = v;
    return x;
  }
  static Value number(double v)
  {
    Value x;
    x.kind = Kind::Double;
    x.d = v;
    return x;
  }
  /// A double written exactly (shortest round trip; a JSON number with a '.' or an exponent;
  /// NaN and infinities as the strings "nan", "inf", "-inf").
  static Value real(double v)
  {
    Value x;
    x.kind = Kind::Real;
    x.d = v;
    return x;
  }
  static Value string(std::string v)
  {
    Value x;
    x.kind = Kind::String;
    x.s = std::move(v);
    return x;
  }
  static Value array()
  {
    Value x;
    x.kind = Kind::Array;
    return x;
  }
  static Value object()
  {
    Value x;
    x.kind = Kind::Object;
    return x;
  }
  Value & add(std::string key, Value v)
  {
    fields.emplace_back(std::move(key), std::move(v));
    return *this;
  }
  Value & push(Value v)
  {
    items.push_back(std::move(v));
    return *this;
  }
};

// Quote a string for JSON (also a valid YAML double-quoted scalar). Invalid UTF-8 bytes
// become U+FFFD so that the document always decodes.
std::string quote(const std::string & in)
{
  std::string out;
  out.reserve(in.size() + 2);
  out.push_back('"');
  const auto * p = reinterpret_cast<const unsigned char *>(in.data());
  const size_t n = in.size();
  for (size_t k = 0; k < n;) {
    const unsigned char c = p[k];
    if (c == '"') {
      out += "\\\"";
      ++k;
    } else if (c == '\\') {
      out += "\\\\";
      ++k;
    } else if (c == '\n') {
      out += "\\n";
      ++k;
    } else if (c == '\t') {
      out += "\\t";
      ++k;
    } else if (c == '\r') {
      out += "\\r";
      ++k;
    } else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      snprintf(buf, sizeof(buf), "\\u%04x", c);
      out += buf;
      ++k;
    } else if (c < 0x80) {
      out.push_back(static_cast<char>(c));
      ++k;
    } else {
      size_t len = 0;
      if ((c & 0xE0) == 0xC0 && c >= 0xC2) {
        len = 2;
      } else if ((c & 0xF0) == 0xE0) {
        len = 3;
      } else if ((c & 0xF8) == 0xF0 && c <= 0xF4) {
        len = 4;
      }
      bool ok = len != 0 && k + len <= n;
      for (size_t j = 1; ok && j < len; ++j) {
        ok = (p[k + j] & 0xC0) == 0x80;
      }
      if (ok) {
        out.append(reinterpret_cast<const char *>(p + k), len);
        k += len;
      } else {
        out += "\\ufffd";
        ++k;
      }
    }
  }
  out.push_back('"');
  return out;
}

std::string exact_double(double d)
{
  if (std::isnan(d)) {
    return "\"nan\"";
  }
  if (std::isinf(d)) {
    return d > 0 ? "\"inf\"" : "\"-inf\"";
  }
  char buf[64];
  for (int precision = 15; precision <= 17; ++precision) {
    snprintf(buf, sizeof(buf), "%.*g", precision, d);
    if (std::strtod(buf, nullptr) == d) {
      break;
    }
  }
  std::string out(buf);
  if (out.find_first_of(".e") == std::string::npos) {
    out += ".0";  // stays a floating point number for the reader
  }
  return out;
}

std::string scalar(const Value & v)
{
  char buf[64];
  switch (v.kind) {
    case Value::Kind::Null: return "null";
    case Value::Kind::Bool: return v.b ? "true" : "false";
    case Value::Kind::Int: snprintf(buf, sizeof(buf), "%" PRId64, v.i); return buf;
    case Value::Kind::Double: snprintf(buf, sizeof(buf), "%.3f", v.d); return buf;
    case Value::Kind::Real: return exact_double(v.d);
    case Value::Kind::String: return quote(v.s);
    default: return "";
  }
}

bool is_container(const Value & v)
{
  return v.kind == Value::Kind::Array || v.kind == Value::Kind::Object;
}

void emit_json(const Value & v, int indent, std::string & out)
{
  const std::string pad(static_cast<size_t>(indent + 2), ' ');
  const std::string end_pad(static_cast<size_t>(indent), ' ');
  if (v.kind == Value::Kind::Array) {
    if (v.items.empty()) {
      out += "[]";
      return;
    }
    // Arrays of scalars stay on one line (argv).
    bool flat = true;
    for (const auto & item : v.items) {
      flat = flat && !is_container(item);
    }
    out += flat ? "[" : "[\n";
    for (size_t k = 0; k < v.items.size(); ++k) {
      if (!flat) {
        out += pad;
      }
      emit_json(v.items[k], indent + 2, out);
      if (k + 1 < v.items.size()) {
        out += flat ? ", " : ",\n";
      }
    }
    out += flat ? "]" : "\n" + end_pad + "]";
  } else if (v.kind == Value::Kind::Object) {
    if (v.fields.empty()) {
      out += "{}";
      return;
    }
    out += "{\n";
    for (size_t k = 0; k < v.fields.size(); ++k) {
      out += pad + quote(v.fields[k].first) + ": ";
      emit_json(v.fields[k].second, indent + 2, out);
      if (k + 1 < v.fields.size()) {
        out += ",";
      }
      out += "\n";
    }
    out += end_pad + "}";
  } else {
    out += scalar(v);
  }
}

void emit_yaml_object(const Value & v, int indent, std::string & out);

void emit_yaml_value_after_key(const Value & v, int indent, std::string & out)
{
  if (v.kind == Value::Kind::Array) {
    if (v.items.empty()) {
      out += " []\n";
      return;
    }
    out += "\n";
    const std::string pad(static_cast<size_t>(indent), ' ');
    for (const auto & item : v.items) {
      if (item.kind == Value::Kind::Object && !item.fields.empty()) {
        out += pad + "- ";
        // first field on the dash line, others indented under it
        std::string nested;
        emit_yaml_object(item, indent + 2, nested);
        out += nested.substr(static_cast<size_t>(indent + 2));
      } else if (is_container(item)) {
        out += pad + "- " + (item.kind == Value::Kind::Array ? "[]" : "{}") + "\n";
      } else {
        out += pad + "- " + scalar(item) + "\n";
      }
    }
  } else if (v.kind == Value::Kind::Object) {
    if (v.fields.empty()) {
      out += " {}\n";
      return;
    }
    out += "\n";
    emit_yaml_object(v, indent + 2, out);
  } else {
    out += " " + scalar(v) + "\n";
  }
}

void emit_yaml_object(const Value & v, int indent, std::string & out)
{
  const std::string pad(static_cast<size_t>(indent), ' ');
  for (const auto & field : v.fields) {
    out += pad + field.first + ":";
    emit_yaml_value_after_key(field.second, indent, out);
  }
}

Value qos_value(const rmw_qos_profile_t & qos)
{
  Value v = Value::object();
  v.add("history", Value::string(history_to_string(qos.history)));
  v.add("depth", Value::integer(static_cast<int64_t>(qos.depth)));
  v.add("reliability", Value::string(reliability_to_string(qos.reliability)));
  v.add("durability", Value::string(durability_to_string(qos.durability)));
  v.add("liveliness", Value::string(liveliness_to_string(qos.liveliness)));
  v.add("deadline_ns", Value::integer(duration_to_ns(qos.deadline)));
  v.add("lifespan_ns", Value::integer(duration_to_ns(qos.lifespan)));
  v.add(
    "liveliness_lease_duration_ns", Value::integer(duration_to_ns(qos.liveliness_lease_duration)));
  v.add("avoid_ros_namespace_conventions", Value::boolean(qos.avoid_ros_namespace_conventions));
  return v;
}

Value optional_string(const std::string & s)
{
  return s.empty() ? Value::null() : Value::string(s);
}

Value parameter_value(const ParameterValue & v)
{
  Value array = Value::array();
  switch (v.type) {
    case kParameterBool: return Value::boolean(v.bool_value);
    case kParameterInteger: return Value::integer(v.integer_value);
    case kParameterDouble: return Value::real(v.double_value);
    case kParameterString: return Value::string(v.string_value);
    case kParameterByteArray:
      for (uint8_t b : v.byte_array_value) {
        array.push(Value::integer(b));
      }
      return array;
    case kParameterBoolArray:
      for (bool b : v.bool_array_value) {
        array.push(Value::boolean(b));
      }
      return array;
    case kParameterIntegerArray:
      for (int64_t i : v.integer_array_value) {
        array.push(Value::integer(i));
      }
      return array;
    case kParameterDoubleArray:
      for (double d : v.double_array_value) {
        array.push(Value::real(d));
      }
      return array;
    case kParameterStringArray:
      for (const auto & s : v.string_array_value) {
        array.push(Value::string(s));
      }
      return array;
    default: return Value::null();
  }
}

Value parameter(const ParameterRecord & p)
{
  Value v = Value::object();
  v.add("name", Value::string(p.name));
  const char * type = parameter_type_name(p.type());
  v.add("type", type != nullptr ? Value::string(type) : Value::null());
  v.add("value", parameter_value(p.value));
  v.add("read_only", Value::boolean(p.read_only));
  v.add("dynamic_typing", Value::boolean(p.dynamic_typing));
  v.add("description", Value::string(p.description));
  v.add("additional_constraints", Value::string(p.additional_constraints));
  if (p.has_integer_range) {
    Value range = Value::object();
    range.add("from_value", Value::integer(p.integer_range.from_value));
    range.add("to_value", Value::integer(p.integer_range.to_value));
    range.add("step", Value::integer(static_cast<int64_t>(p.integer_range.step)));
    v.add("integer_range", std::move(range));
  } else {
    v.add("integer_range", Value::null());
  }
  if (p.has_floating_point_range) {
    Value range = Value::object();
    range.add("from_value", Value::real(p.floating_point_range.from_value));
    range.add("to_value", Value::real(p.floating_point_range.to_value));
    range.add("step", Value::real(p.floating_point_range.step));
    v.add("floating_point_range", std::move(range));
  } else {
    v.add("floating_point_range", Value::null());
  }
  v.add("declared_in", optional_string(p.declared_in));
  return v;
}

const char * transition_result(LifecycleTransitionRecord::Result result)
{
  switch (result) {
    case LifecycleTransitionRecord::Result::kSuccess: return "success";
    case LifecycleTransitionRecord::Result::kFailure: return "failure";
    case LifecycleTransitionRecord::Result::kNoAnswer: return "no_answer";
    case LifecycleTransitionRecord::Result::kPending: return "pending";
  }
  return "pending";
}

Value lifecycle(const LifecycleRecord & lc)
{
  Value v = Value::object();
  v.add("target", Value::string(lc.target));
  v.add("initial_state", optional_string(lc.initial_state));
  v.add("state", optional_string(lc.state));
  Value transitions = Value::array();
  for (const auto & t : lc.transitions) {
    Value tv = Value::object();
    tv.add("id", Value::integer(t.id));
    tv.add("label", Value::string(t.label));
    tv.add("result", Value::string(transition_result(t.result)));
    tv.add(
      "success",
      t.result == LifecycleTransitionRecord::Result::kSuccess   ? Value::boolean(true) :
        t.result == LifecycleTransitionRecord::Result::kFailure ? Value::boolean(false) :
                                                                  Value::null());
    transitions.push(std::move(tv));
  }
  v.add("transitions", std::move(transitions));
  v.add("error", optional_string(lc.error));
  return v;
}

// The node's "parameters", "parameters_error" and "lifecycle".
void add_probe_fields(const NodeRecord & n, Value & node)
{
  const NodeProbe * probe = n.probe.get();
  if (probe != nullptr && probe->has_parameters) {
    Value parameters = Value::array();
    for (const auto & p : probe->parameters) {
      parameters.push(parameter(p));
    }
    node.add("parameters", std::move(parameters));
  } else {
    node.add("parameters", Value::null());
  }
  node.add(
    "parameters_error",
    probe != nullptr ? optional_string(probe->parameters_error) : Value::null());
  node.add(
    "lifecycle",
    probe != nullptr && probe->has_lifecycle ? lifecycle(probe->lifecycle) : Value::null());
}

Value type_value(const TypeDescription & type)
{
  Value v = Value::object();
  if (type.is_service) {
    v.add("kind", Value::string("service"));
    v.add("request", Value::string(type.request));
    v.add("response", Value::string(type.response));
    return v;
  }
  v.add("kind", Value::string("message"));
  Value fields = Value::array();
  for (const auto & f : type.fields) {
    Value field = Value::object();
    field.add("name", Value::string(f.name));
    field.add("type", Value::string(f.type));
    if (f.array != FieldArray::None) {
      field.add("array", Value::string(field_array_to_string(f.array)));
      if (f.array != FieldArray::Unbounded) {
        field.add("array_size", Value::integer(static_cast<int64_t>(f.array_size)));
      }
    }
    if (f.string_bound > 0) {
      field.add("string_bound", Value::integer(static_cast<int64_t>(f.string_bound)));
    }
    fields.push(std::move(field));
  }
  v.add("fields", std::move(fields));
  if (type.constants_known) {
    Value constants = Value::array();
    for (const auto & c : type.constants) {
      Value constant = Value::object();
      constant.add("name", Value::string(c.name));
      constant.add("type", Value::string(c.type));
      constant.add("value", Value::string(c.value));
      constants.push(std::move(constant));
    }
    v.add("constants", std::move(constants));
  }
  return v;
}

// The `types` table: every type the endpoints refer to, nested ones included, each once,
// by name.
Value types_value(const RecorderSnapshot & snapshot)
{
  std::map<std::string, const TypeDescription *> types;
  for (const auto & e : snapshot.endpoints) {
    if (!e.types) {
      continue;
    }
    for (const auto & type : *e.types) {
      types.emplace(type.name, &type);
    }
  }
  Value table = Value::object();
  for (const auto & entry : types) {
    table.add(entry.first, type_value(*entry.second));
  }
  return table;
}

Value stimuli_value(const std::vector<StimulusRecord> & stimuli)
{
  Value list = Value::array();
  for (const auto & record : stimuli) {
    Value v = Value::object();
    v.add("name", Value::string(record.name));
    v.add("state", Value::string(stimulus_state_name(record.state)));
    Value targets = Value::array();
    for (const auto & t : record.targets) {
      Value tv = Value::object();
      tv.add("kind", Value::string(endpoint_kind_to_string(t.kind)));
      tv.add("node", Value::string(t.node));
      tv.add("type", Value::string(t.type));
      tv.add("result", Value::string(stimulus_result_name(t.result)));
      tv.add("error", optional_string(t.error));
      targets.push(std::move(tv));
    }
    v.add("targets", std::move(targets));
    v.add("error", optional_string(record.error));
    list.push(std::move(v));
  }
  return list;
}

Value build_document(const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  Value doc = Value::object();
  doc.add("format", Value::string("rmw_introspect_capture"));
  doc.add("format_version", Value::integer(1));
  doc.add("format_minor", Value::integer(4));
  doc.add("rmw_implementation", Value::string("rmw_introspect_cpp"));
  doc.add("pid", Value::integer(header.pid));
  Value argv = Value::array();
  for (const auto & arg : header.argv) {
    argv.push(Value::string(arg));
  }
  doc.add("argv", std::move(argv));
  doc.add("state", Value::string(header.state));
  doc.add("settle_ms", Value::integer(header.settle_ms));
  doc.add(
    "time_to_settle_ms",
    header.has_time_to_settle ? Value::number(header.time_to_settle_ms) : Value::null());
  doc.add("elapsed_ms", Value::number(header.elapsed_ms));
  doc.add(
    "settled_by", header.settled_by.empty() ? Value::null() : Value::string(header.settled_by));
  doc.add("ever_waited", Value::boolean(header.ever_waited));
  doc.add("activity_calls", Value::integer(static_cast<int64_t>(header.activity_calls)));
  Value quiescence = Value::object();
  quiescence.add("detect", Value::boolean(header.idle_detect));
  quiescence.add("detected", Value::integer(static_cast<int64_t>(header.idle_settles)));
  quiescence.add("window", Value::integer(static_cast<int64_t>(header.window_settles)));
  quiescence.add("polls", Value::integer(static_cast<int64_t>(header.polls)));
  quiescence.add(
    "not_idle", header.not_idle.empty() ? Value::null() : Value::string(header.not_idle));
  doc.add("quiescence", std::move(quiescence));
  Value time = Value::object();
  time.add("horizon_ms", Value::integer(header.horizon_ms));
  time.add("virtual_elapsed_ms", Value::number(header.virtual_elapsed_ms));
  time.add("real_elapsed_ms", Value::number(header.real_elapsed_ms));
  time.add("jumps", Value::integer(static_cast<int64_t>(header.jumps)));
  time.add("warp_ms", Value::number(header.warp_ms));
  time.add("horizon_reached", Value::boolean(header.horizon_reached));
  time.add("warp_budget_exhausted", Value::boolean(header.warp_budget_exhausted));
  time.add("warp_stalled", Value::boolean(header.warp_stalled));
  time.add("warp_real_waits", Value::boolean(header.warp_real_waits));
  time.add("warp_real_ms", Value::number(header.warp_real_ms));
  time.add("warp_polls", Value::integer(static_cast<int64_t>(header.warp_polls)));
  time.add("warp_activity", Value::integer(static_cast<int64_t>(header.warp_activity)));
  doc.add("time", std::move(time));
  Value probe = Value::object();
  probe.add("state", Value::string(header.probe_state));
  probe.add("parameters", Value::boolean(header.probe_parameters));
  probe.add("lifecycle", Value::string(header.probe_lifecycle));
  probe.add("answer_timeout_ms", Value::integer(header.answer_timeout_ms));
  probe.add("requests", Value::integer(static_cast<int64_t>(header.probe_requests)));
  probe.add("unanswered", Value::integer(static_cast<int64_t>(header.probe_unanswered)));
  doc.add("probe", std::move(probe));
  doc.add("stimuli", stimuli_value(header.stimuli));
  if (header.has_ended) {
    Value ended = Value::object();
    ended.add("before_settle", Value::boolean(header.ended_before_settle));
    doc.add("ended", std::move(ended));
  }
  Value nodes = Value::array();
  for (const auto & n : snapshot.nodes) {
    Value node = Value::object();
    node.add("id", Value::integer(static_cast<int64_t>(n.id)));
    node.add("seq", Value::integer(static_cast<int64_t>(n.seq)));
    node.add("name", Value::string(n.name));
    node.add("namespace", Value::string(n.namespace_));
    node.add("fqn", Value::string(n.fqn));
    node.add("enclave", Value::string(n.enclave));
    node.add("destroyed", Value::boolean(n.destroyed));
    node.add("in_teardown", Value::boolean(n.in_teardown));
    node.add("created_virtual_ms", Value::number(n.created.virtual_ms));
    node.add("created_real_ms", Value::number(n.created.real_ms));
    node.add(
      "destroyed_virtual_ms",
      n.destroyed ? Value::number(n.destroyed_at.virtual_ms) : Value::null());
    node.add(
      "destroyed_real_ms", n.destroyed ? Value::number(n.destroyed_at.real_ms) : Value::null());
    add_probe_fields(n, node);
    nodes.push(std::move(node));
  }
  doc.add("nodes", std::move(nodes));
  Value endpoints = Value::array();
  for (const auto & e : snapshot.endpoints) {
    Value ep = Value::object();
    ep.add("seq", Value::integer(static_cast<int64_t>(e.seq)));
    ep.add("kind", Value::string(endpoint_kind_to_string(e.kind)));
    ep.add("node_id", Value::integer(static_cast<int64_t>(e.node_id)));
    ep.add("node", Value::string(e.node_fqn));
    ep.add("name", Value::string(e.name));
    ep.add("type", Value::string(e.type));
    ep.add("type_hash", e.type_hash.empty() ? Value::null() : Value::string(e.type_hash));
    ep.add("typesupport", Value::string(e.typesupport));
    ep.add("qos", qos_value(e.qos));
    ep.add("destroyed", Value::boolean(e.destroyed));
    ep.add("in_teardown", Value::boolean(e.in_teardown));
    ep.add("created_virtual_ms", Value::number(e.created.virtual_ms));
    ep.add("created_real_ms", Value::number(e.created.real_ms));
    ep.add(
      "destroyed_virtual_ms",
      e.destroyed ? Value::number(e.destroyed_at.virtual_ms) : Value::null());
    ep.add(
      "destroyed_real_ms", e.destroyed ? Value::number(e.destroyed_at.real_ms) : Value::null());
    ep.add("created_in", optional_string(e.created_in));
    endpoints.push(std::move(ep));
  }
  doc.add("endpoints", std::move(endpoints));
  doc.add("types", types_value(snapshot));
  return doc;
}

}  // namespace

std::string quote_string(const std::string & in)
{
  return quote(in);
}

std::string exact_double_text(double d)
{
  return exact_double(d);
}

std::string render_capture_json(const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  std::string out;
  emit_json(build_document(header, snapshot), 0, out);
  out += "\n";
  return out;
}

std::string render_capture_yaml(const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  std::string out = "# rmw_introspect capture (format_version 1, format_minor 4)\n";
  emit_yaml_object(build_document(header, snapshot), 0, out);
  return out;
}

}  // namespace rmwi_reference
