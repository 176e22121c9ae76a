// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/config.hpp"

#include <stdlib.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>

#include "detail/stimuli.hpp"

namespace rmw_introspect
{

bool parse_flag(const char * value, bool fallback)
{
  if (value == nullptr) {
    return fallback;
  }
  std::string v;
  for (const char * p = value; *p; ++p) {
    v.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(*p))));
  }
  if (v == "1" || v == "true" || v == "yes" || v == "on") {
    return true;
  }
  if (v == "0" || v == "false" || v == "no" || v == "off" || v.empty()) {
    return false;
  }
  return fallback;
}

void parse_ms(const char * name, int64_t * value, std::vector<std::string> * warnings)
{
  constexpr long long kMaxMs = 24LL * 3600LL * 1000LL;
  const char * text = std::getenv(name);
  if (text == nullptr || text[0] == '\0') {
    return;
  }
  char * end = nullptr;
  errno = 0;
  const long long parsed = std::strtoll(text, &end, 10);
  if (end == text || *end != '\0' || errno == ERANGE || parsed < 0 || parsed > kMaxMs) {
    warnings->push_back(
      std::string(name) + "=" + text + " is not a number of milliseconds in 0.." +
      std::to_string(kMaxMs) + ": using " + std::to_string(*value));
    return;
  }
  *value = parsed;
}

Config Config::from_environment(long pid)
{
  Config config;
  const char * format = std::getenv("RMW_INTROSPECT_FORMAT");
  if (format != nullptr) {
    std::string f(format);
    for (auto & c : f) {
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    if (f == "yaml" || f == "yml") {
      config.format = CaptureFormat::Yaml;
    }
  }
  const std::string pid_string = std::to_string(pid);
  const char * output = std::getenv("RMW_INTROSPECT_OUTPUT");
  if (output != nullptr && output[0] != '\0') {
    config.output_path = output;
    const std::string placeholder = "<pid>";
    for (size_t pos = config.output_path.find(placeholder); pos != std::string::npos;
         pos = config.output_path.find(placeholder, pos + pid_string.size()))
    {
      config.output_path.replace(pos, placeholder.size(), pid_string);
    }
  } else {
    config.default_output_name =
      "rmw_introspect_" + pid_string + (config.format == CaptureFormat::Yaml ? ".yaml" : ".json");
  }
  int64_t settle_ms = config.settle_ms;
  parse_ms("RMW_INTROSPECT_SETTLE_MS", &settle_ms, &config.warnings);
  config.settle_ms = static_cast<int>(settle_ms);
  parse_ms("RMW_INTROSPECT_HORIZON_MS", &config.horizon_ms, &config.warnings);
  parse_ms("RMW_INTROSPECT_WARP_BUDGET_MS", &config.warp_budget_ms, &config.warnings);
  config.exit_on_settle = parse_flag(std::getenv("RMW_INTROSPECT_EXIT"), false);
  config.auto_export = parse_flag(std::getenv("RMW_INTROSPECT_AUTO_EXPORT"), true);
  config.verbose = parse_flag(std::getenv("RMW_INTROSPECT_VERBOSE"), false);
  config.server_available = parse_flag(std::getenv("RMW_INTROSPECT_SERVER_AVAILABLE"), true);
  config.delivery = parse_flag(std::getenv("RMW_INTROSPECT_DELIVERY"), false);
  config.detect_idle = parse_flag(std::getenv("RMW_INTROSPECT_IDLE"), true);
  config.virtual_sleeps = parse_flag(std::getenv("RMW_INTROSPECT_SLEEPS"), true);
  config.probe.parameters = parse_flag(std::getenv("RMW_INTROSPECT_PARAMETERS"), true);
  const char * lifecycle = std::getenv("RMW_INTROSPECT_LIFECYCLE");
  if (lifecycle != nullptr && lifecycle[0] != '\0' &&
      !parse_lifecycle_target(lifecycle, &config.probe.lifecycle))
  {
    config.warnings.push_back(
      std::string("RMW_INTROSPECT_LIFECYCLE=") + lifecycle +
      " is not one of active, inactive, unconfigured, none: using " +
      lifecycle_target_name(config.probe.lifecycle));
  }
  int64_t answer_timeout_ms = config.answer_timeout_ms;
  parse_ms("RMW_INTROSPECT_ANSWER_TIMEOUT_MS", &answer_timeout_ms, &config.warnings);
  if (answer_timeout_ms == 0) {
    config.warnings.push_back(
      "RMW_INTROSPECT_ANSWER_TIMEOUT_MS=0 leaves a node no time to answer: using " +
      std::to_string(config.answer_timeout_ms));
  } else {
    config.answer_timeout_ms = answer_timeout_ms;
  }
  config.stimuli = parse_stimuli(std::getenv("RMW_INTROSPECT_STIMULI"), &config.warnings);
  const char * loads = std::getenv("RMW_INTROSPECT_LOAD_NODES");
  if (loads != nullptr && *loads != '\0') {
    config.component_loads = read_component_loads(loads, &config.warnings);
  }
  return config;
}

std::string private_output_directory(long pid, std::string * error)
{
  const char * tmpdir = std::getenv("TMPDIR");
  std::string pattern = (tmpdir != nullptr && tmpdir[0] == '/') ? tmpdir : "/tmp";
  pattern += "/rmw_introspect_" + std::to_string(pid) + ".XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) {  // mode 0700, a name no one else could plant
    if (error != nullptr) {
      *error = "cannot create a private directory " + pattern + ": " + std::strerror(errno);
    }
    return std::string();
  }
  return pattern;
}

}  // namespace rmw_introspect
