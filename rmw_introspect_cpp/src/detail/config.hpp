// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__CONFIG_HPP_
#define DETAIL__CONFIG_HPP_

#include <cstdint>
#include <string>
#include <vector>

#include "detail/component_loads.hpp"
#include "detail/prober.hpp"

namespace rmw_introspect
{

enum class CaptureFormat { Json, Yaml };

/// Settings read from the RMW_INTROSPECT_* environment variables (see README.md).
struct Config
{
  std::string output_path;        // RMW_INTROSPECT_OUTPUT, <pid> substituted; empty: the default
  /// The default output's file name (rmw_introspect_<pid>.json or .yaml): it is written in a
  /// private directory the Runtime creates at the first write (private_output_directory), never
  /// at a predictable name in /tmp.
  std::string default_output_name;
  CaptureFormat format = CaptureFormat::Json;  // RMW_INTROSPECT_FORMAT
  int settle_ms = 10;             // RMW_INTROSPECT_SETTLE_MS
  bool exit_on_settle = false;    // RMW_INTROSPECT_EXIT
  bool auto_export = true;        // RMW_INTROSPECT_AUTO_EXPORT
  bool verbose = false;           // RMW_INTROSPECT_VERBOSE
  bool server_available = true;   // RMW_INTROSPECT_SERVER_AVAILABLE
  bool delivery = false;          // RMW_INTROSPECT_DELIVERY: in-process delivery
  bool detect_idle = true;        // RMW_INTROSPECT_IDLE: settle at once when provably idle
  bool virtual_sleeps = true;     // RMW_INTROSPECT_SLEEPS: the warp steps the process's sleeps
  int64_t horizon_ms = 0;         // RMW_INTROSPECT_HORIZON_MS (0: virtual time off)
  int64_t warp_budget_ms = 3000;  // RMW_INTROSPECT_WARP_BUDGET_MS
  /// RMW_INTROSPECT_PARAMETERS (read the nodes' parameters), RMW_INTROSPECT_LIFECYCLE (drive
  /// lifecycle nodes to this state).
  ProbeSettings probe;
  int64_t answer_timeout_ms = 5000;  // RMW_INTROSPECT_ANSWER_TIMEOUT_MS
  /// RMW_INTROSPECT_STIMULI: topic and service names that get one default message or request
  /// after the probing (stimuli.hpp); empty = off.
  std::vector<std::string> stimuli;
  /// RMW_INTROSPECT_LOAD_NODES: a file of LoadNode requests for this process's component
  /// containers, sent before the probing (component_loads.hpp); empty = none.
  std::vector<ComponentLoad> component_loads;
  /// One line per value that was out of range or not a number (kept at its default);
  /// the Runtime prints them on stderr.
  std::vector<std::string> warnings;

  /// Parse the environment of this process (pid used for the default output path).
  static Config from_environment(long pid);
};

/// Create a directory only the calling user can enter (mode 0700, mkdtemp) for the default
/// output: `<$TMPDIR or /tmp>/rmw_introspect_<pid>.XXXXXX`. Returns its path, or an empty string
/// with `error` set.
std::string private_output_directory(long pid, std::string * error);

/// Interpret an environment flag: "1", "true", "yes", "on" (any case) are true,
/// "0", "false", "no", "off", "" are false; anything else gives `fallback`.
bool parse_flag(const char * value, bool fallback);

/// A duration in milliseconds from the environment variable `name`: 0 .. 24 h. Unset or
/// empty keeps `*value`; anything else out of range or not a number keeps it too and adds a
/// line to `warnings`.
void parse_ms(const char * name, int64_t * value, std::vector<std::string> * warnings);

}  // namespace rmw_introspect

#endif  // DETAIL__CONFIG_HPP_
