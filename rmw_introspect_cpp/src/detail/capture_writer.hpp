// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__CAPTURE_WRITER_HPP_
#define DETAIL__CAPTURE_WRITER_HPP_

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "detail/config.hpp"
#include "detail/recorder.hpp"
#include "detail/component_loads.hpp"
#include "detail/stimuli.hpp"
#include "detail/type_text_cache.hpp"

namespace rmw_introspect
{

/// Process-level fields of a capture (design.md section 1).
struct CaptureHeader
{
  long pid = 0;
  std::vector<std::string> argv;
  std::string state = "running";  // running | probing | warping | settled | shutdown | exit
  int settle_ms = 10;
  bool has_time_to_settle = false;
  double time_to_settle_ms = 0.0;
  double elapsed_ms = 0.0;
  std::string settled_by;  // "wait" | "poll" | "activity" | "sleep" | "" (null: not settled)
  bool ever_waited = false;
  uint64_t activity_calls = 0;
  // "quiescence": how the settles ended (docs/design.md, "Detected quiescence")
  bool idle_detect = false;
  uint64_t idle_settles = 0;
  uint64_t window_settles = 0;
  uint64_t polls = 0;  // polls of rmw_wait (timeout 0)
  std::string not_idle;  // why the latest census found the process not idle ("": null)
  // "time": virtual time (horizon 0 = off)
  int64_t horizon_ms = 0;
  double virtual_elapsed_ms = 0.0;
  double real_elapsed_ms = 0.0;
  uint64_t jumps = 0;
  double warp_ms = 0.0;
  bool horizon_reached = false;
  bool warp_budget_exhausted = false;
  bool warp_stalled = false;  // ended early: the process never waited with a timeout
  bool warp_real_waits = false;  // ended early: idle while a loop waited on the real clock
  double warp_real_ms = 0.0;  // real time the warp lasted (so far)
  uint64_t warp_polls = 0;  // polls of rmw_wait in the warp (returns without waiting)
  uint64_t warp_activity = 0;  // activity calls in the warp
  // "probe": asking the nodes' own services (parameters, lifecycle)
  std::string probe_state = "off";  // off | pending | running | done | skipped
  bool probe_parameters = false;
  std::string probe_lifecycle = "none";
  int64_t answer_timeout_ms = 0;
  uint64_t probe_requests = 0;
  uint64_t probe_unanswered = 0;
  // "stimuli": RMW_INTROSPECT_STIMULI, in the order given, and what each came to
  std::vector<StimulusRecord> stimuli;
  // "component_loads": RMW_INTROSPECT_LOAD_NODES, in the order given (absent when none)
  std::vector<ComponentLoadRecord> component_loads;
  // "ended": only in the captures written as the process ends (exit, shutdown)
  bool has_ended = false;
  bool ended_before_settle = false;
};

/// Renders the captures of one process. JSON is written straight into the output, each
/// `types` entry rendered once and reused by later captures (TypeTextCache); YAML goes
/// through a document tree. Not thread-safe: one render at a time (Runtime::write_mutex_).
class CaptureRenderer
{
public:
  CaptureRenderer();
  CaptureRenderer(const CaptureRenderer &) = delete;
  CaptureRenderer & operator=(const CaptureRenderer &) = delete;

  std::string render(
    CaptureFormat format, const CaptureHeader & header, const RecorderSnapshot & snapshot);
  std::string render_json(const CaptureHeader & header, const RecorderSnapshot & snapshot);
  std::string render_yaml(const CaptureHeader & header, const RecorderSnapshot & snapshot);

  const TypeTextCache & type_cache() const { return types_; }

private:
  TypeTextCache types_;
  size_t last_json_size_ = 0;  // to reserve the next output at once
};

/// One capture with a renderer of its own (nothing cached from one call to the next).
std::string render_capture_json(const CaptureHeader & header, const RecorderSnapshot & snapshot);
std::string render_capture_yaml(const CaptureHeader & header, const RecorderSnapshot & snapshot);
std::string render_capture(
  CaptureFormat format, const CaptureHeader & header, const RecorderSnapshot & snapshot);

/// Write `content` to a new `<path>.tmp.XXXXXX` (created exclusively), then rename over `path`.
/// Returns false and fills `error` on failure (the target is then left untouched).
bool write_file_atomically(
  const std::string & path, const std::string & content, std::string * error);

/// This process's argv from /proc/self/cmdline.
std::vector<std::string> read_process_argv();

}  // namespace rmw_introspect

#endif  // DETAIL__CAPTURE_WRITER_HPP_
