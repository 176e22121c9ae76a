// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__CAPTURE_WRITER_HPP_
#define DETAIL__CAPTURE_WRITER_HPP_

#include <string>
#include <vector>

#include "detail/config.hpp"
#include "detail/recorder.hpp"

namespace rmw_introspect
{

/// Process-level fields of a capture (design.md section 1).
struct CaptureHeader
{
  long pid = 0;
  std::vector<std::string> argv;
  std::string state = "running";  // running | settled | shutdown | exit
  int settle_ms = 10;
  bool has_time_to_settle = false;
  double time_to_settle_ms = 0.0;
  double elapsed_ms = 0.0;
};

std::string render_capture_json(const CaptureHeader & header, const RecorderSnapshot & snapshot);
std::string render_capture_yaml(const CaptureHeader & header, const RecorderSnapshot & snapshot);
std::string render_capture(
  CaptureFormat format, const CaptureHeader & header, const RecorderSnapshot & snapshot);

/// Write `content` to `<path>.tmp.<pid>`, fsync-free flush, then rename over `path`.
/// Returns false and fills `error` on failure (the target is then left untouched).
bool write_file_atomically(const std::string & path, const std::string & content, std::string * error);

/// This process's argv from /proc/self/cmdline.
std::vector<std::string> read_process_argv();

}  // namespace rmw_introspect

#endif  // DETAIL__CAPTURE_WRITER_HPP_
