// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// The previous capture renderer, kept as the reference of the exact output (test only).
#ifndef REFERENCE_CAPTURE_WRITER_HPP_
#define REFERENCE_CAPTURE_WRITER_HPP_

#include <string>

#include "detail/capture_writer.hpp"

namespace rmwi_reference
{

std::string quote_string(const std::string & in);
std::string exact_double_text(double d);
std::string render_capture_json(
  const rmw_introspect::CaptureHeader & header, const rmw_introspect::RecorderSnapshot & snapshot);
std::string render_capture_yaml(
  const rmw_introspect::CaptureHeader & header, const rmw_introspect::RecorderSnapshot & snapshot);

}  // namespace rmwi_reference

#endif  // REFERENCE_CAPTURE_WRITER_HPP_
