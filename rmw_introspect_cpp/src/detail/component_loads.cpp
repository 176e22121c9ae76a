// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/component_loads.hpp"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace rmw_introspect
{
namespace
{

std::string unescape(const std::string & field)
{
  std::string out;
  for (size_t i = 0; i < field.size(); ++i) {
    if (field[i] == '\\' && i + 1 < field.size()) {
      const char c = field[++i];
      out += c == 't' ? '\t' : c == 'n' ? '\n' : c;
    } else {
      out += field[i];
    }
  }
  return out;
}

std::vector<std::string> split_fields(const std::string & line)
{
  std::vector<std::string> fields;
  size_t start = 0;
  while (true) {
    const size_t tab = line.find('\t', start);
    fields.push_back(
      unescape(line.substr(start, tab == std::string::npos ? std::string::npos : tab - start)));
    if (tab == std::string::npos) {
      return fields;
    }
    start = tab + 1;
  }
}

bool parse_bool(const std::string & text, DynValue * out)
{
  if (text != "true" && text != "false") {
    return false;
  }
  *out = DynValue::boolean(text == "true");
  return true;
}

bool parse_int(const std::string & text, DynValue * out)
{
  char * end = nullptr;
  errno = 0;
  const long long value = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0) {
    return false;
  }
  *out = DynValue::integer(value);
  return true;
}

bool parse_double(const std::string & text, DynValue * out)
{
  char * end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') {
    return false;
  }
  *out = DynValue::real(value);
  return true;
}

/// rcl_interfaces/msg/Parameter from `name`, TYPE and its VALUE fields; false if unreadable.
bool parameter_value(const std::vector<std::string> & f, DynValue * out)
{
  if (f.size() < 3) {
    return false;
  }
  DynValue type;
  if (!parse_int(f[2], &type) || type.i < 1 || type.i > 9 || type.i == 5) {
    return false;
  }
  static const char * const kScalar[] = {
    "", "bool_value", "integer_value", "double_value", "string_value"};
  static const char * const kArray[] = {
    "",
    "",
    "",
    "",
    "",
    "",
    "bool_array_value",
    "integer_array_value",
    "double_array_value",
    "string_array_value"};
  const int64_t kind = type.i;
  const int64_t item_kind = kind <= 4 ? kind : kind - 5;  // 6..9 -> 1..4
  std::vector<DynValue> items;
  for (size_t i = 3; i < f.size(); ++i) {
    DynValue item;
    const bool ok = item_kind == 1 ? parse_bool(f[i], &item) :
      item_kind == 2               ? parse_int(f[i], &item) :
      item_kind == 3               ? parse_double(f[i], &item) :
                                     (item = DynValue::string(f[i]), true);
    if (!ok) {
      return false;
    }
    items.push_back(std::move(item));
  }
  if (kind <= 4 && items.size() != 1) {
    return false;
  }
  DynValue value = DynValue::structure();
  value.set("type", DynValue::uinteger(static_cast<uint64_t>(kind)));
  if (kind <= 4) {
    value.set(kScalar[kind], std::move(items[0]));
  } else {
    value.set(kArray[kind], DynValue::sequence(std::move(items)));
  }
  *out = DynValue::structure();
  out->set("name", DynValue::string(f[1]));
  out->set("value", std::move(value));
  return true;
}

}  // namespace

std::vector<ComponentLoad> parse_component_loads(
  const std::string & text, std::vector<std::string> * warnings)
{
  std::vector<ComponentLoad> loads;
  std::istringstream lines(text);
  std::string line;
  size_t number = 0;
  bool open = false;
  bool broken = false;
  ComponentLoad current;
  std::vector<DynValue> remaps, parameters, extras;
  auto warn = [&](const std::string & why) {
    warnings->push_back("RMW_INTROSPECT_LOAD_NODES line " + std::to_string(number) + ": " + why);
    broken = true;
  };
  while (std::getline(lines, line)) {
    ++number;
    if (line.empty() || line[0] == '#') {
      continue;
    }
    const std::vector<std::string> f = split_fields(line);
    const std::string & key = f[0];
    if (key == "load") {
      if (open) {
        warn("a request without `end` before it");
      }
      open = true;
      broken = f.size() != 2;
      if (broken) {
        warn("`load` takes one field, the service");
      }
      current = ComponentLoad();
      current.service = f.size() > 1 ? f[1] : "";
      current.request = DynValue::structure();
      remaps.clear();
      parameters.clear();
      extras.clear();
    } else if (!open) {
      warn("`" + key + "` outside a request (`load` ... `end`)");
    } else if (key == "end") {
      open = false;
      if (broken) {
        continue;
      }
      current.request.set("remap_rules", DynValue::sequence(remaps));
      current.request.set("parameters", DynValue::sequence(parameters));
      current.request.set("extra_arguments", DynValue::sequence(extras));
      loads.push_back(current);
    } else if ((key == "package_name" || key == "plugin_name" || key == "node_name" ||
                key == "node_namespace") &&
               f.size() == 2)
    {
      current.request.set(key, DynValue::string(f[1]));
      if (key == "plugin_name") {
        current.plugin = f[1];
      } else if (key == "node_name") {
        current.node = f[1];
      }
    } else if (key == "log_level" && f.size() == 2) {
      DynValue level;
      if (!parse_int(f[1], &level) || level.i < 0 || level.i > 255) {
        warn("log_level must be a number from 0 to 255");
      } else {
        current.request.set("log_level", DynValue::uinteger(static_cast<uint64_t>(level.i)));
      }
    } else if (key == "remap_rule" && f.size() == 2) {
      remaps.push_back(DynValue::string(f[1]));
    } else if (key == "parameter" || key == "extra_argument") {
      DynValue parameter;
      if (!parameter_value(f, &parameter)) {
        warn("cannot read the " + key + " (NAME, TYPE 1-4 or 6-9, then its values)");
      } else {
        (key == "parameter" ? parameters : extras).push_back(std::move(parameter));
      }
    } else {
      warn("unknown line `" + key + "` (or the wrong number of fields)");
    }
  }
  if (open) {
    warnings->push_back("RMW_INTROSPECT_LOAD_NODES: the last request has no `end`: left out");
  }
  return loads;
}

std::vector<ComponentLoad> read_component_loads(
  const std::string & path, std::vector<std::string> * warnings)
{
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    warnings->push_back(
      "RMW_INTROSPECT_LOAD_NODES=" + path + ": cannot read the file: no component is loaded");
    return {};
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_component_loads(text.str(), warnings);
}

const char * component_load_result_name(ComponentLoadRecord::Result result)
{
  switch (result) {
    case ComponentLoadRecord::Result::kPending: return "pending";
    case ComponentLoadRecord::Result::kLoaded: return "loaded";
    case ComponentLoadRecord::Result::kRefused: return "refused";
    case ComponentLoadRecord::Result::kNoAnswer: return "no_answer";
    case ComponentLoadRecord::Result::kNoService: return "no_service";
    case ComponentLoadRecord::Result::kFailed: return "failed";
  }
  return "pending";
}

ComponentLoadPlan::ComponentLoadPlan(std::vector<ComponentLoad> loads)
: loads_(std::move(loads))
{
  for (const auto & load : loads_) {
    ComponentLoadRecord record;
    record.service = load.service;
    record.plugin = load.plugin;
    record.node = load.node;
    records_.push_back(record);
  }
}

bool ComponentLoadPlan::next(
  const RecorderSnapshot & snapshot, uint64_t * service_id, const ComponentLoad ** out)
{
  while (next_ < loads_.size()) {
    const ComponentLoad & load = loads_[next_];
    ComponentLoadRecord & record = records_[next_];
    ++next_;
    std::string services;
    for (const auto & e : snapshot.endpoints) {
      if (e.kind != EndpointKind::Service || !e.alive) {
        continue;
      }
      if (e.name == load.service) {
        *service_id = e.id;
        *out = &load;
        return true;
      }
      if (e.name.size() > 21 &&
          e.name.compare(e.name.size() - 21, 21, "/_container/load_node") == 0)
      {
        services += (services.empty() ? "" : ", ") + e.name;
      }
    }
    record.result = ComponentLoadRecord::Result::kNoService;
    record.error = "the process has no service " + load.service +
      " (its component containers' are: " + (services.empty() ? std::string("none") : services) +
      ")";
  }
  return false;
}

void ComponentLoadPlan::on_answer(const DynValue & response)
{
  if (next_ == 0) {
    return;
  }
  ComponentLoadRecord & record = records_[next_ - 1];
  const DynValue * success = response.field("success");
  const DynValue * error = response.field("error_message");
  const DynValue * name = response.field("full_node_name");
  if (success != nullptr && success->as_bool()) {
    record.result = ComponentLoadRecord::Result::kLoaded;
    record.full_node_name = name != nullptr ? name->s : std::string();
  } else {
    record.result = ComponentLoadRecord::Result::kRefused;
    record.error =
      error != nullptr && !error->s.empty() ? error->s : std::string("the container refused it");
  }
}

void ComponentLoadPlan::on_failed(const std::string & why, bool timed_out)
{
  if (next_ == 0) {
    return;
  }
  ComponentLoadRecord & record = records_[next_ - 1];
  record.result =
    timed_out ? ComponentLoadRecord::Result::kNoAnswer : ComponentLoadRecord::Result::kFailed;
  record.error = why;
}

}  // namespace rmw_introspect
