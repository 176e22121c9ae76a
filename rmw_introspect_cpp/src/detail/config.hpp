// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__CONFIG_HPP_
#define DETAIL__CONFIG_HPP_

#include <string>

namespace rmw_introspect
{

enum class CaptureFormat { Json, Yaml };

/// Settings read from the RMW_INTROSPECT_* environment variables (see README.md).
struct Config
{
  std::string output_path;        // RMW_INTROSPECT_OUTPUT, <pid> substituted
  CaptureFormat format = CaptureFormat::Json;  // RMW_INTROSPECT_FORMAT
  int settle_ms = 10;             // RMW_INTROSPECT_SETTLE_MS
  bool exit_on_settle = false;    // RMW_INTROSPECT_EXIT
  bool auto_export = true;        // RMW_INTROSPECT_AUTO_EXPORT
  bool verbose = false;           // RMW_INTROSPECT_VERBOSE
  bool server_available = true;   // RMW_INTROSPECT_SERVER_AVAILABLE

  /// Parse the environment of this process (pid used for the default output path).
  static Config from_environment(long pid);
};

/// Interpret an environment flag: "1", "true", "yes", "on" (any case) are true,
/// "0", "false", "no", "off", "" are false; anything else gives `fallback`.
bool parse_flag(const char * value, bool fallback);

}  // namespace rmw_introspect

#endif  // DETAIL__CONFIG_HPP_
