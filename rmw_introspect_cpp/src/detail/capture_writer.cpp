// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/capture_writer.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "detail/json_writer.hpp"
#include "detail/qos.hpp"

namespace rmw_introspect
{

namespace
{

// The document is described once (write_document, a template over its writer) and written
// either straight as JSON (JsonWriter) or as a tree (ValueBuilder) that emit_yaml_* prints.

// A minimal ordered document tree, for the YAML output.
struct Value
{
  enum class Kind { Null, Bool, Int, Double, Real, String, Array, Object };
  Kind kind = Kind::Null;
  bool b = false;
  int64_t i = 0;
  double d = 0.0;  // Double: %.3f; Real: append_exact_double
  std::string s;
  std::vector<Value> items;                           // Array
  std::vector<std::pair<std::string, Value>> fields;  // Object
};

// The JsonWriter interface, building a Value tree.
class ValueBuilder
{
public:
  ValueBuilder & key(std::string_view name)
  {
    key_.assign(name.data(), name.size());
    return *this;
  }
  void begin_object() { open(Value::Kind::Object); }
  void end_object() { stack_.pop_back(); }
  void begin_array() { open(Value::Kind::Array); }
  void begin_flat_array() { open(Value::Kind::Array); }
  void end_array() { stack_.pop_back(); }
  void null() { add(Value::Kind::Null); }
  void boolean(bool b) { add(Value::Kind::Bool)->b = b; }
  void integer(int64_t i) { add(Value::Kind::Int)->i = i; }
  void fixed(double d) { add(Value::Kind::Double)->d = d; }
  void real(double d) { add(Value::Kind::Real)->d = d; }
  void string(std::string_view s) { add(Value::Kind::String)->s.assign(s.data(), s.size()); }

  const Value & root() const { return root_; }

private:
  Value * add(Value::Kind kind)
  {
    Value * v = &root_;
    if (!stack_.empty()) {
      Value & top = *stack_.back();
      if (top.kind == Value::Kind::Object) {
        top.fields.emplace_back(key_, Value());
        v = &top.fields.back().second;
      } else {
        top.items.emplace_back();
        v = &top.items.back();
      }
    }
    v->kind = kind;
    return v;
  }
  // The open containers are the last element of their parent, which only grows once they close.
  void open(Value::Kind kind) { stack_.push_back(add(kind)); }

  Value root_;
  std::vector<Value *> stack_;
  std::string key_;
};

void append_scalar(std::string & out, const Value & v)
{
  switch (v.kind) {
    case Value::Kind::Null: out += "null"; break;
    case Value::Kind::Bool: out += v.b ? "true" : "false"; break;
    case Value::Kind::Int: append_integer(out, v.i); break;
    case Value::Kind::Double: append_fixed_double(out, v.d); break;
    case Value::Kind::Real: append_exact_double(out, v.d); break;
    case Value::Kind::String: append_json_string(out, v.s); break;
    default: break;
  }
}

bool is_container(const Value & v)
{
  return v.kind == Value::Kind::Array || v.kind == Value::Kind::Object;
}

void emit_yaml_object(const Value & v, int indent, std::string & out);

void emit_yaml_value_after_key(const Value & v, int indent, std::string & out)
{
  const size_t pad = static_cast<size_t>(indent);
  if (v.kind == Value::Kind::Array) {
    if (v.items.empty()) {
      out += " []\n";
      return;
    }
    out += "\n";
    for (const auto & item : v.items) {
      out.append(pad, ' ');
      out += "- ";
      if (item.kind == Value::Kind::Object && !item.fields.empty()) {
        // first field on the dash line, others indented under it
        const size_t at = out.size();
        emit_yaml_object(item, indent + 2, out);
        out.erase(at, pad + 2);
      } else if (is_container(item)) {
        out += item.kind == Value::Kind::Array ? "[]\n" : "{}\n";
      } else {
        append_scalar(out, item);
        out += "\n";
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
    out += " ";
    append_scalar(out, v);
    out += "\n";
  }
}

void emit_yaml_object(const Value & v, int indent, std::string & out)
{
  for (const auto & field : v.fields) {
    out.append(static_cast<size_t>(indent), ' ');
    out += field.first;
    out += ":";
    emit_yaml_value_after_key(field.second, indent, out);
  }
}

template<typename W>
void optional_string(W & w, const std::string & s)
{
  if (s.empty()) {
    w.null();
  } else {
    w.string(s);
  }
}

// When the program itself destroyed the entity (format_minor 4): its virtual and real age then,
// null for an entity alive at the end or destroyed in the process's teardown.
template<typename W, typename Record>
void write_destruction(W & w, const Record & r)
{
  if (r.destroyed) {
    w.key("destroyed_virtual_ms").fixed(r.destroyed_at.virtual_ms);
    w.key("destroyed_real_ms").fixed(r.destroyed_at.real_ms);
  } else {
    w.key("destroyed_virtual_ms").null();
    w.key("destroyed_real_ms").null();
  }
}

template<typename W>
void write_qos(W & w, const rmw_qos_profile_t & qos)
{
  w.begin_object();
  w.key("history").string(history_to_string(qos.history));
  w.key("depth").integer(static_cast<int64_t>(qos.depth));
  w.key("reliability").string(reliability_to_string(qos.reliability));
  w.key("durability").string(durability_to_string(qos.durability));
  w.key("liveliness").string(liveliness_to_string(qos.liveliness));
  w.key("deadline_ns").integer(duration_to_ns(qos.deadline));
  w.key("lifespan_ns").integer(duration_to_ns(qos.lifespan));
  w.key("liveliness_lease_duration_ns").integer(duration_to_ns(qos.liveliness_lease_duration));
  w.key("avoid_ros_namespace_conventions").boolean(qos.avoid_ros_namespace_conventions);
  w.end_object();
}

template<typename W>
void write_parameter_value(W & w, const ParameterValue & v)
{
  switch (v.type) {
    case kParameterBool: w.boolean(v.bool_value); return;
    case kParameterInteger: w.integer(v.integer_value); return;
    case kParameterDouble: w.real(v.double_value); return;
    case kParameterString: w.string(v.string_value); return;
    case kParameterByteArray:
      w.begin_flat_array();
      for (uint8_t b : v.byte_array_value) {
        w.integer(b);
      }
      break;
    case kParameterBoolArray:
      w.begin_flat_array();
      for (bool b : v.bool_array_value) {
        w.boolean(b);
      }
      break;
    case kParameterIntegerArray:
      w.begin_flat_array();
      for (int64_t i : v.integer_array_value) {
        w.integer(i);
      }
      break;
    case kParameterDoubleArray:
      w.begin_flat_array();
      for (double d : v.double_array_value) {
        w.real(d);
      }
      break;
    case kParameterStringArray:
      w.begin_flat_array();
      for (const auto & s : v.string_array_value) {
        w.string(s);
      }
      break;
    default: w.null(); return;
  }
  w.end_array();
}

template<typename W>
void write_parameter(W & w, const ParameterRecord & p)
{
  w.begin_object();
  w.key("name").string(p.name);
  const char * type = parameter_type_name(p.type());
  if (type != nullptr) {
    w.key("type").string(type);
  } else {
    w.key("type").null();
  }
  write_parameter_value(w.key("value"), p.value);
  w.key("read_only").boolean(p.read_only);
  w.key("dynamic_typing").boolean(p.dynamic_typing);
  w.key("description").string(p.description);
  w.key("additional_constraints").string(p.additional_constraints);
  if (p.has_integer_range) {
    w.key("integer_range").begin_object();
    w.key("from_value").integer(p.integer_range.from_value);
    w.key("to_value").integer(p.integer_range.to_value);
    w.key("step").integer(static_cast<int64_t>(p.integer_range.step));
    w.end_object();
  } else {
    w.key("integer_range").null();
  }
  if (p.has_floating_point_range) {
    w.key("floating_point_range").begin_object();
    w.key("from_value").real(p.floating_point_range.from_value);
    w.key("to_value").real(p.floating_point_range.to_value);
    w.key("step").real(p.floating_point_range.step);
    w.end_object();
  } else {
    w.key("floating_point_range").null();
  }
  optional_string(w.key("declared_in"), p.declared_in);
  w.end_object();
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

template<typename W>
void write_lifecycle(W & w, const LifecycleRecord & lc)
{
  w.begin_object();
  w.key("target").string(lc.target);
  optional_string(w.key("initial_state"), lc.initial_state);
  optional_string(w.key("state"), lc.state);
  w.key("transitions").begin_array();
  for (const auto & t : lc.transitions) {
    w.begin_object();
    w.key("id").integer(t.id);
    w.key("label").string(t.label);
    w.key("result").string(transition_result(t.result));
    if (t.result == LifecycleTransitionRecord::Result::kSuccess) {
      w.key("success").boolean(true);
    } else if (t.result == LifecycleTransitionRecord::Result::kFailure) {
      w.key("success").boolean(false);
    } else {
      w.key("success").null();
    }
    w.end_object();
  }
  w.end_array();
  optional_string(w.key("error"), lc.error);
  w.end_object();
}

// The node's "parameters", "parameters_error" and "lifecycle".
template<typename W>
void write_probe_fields(W & w, const NodeRecord & n)
{
  const NodeProbe * probe = n.probe.get();
  if (probe != nullptr && probe->has_parameters) {
    w.key("parameters").begin_array();
    for (const auto & p : probe->parameters) {
      write_parameter(w, p);
    }
    w.end_array();
  } else {
    w.key("parameters").null();
  }
  if (probe != nullptr) {
    optional_string(w.key("parameters_error"), probe->parameters_error);
  } else {
    w.key("parameters_error").null();
  }
  if (probe != nullptr && probe->has_lifecycle) {
    write_lifecycle(w.key("lifecycle"), probe->lifecycle);
  } else {
    w.key("lifecycle").null();
  }
}

// One entry of the `types` table (its value).
template<typename W>
void write_type(W & w, const TypeDescription & type)
{
  w.begin_object();
  if (type.is_service) {
    w.key("kind").string("service");
    w.key("request").string(type.request);
    w.key("response").string(type.response);
    w.end_object();
    return;
  }
  w.key("kind").string("message");
  w.key("fields").begin_array();
  for (const auto & f : type.fields) {
    w.begin_object();
    w.key("name").string(f.name);
    w.key("type").string(f.type);
    if (f.array != FieldArray::None) {
      w.key("array").string(field_array_to_string(f.array));
      if (f.array != FieldArray::Unbounded) {
        w.key("array_size").integer(static_cast<int64_t>(f.array_size));
      }
    }
    if (f.string_bound > 0) {
      w.key("string_bound").integer(static_cast<int64_t>(f.string_bound));
    }
    w.end_object();
  }
  w.end_array();
  if (type.constants_known) {
    w.key("constants").begin_array();
    for (const auto & c : type.constants) {
      w.begin_object();
      w.key("name").string(c.name);
      w.key("type").string(c.type);
      w.key("value").string(c.value);
      w.end_object();
    }
    w.end_array();
  }
  w.end_object();
}

// The column of a `types` entry's value in the JSON document (document > types > entry):
// the cached texts are rendered for it.
constexpr int kTypeEntryIndent = 4;

void render_type_json(const TypeDescription & type, std::string * out)
{
  JsonWriter w(*out, kTypeEntryIndent);
  write_type(w, type);
}

template<typename W>
void write_component_loads(W & w, const std::vector<ComponentLoadRecord> & loads)
{
  w.begin_array();
  for (const auto & record : loads) {
    w.begin_object();
    w.key("service").string(record.service);
    w.key("plugin").string(record.plugin);
    w.key("node").string(record.node);
    w.key("result").string(component_load_result_name(record.result));
    w.key("full_node_name").string(record.full_node_name);
    optional_string(w.key("error"), record.error);
    w.end_object();
  }
  w.end_array();
}

template<typename W>
void write_stimuli(W & w, const std::vector<StimulusRecord> & stimuli)
{
  w.begin_array();
  for (const auto & record : stimuli) {
    w.begin_object();
    w.key("name").string(record.name);
    w.key("state").string(stimulus_state_name(record.state));
    w.key("targets").begin_array();
    for (const auto & t : record.targets) {
      w.begin_object();
      w.key("kind").string(endpoint_kind_to_string(t.kind));
      w.key("node").string(t.node);
      w.key("type").string(t.type);
      w.key("result").string(stimulus_result_name(t.result));
      optional_string(w.key("error"), t.error);
      w.end_object();
    }
    w.end_array();
    optional_string(w.key("error"), record.error);
    w.end_object();
  }
  w.end_array();
}

// The whole document; `write_types(w)` writes the value of "types".
template<typename W, typename TypesFn>
void write_document(
  W & w, const CaptureHeader & header, const RecorderSnapshot & snapshot, TypesFn && write_types)
{
  w.begin_object();
  w.key("format").string("rmw_introspect_capture");
  w.key("format_version").integer(1);
  w.key("format_minor").integer(4);
  w.key("rmw_implementation").string("rmw_introspect_cpp");
  w.key("pid").integer(header.pid);
  w.key("argv").begin_flat_array();
  for (const auto & arg : header.argv) {
    w.string(arg);
  }
  w.end_array();
  w.key("state").string(header.state);
  w.key("settle_ms").integer(header.settle_ms);
  if (header.has_time_to_settle) {
    w.key("time_to_settle_ms").fixed(header.time_to_settle_ms);
  } else {
    w.key("time_to_settle_ms").null();
  }
  w.key("elapsed_ms").fixed(header.elapsed_ms);
  optional_string(w.key("settled_by"), header.settled_by);
  w.key("ever_waited").boolean(header.ever_waited);
  w.key("activity_calls").integer(static_cast<int64_t>(header.activity_calls));
  w.key("quiescence").begin_object();
  w.key("detect").boolean(header.idle_detect);
  w.key("detected").integer(static_cast<int64_t>(header.idle_settles));
  w.key("window").integer(static_cast<int64_t>(header.window_settles));
  w.key("polls").integer(static_cast<int64_t>(header.polls));
  optional_string(w.key("not_idle"), header.not_idle);
  w.end_object();
  w.key("time").begin_object();
  w.key("horizon_ms").integer(header.horizon_ms);
  w.key("virtual_elapsed_ms").fixed(header.virtual_elapsed_ms);
  w.key("real_elapsed_ms").fixed(header.real_elapsed_ms);
  w.key("jumps").integer(static_cast<int64_t>(header.jumps));
  w.key("warp_ms").fixed(header.warp_ms);
  w.key("horizon_reached").boolean(header.horizon_reached);
  w.key("warp_budget_exhausted").boolean(header.warp_budget_exhausted);
  w.key("warp_stalled").boolean(header.warp_stalled);
  w.key("warp_real_waits").boolean(header.warp_real_waits);
  w.key("warp_real_ms").fixed(header.warp_real_ms);
  w.key("warp_polls").integer(static_cast<int64_t>(header.warp_polls));
  w.key("warp_activity").integer(static_cast<int64_t>(header.warp_activity));
  w.end_object();
  w.key("probe").begin_object();
  w.key("state").string(header.probe_state);
  w.key("parameters").boolean(header.probe_parameters);
  w.key("lifecycle").string(header.probe_lifecycle);
  w.key("answer_timeout_ms").integer(header.answer_timeout_ms);
  w.key("requests").integer(static_cast<int64_t>(header.probe_requests));
  w.key("unanswered").integer(static_cast<int64_t>(header.probe_unanswered));
  w.end_object();
  write_stimuli(w.key("stimuli"), header.stimuli);
  if (!header.component_loads.empty()) {
    write_component_loads(w.key("component_loads"), header.component_loads);
  }
  if (header.has_ended) {
    w.key("ended").begin_object();
    w.key("before_settle").boolean(header.ended_before_settle);
    w.end_object();
  }
  w.key("nodes").begin_array();
  for (const auto & n : snapshot.nodes) {
    w.begin_object();
    w.key("id").integer(static_cast<int64_t>(n.id));
    w.key("seq").integer(static_cast<int64_t>(n.seq));
    w.key("name").string(n.name);
    w.key("namespace").string(n.namespace_);
    w.key("fqn").string(n.fqn);
    w.key("enclave").string(n.enclave);
    w.key("destroyed").boolean(n.destroyed);
    w.key("in_teardown").boolean(n.in_teardown);
    w.key("created_virtual_ms").fixed(n.created.virtual_ms);
    w.key("created_real_ms").fixed(n.created.real_ms);
    write_destruction(w, n);
    write_probe_fields(w, n);
    w.end_object();
  }
  w.end_array();
  w.key("endpoints").begin_array();
  for (const auto & e : snapshot.endpoints) {
    w.begin_object();
    w.key("seq").integer(static_cast<int64_t>(e.seq));
    w.key("kind").string(endpoint_kind_to_string(e.kind));
    w.key("node_id").integer(static_cast<int64_t>(e.node_id));
    w.key("node").string(e.node_fqn);
    w.key("name").string(e.name);
    w.key("type").string(e.type);
    optional_string(w.key("type_hash"), e.type_hash);
    w.key("typesupport").string(e.typesupport);
    write_qos(w.key("qos"), e.qos);
    w.key("destroyed").boolean(e.destroyed);
    w.key("in_teardown").boolean(e.in_teardown);
    w.key("created_virtual_ms").fixed(e.created.virtual_ms);
    w.key("created_real_ms").fixed(e.created.real_ms);
    write_destruction(w, e);
    optional_string(w.key("created_in"), e.created_in);
    w.end_object();
  }
  w.end_array();
  write_types(w.key("types"));
  w.end_object();
}

}  // namespace

CaptureRenderer::CaptureRenderer()
: types_(render_type_json)
{
}

std::string CaptureRenderer::render_json(
  const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  const auto & types = types_.table(snapshot);
  size_t estimate = 4096 + 1024 * (snapshot.nodes.size() + snapshot.endpoints.size());
  for (const auto & entry : types) {
    estimate += entry.name.size() + entry.text->size() + 8;
  }
  std::string out;
  out.reserve(std::max(estimate, last_json_size_ + last_json_size_ / 8));
  JsonWriter w(out);
  write_document(w, header, snapshot, [&types](JsonWriter & tw) {
    tw.begin_object();
    for (const auto & entry : types) {
      tw.key(entry.name);
      assert(tw.value_indent() == kTypeEntryIndent);
      tw.raw(*entry.text);
    }
    tw.end_object();
  });
  out += "\n";
  last_json_size_ = out.size();
  return out;
}

std::string CaptureRenderer::render_yaml(
  const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  ValueBuilder tree;
  write_document(tree, header, snapshot, [&snapshot](ValueBuilder & tw) {
    // Each name once (the first endpoint listing it wins), sorted by name.
    std::map<std::string_view, const TypeDescription *> types;
    for (const auto & e : snapshot.endpoints) {
      if (!e.types) {
        continue;
      }
      for (const auto & type : *e.types) {
        types.emplace(type.name, &type);
      }
    }
    tw.begin_object();
    for (const auto & entry : types) {
      write_type(tw.key(entry.first), *entry.second);
    }
    tw.end_object();
  });
  std::string out = "# rmw_introspect capture (format_version 1, format_minor 4)\n";
  emit_yaml_object(tree.root(), 0, out);
  return out;
}

std::string CaptureRenderer::render(
  CaptureFormat format, const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  return format == CaptureFormat::Yaml ? render_yaml(header, snapshot) :
                                         render_json(header, snapshot);
}

std::string render_capture_json(const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  return CaptureRenderer().render_json(header, snapshot);
}

std::string render_capture_yaml(const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  return CaptureRenderer().render_yaml(header, snapshot);
}

std::string render_capture(
  CaptureFormat format, const CaptureHeader & header, const RecorderSnapshot & snapshot)
{
  return CaptureRenderer().render(format, header, snapshot);
}

bool write_file_atomically(
  const std::string & path, const std::string & content, std::string * error)
{
  // A new file of an unpredictable name, created exclusively (mkostemp): the default output
  // lies in /tmp, where a name derived from the pid could be a symlink planted by another user,
  // which an O_TRUNC open would follow. rename() then replaces `path` itself, never a link's target.
  std::string tmp = path + ".tmp.XXXXXX";
  const int fd = ::mkostemp(tmp.data(), O_CLOEXEC);
  if (fd < 0) {
    if (error) {
      *error = "cannot create a temporary file next to " + path + ": " + std::strerror(errno);
    }
    return false;
  }
  size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      if (error) {
        *error = "cannot write " + tmp + ": " + std::strerror(errno);
      }
      ::close(fd);
      ::unlink(tmp.c_str());
      return false;
    }
    written += static_cast<size_t>(n);
  }
  // mkostemp created it 0600; readable by others (whoever runs the tests) once it is complete
  (void)::fchmod(fd, 0644);
  if (::close(fd) != 0) {
    if (error) {
      *error = "cannot close " + tmp + ": " + std::strerror(errno);
    }
    ::unlink(tmp.c_str());
    return false;
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    if (error) {
      *error = "cannot rename " + tmp + " to " + path + ": " + std::strerror(errno);
    }
    ::unlink(tmp.c_str());
    return false;
  }
  return true;
}

std::vector<std::string> read_process_argv()
{
  std::vector<std::string> argv;
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  if (!in) {
    return argv;
  }
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  size_t start = 0;
  while (start < data.size()) {
    size_t end = data.find('\0', start);
    if (end == std::string::npos) {
      end = data.size();
    }
    argv.push_back(data.substr(start, end - start));
    start = end + 1;
  }
  return argv;
}

}  // namespace rmw_introspect
