// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/runtime.hpp"

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <thread>

#include "detail/capture_writer.hpp"
#include "detail/handles.hpp"
#include "detail/log.hpp"
#include "detail/python.hpp"

namespace rmw_introspect
{

namespace
{
// The process's runtime (leaked on purpose, see the declaration), made on first use.
std::atomic<Runtime *> g_runtime{nullptr};
std::atomic<bool> g_started{false};  // rmw_init reached this process's runtime
std::mutex g_make_mutex;

// A process forked before any rmw_init (a warm start server's child) makes its own runtime on
// first use, reading the configuration from the environment it has by then: a runtime the parent
// made (say, rcutils_steady_time_now reached it) holds the parent's pid, output path and settings.
// A runtime that was initialized stays: a node that forks keeps its middleware as before.
void before_fork()
{
  g_make_mutex.lock();
}
void after_fork_parent()
{
  g_make_mutex.unlock();
}
void after_fork_child()
{
  new (&g_make_mutex) std::mutex();  // the parent's lock state is not the child's to keep
  if (!g_started.load()) {
    g_runtime.store(nullptr);
  }
}
}  // namespace

Runtime & Runtime::instance()
{
  Runtime * runtime = g_runtime.load(std::memory_order_acquire);
  if (runtime != nullptr) {
    return *runtime;
  }
  std::lock_guard<std::mutex> lock(g_make_mutex);
  runtime = g_runtime.load(std::memory_order_acquire);
  if (runtime == nullptr) {
    static const int registered = pthread_atfork(before_fork, after_fork_parent, after_fork_child);
    (void)registered;
    runtime = new Runtime();
    g_runtime.store(runtime, std::memory_order_release);
  }
  return *runtime;
}

Runtime * Runtime::started_instance()
{
  if (!g_started.load(std::memory_order_acquire)) {
    return nullptr;
  }
  Runtime * runtime = g_runtime.load(std::memory_order_acquire);
  return runtime != nullptr && runtime->init_pid_ == getpid() ? runtime : nullptr;
}

namespace
{
Session::Settings session_settings(const Config & config)
{
  Session::Settings settings;
  settings.settle_ms = config.settle_ms;
  settings.horizon_ms = config.horizon_ms;
  settings.warp_budget_ms = config.warp_budget_ms;
  // The stimuli follow the probing, in the same phase: either turns it on.
  // So do the component loads, which come first.
  settings.probe =
    config.probe.enabled() || !config.stimuli.empty() || !config.component_loads.empty();
  settings.answer_timeout_ms = config.answer_timeout_ms;
  settings.detect_idle = config.detect_idle;
  settings.virtual_sleeps = config.virtual_sleeps;
  return settings;
}
}  // namespace

Runtime::Runtime()
: config_(Config::from_environment(static_cast<long>(getpid()))),
  delivery_(wait_hub_),
  probe_driver_(config_.probe, config_.stimuli, config_.component_loads, recorder_, injector_),
  session_(clock_, virtual_clock_, session_settings(config_), &main_thread_state_),
  sleeps_stepped_(config_.virtual_sleeps && config_.horizon_ms > 0)
{
  // Before anything can log: verbose_log's callers all reach this Runtime first (instance()).
  set_verbose_log(config_.verbose);
  for (const auto & warning : config_.warnings) {
    std::fprintf(stderr, "[rmw_introspect] warning: %s\n", warning.c_str());
  }
  recorder_.set_change_listener([this]() { on_change(); });
  // Under the wait hub's lock (lock order: hub, then session).
  // A thread blocked on these waits for the monitor (which holds the session's lock while it
  // decides) or for a thread that does: not idle.
  thread_census_.set_busy_futexes(
    {reinterpret_cast<uintptr_t>(session_mutex_.native_handle()), wait_hub_.lock_address()});
  wait_hub_.set_wake_listener([this](pid_t by) {
    std::lock_guard<std::mutex> lock(session_mutex_);
    session_.on_wake(by);
  });
  {
    std::lock_guard<std::mutex> lock(stimuli_mutex_);
    stimuli_ = probe_driver_.stimuli();  // every name pending
    component_loads_ = probe_driver_.component_loads();
  }
  injector_.set_answer_listener([this](bool changes_node) { on_probe_answer(changes_node); });
}

void Runtime::notify_graph_change()
{
  graph_guards_.trigger_all(wait_hub_);
}

void Runtime::on_init()
{
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    if (!session_.start()) {
      return;
    }
    init_pid_ = getpid();
    g_started.store(true);
    argv_ = read_process_argv();
  }
  std::atexit([]() { Runtime::instance().on_process_exit(); });
  std::thread([this]() { monitor_loop(); }).detach();
}

void Runtime::on_change()
{
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    session_.on_change(current_tid());
  }
  session_cv_.notify_all();
}

void Runtime::on_probe_answer(bool changes_node)
{
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    session_.probe_answered(changes_node);
  }
  session_cv_.notify_all();
}

void Runtime::probe_step()
{
  const bool sent = probe_driver_.step(wait_hub_, [this]() {
    std::lock_guard<std::mutex> lock(session_mutex_);
    session_.probe_sent();
  });
  probe_requests_.store(probe_driver_.requests());
  probe_unanswered_.store(probe_driver_.unanswered());
  publish_stimuli();
  if (!sent) {
    std::lock_guard<std::mutex> lock(session_mutex_);
    session_.probe_done();
  }
  if (config_.verbose) {
    std::fprintf(
      stderr, "[rmw_introspect] %s\n",
      sent ? "sent a request to a node's own service" : "asked every node: probing done");
  }
}

void Runtime::probe_timeout()
{
  probe_driver_.timeout(config_.answer_timeout_ms);
  probe_requests_.store(probe_driver_.requests());
  probe_unanswered_.store(probe_driver_.unanswered());
  publish_stimuli();
}

void Runtime::publish_stimuli()
{
  if (config_.stimuli.empty() && config_.component_loads.empty()) {
    return;
  }
  std::lock_guard<std::mutex> lock(stimuli_mutex_);
  stimuli_ = probe_driver_.stimuli();
  component_loads_ = probe_driver_.component_loads();
}

uint64_t Runtime::enter_wait(int64_t deadline_ns)
{
  uint64_t token = 0;
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    token = session_.enter_wait(current_tid(), deadline_ns);
  }
  session_cv_.notify_all();
  return token;
}

void Runtime::leave_wait(uint64_t token)
{
  std::lock_guard<std::mutex> lock(session_mutex_);
  session_.leave_wait(token);
}

void Runtime::note_wait_entered()
{
  // Once for ever_waited; during the warp every time (it breaks the warp's quiet).
  const bool first = !ever_waited_.exchange(true);
  if (first || warping_.load()) {
    {
      std::lock_guard<std::mutex> lock(session_mutex_);
      session_.on_wait_entered();
    }
    if (first) {
      session_cv_.notify_all();  // a probing that waits for the first wait goes on
    }
  }
}

void Runtime::note_poll(bool found_nothing)
{
  const bool first = !ever_waited_.exchange(true);
  const pid_t tid = current_tid();
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);  // blocked or slept since the last poll? (Session::on_poll)
  bool wake = false;
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    wake = session_.on_poll(tid, found_nothing, static_cast<uint64_t>(usage.ru_nvcsw));
  }
  if (first || wake) {
    session_cv_.notify_all();
  }
}

void Runtime::on_activity()
{
  const pid_t tid = current_tid();
  bool wake = false;
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    wake = session_.on_activity(tid);
  }
  if (wake) {
    session_cv_.notify_all();
  }
}

bool Runtime::jump_sleep(int64_t duration_ns)
{
  if (duration_ns <= 0 || !warping_.load()) {
    return false;
  }
  bool jumped = false;
  bool warp_over = false;
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    jumped = session_.try_jump(session_.virtual_now_ns() + duration_ns);
    warp_over = !session_.warping();
    warping_.store(!warp_over);
  }
  if (warp_over) {
    session_cv_.notify_all();  // the final settle may be taken now
  }
  return jumped;
}

Runtime::Sleeping::Sleeping(Runtime & runtime, int64_t deadline_ns)
: runtime_(runtime)
{
  const pid_t tid = current_tid();
  {
    std::lock_guard<std::mutex> lock(runtime_.session_mutex_);
    token_ = runtime_.session_.enter_sleep(tid, deadline_ns);
  }
  runtime_.session_cv_.notify_all();  // a sleeper may complete a proof of idleness
}

Runtime::Sleeping::~Sleeping()
{
  std::lock_guard<std::mutex> lock(runtime_.session_mutex_);
  runtime_.session_.leave_sleep(token_);
}

CreationTime Runtime::creation_time()
{
  std::lock_guard<std::mutex> lock(session_mutex_);
  CreationTime created;
  created.virtual_ms = session_.virtual_age_ms();
  created.real_ms = session_.real_age_ms();
  return created;
}

void Runtime::monitor_loop()
{
  pthread_setname_np(pthread_self(), "rmwi_monitor");
  std::unique_lock<std::mutex> lock(session_mutex_);
  session_.set_monitor_tid(current_tid());
  while (!session_.exiting()) {
    const Session::Step step = session_.poll();
    warping_.store(session_.warping());
    if (step.action == Session::Action::kCheckIdle) {
      check_idle(lock);
      continue;
    }
    if (step.action != Session::Action::kNone) {
      CaptureHeader header;
      session_.fill_header("settled", &header);
      const char * progress = session_.progress_state();
      const bool probe_skipped = std::strcmp(session_.probe_state(), "skipped") == 0;
      lock.unlock();
      if (probe_skipped && !config_.stimuli.empty() &&
          (step.action == Session::Action::kSettle || step.action == Session::Action::kStartWarp))
      {
        probe_driver_.skip(
          "not delivered: no thread of the process ever waited in rmw_wait (no executor spins), "
          "so nothing could take it");
        publish_stimuli();
      }
      switch (step.action) {
        case Session::Action::kSettle:
          write_capture("settled");
          exit_if_asked(header.time_to_settle_ms);
          break;
        case Session::Action::kStartProbe:
          // A valid capture so far (a node may exit or crash in a transition).
          write_capture("probing");
          break;
        case Session::Action::kProbe: probe_step(); break;
        case Session::Action::kProbeTimeout: probe_timeout(); break;
        case Session::Action::kStartWarp:
          // A valid capture so far (the node may exit or crash during the warp), then wake
          // every waiter: those blocked on a finite timeout come back to jump.
          write_capture("warping");
          wait_hub_.update_and_wake([this]() { warp_starts_.fetch_add(1); });
          break;
        default: write_capture(progress); break;
      }
      lock.lock();
      continue;
    }
    if (step.has_deadline) {
      session_cv_.wait_until(
        lock, std::chrono::steady_clock::time_point(std::chrono::nanoseconds(step.deadline_ns)));
    } else {
      session_cv_.wait(lock);
    }
  }
}

void Runtime::check_idle(std::unique_lock<std::mutex> & lock)
{
  const Session::CensusRequest request = session_.census_request();
  lock.unlock();
  std::string culprit;
  SettingUp setting_up;
  const bool idle = thread_census_.others_blocked(
    request.known, request.until_ns, &culprit, &request.settling, &setting_up, &request.looping);
  if (config_.verbose) {
    std::fprintf(
      stderr, "[rmw_introspect] %s\n", idle ? "every thread is blocked: idle" : culprit.c_str());
  }
  lock.lock();
  session_.census_done(request.version, idle, culprit, setting_up);
}

void Runtime::exit_if_asked(double time_to_settle_ms)
{
  if (!config_.exit_on_settle) {
    return;
  }
  if (config_.verbose) {
    std::fprintf(
      stderr, "[rmw_introspect] settled after %.1f ms: exiting (RMW_INTROSPECT_EXIT=1)\n",
      time_to_settle_ms);
  }
  flush_python_streams();
  std::fflush(nullptr);
  _exit(0);
}

void Runtime::on_shutdown()
{
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    session_.note_written();
  }
  write_capture("shutdown");
}

void Runtime::on_process_exit()
{
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    if (!session_.started()) {
      return;
    }
    session_.begin_exit();
    session_.note_written();
  }
  session_cv_.notify_all();
  write_capture("exit");
}

bool Runtime::in_teardown(const ContextImpl * context)
{
  if (context != nullptr && context->is_shutdown.load()) {
    return true;
  }
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    if (session_.exiting()) {
      return true;
    }
  }
  return python_is_finalizing();
}

void Runtime::write_capture(const char * state)
{
  if (!config_.auto_export) {
    return;
  }
  std::lock_guard<std::mutex> write_lock(write_mutex_);
  CaptureHeader header;
  {
    std::lock_guard<std::mutex> lock(session_mutex_);
    if (!session_.started() || (session_.exiting() && std::strcmp(state, "exit") != 0)) {
      return;
    }
    session_.fill_header(state, &header);
  }
  header.probe_parameters = config_.probe.parameters;
  header.probe_lifecycle = lifecycle_target_name(config_.probe.lifecycle);
  header.probe_requests = probe_requests_.load();
  header.probe_unanswered = probe_unanswered_.load();
  {
    std::lock_guard<std::mutex> lock(stimuli_mutex_);
    header.stimuli = stimuli_;
    header.component_loads = component_loads_;
  }
  header.pid = static_cast<long>(getpid());
  header.argv = argv_;
  header.state = state;
  // The captures written as the process ends mark its final run of destructions.
  const std::string content =
    capture_renderer_.render(config_.format, header, recorder_.snapshot(header.has_ended));
  std::string error;
  if (output_path_.empty() && !config_.output_path.empty()) {
    output_path_ = config_.output_path;
  } else if (output_path_.empty()) {
    // No RMW_INTROSPECT_OUTPUT: a private directory, so nothing at a name another user could
    // predict in /tmp is opened, followed or replaced. Said once, for whoever looks for the file.
    const std::string directory = private_output_directory(header.pid, &error);
    if (directory.empty()) {
      std::fprintf(stderr, "[rmw_introspect] cannot write capture: %s\n", error.c_str());
      return;
    }
    output_path_ = directory + "/" + config_.default_output_name;
    std::fprintf(
      stderr, "[rmw_introspect] the capture goes to %s (RMW_INTROSPECT_OUTPUT unset)\n",
      output_path_.c_str());
  }
  if (!write_file_atomically(output_path_, content, &error)) {
    std::fprintf(stderr, "[rmw_introspect] cannot write capture: %s\n", error.c_str());
  } else if (config_.verbose) {
    std::fprintf(stderr, "[rmw_introspect] wrote %s capture to %s\n", state, output_path_.c_str());
  }
}

}  // namespace rmw_introspect
