// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/session.hpp"

#include <dlfcn.h>
#include <pthread.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "detail/capture_writer.hpp"
#include "detail/handles.hpp"
#include "detail/recorder.hpp"

namespace rmw_introspect
{

namespace
{

// Delay after the last change before a "running" progress snapshot is written.
constexpr std::chrono::milliseconds kSnapshotDelay{20};
// How long the exit path may spend flushing Python's own stdout/stderr buffers.
constexpr std::chrono::milliseconds kFlushWatchdog{500};

template<typename FnT>
FnT lookup_symbol(const char * name)
{
  void * sym = dlsym(RTLD_DEFAULT, name);
  FnT fn = nullptr;
  static_assert(sizeof(fn) == sizeof(sym), "function pointer size");
  std::memcpy(&fn, &sym, sizeof(fn));
  return fn;
}

bool python_is_finalizing();

// If this is a Python process, flush sys.stdout/sys.stderr (text written with print()
// sits in Python's buffers, which _exit would drop). Never blocks the exit for long: a
// watchdog ends the process if the interpreter lock cannot be had.
void flush_python_streams()
{
  using IntFn = int (*)();
  using EnsureFn = int (*)();
  using ReleaseFn = void (*)(int);
  using RunFn = int (*)(const char *);
  auto is_initialized = lookup_symbol<IntFn>("Py_IsInitialized");
  if (is_initialized == nullptr || is_initialized() == 0) {
    return;
  }
  if (python_is_finalizing()) {
    return;
  }
  auto ensure = lookup_symbol<EnsureFn>("PyGILState_Ensure");
  auto release = lookup_symbol<ReleaseFn>("PyGILState_Release");
  auto run = lookup_symbol<RunFn>("PyRun_SimpleString");
  if (ensure == nullptr || release == nullptr || run == nullptr) {
    return;
  }
  std::thread(
    []() {
      std::this_thread::sleep_for(kFlushWatchdog);
      std::fflush(nullptr);
      _exit(0);
    }).detach();
  const int state = ensure();
  run(
    "import sys\n"
    "for _s in (sys.stdout, sys.stderr):\n"
    "    try:\n"
    "        _s.flush()\n"
    "    except Exception:\n"
    "        pass\n");
  release(state);
}

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}

bool python_is_finalizing()
{
  using IntFn = int (*)();
  static IntFn fn = []() {
      IntFn f = lookup_symbol<IntFn>("Py_IsFinalizing");  // Python >= 3.13
      return f != nullptr ? f : lookup_symbol<IntFn>("_Py_IsFinalizing");
    }();
  return fn != nullptr && fn() != 0;
}

}  // namespace

bool in_teardown(const ContextImpl * context)
{
  if (context != nullptr && context->is_shutdown.load()) {
    return true;
  }
  return Session::instance().exiting() || python_is_finalizing();
}

Session & Session::instance()
{
  static Session * session = new Session();  // leaked: used from atexit and the monitor
  return *session;
}

Session::Session()
: config_(Config::get())
{
}

void Session::on_init()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (initialized_) {
      return;
    }
    initialized_ = true;
    t0_ = Clock::now();
    last_change_ = t0_;
  }
  Recorder::instance().set_change_listener([]() {Session::instance().on_change();});
  std::atexit([]() {Session::instance().on_process_exit();});
  std::thread([this]() {monitor_loop();}).detach();
}

void Session::on_change()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++generation_;
    last_change_ = Clock::now();
    waiters_current_ = 0;
  }
  cv_.notify_all();
}

uint64_t Session::enter_wait()
{
  bool wake = false;
  uint64_t token = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    token = generation_;
    wake = (++waiters_current_ == 1);
  }
  if (wake) {
    cv_.notify_all();
  }
  return token;
}

void Session::leave_wait(uint64_t token)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (token == generation_ && waiters_current_ > 0) {
    --waiters_current_;
  }
}

void Session::monitor_loop()
{
  pthread_setname_np(pthread_self(), "rmwi_monitor");
  std::unique_lock<std::mutex> lock(mutex_);
  const auto settle = std::chrono::milliseconds(config_.settle_ms);
  while (!exiting_) {
    const auto now = Clock::now();
    bool have_deadline = false;
    Clock::time_point deadline{};
    if (settled_generation_ != generation_ && waiters_current_ > 0) {
      const auto settle_at = last_change_ + settle;
      if (now >= settle_at) {
        settle_locked(lock);
        continue;
      }
      deadline = settle_at;
      have_deadline = true;
    }
    if (written_generation_ != generation_) {
      const auto snapshot_at = last_change_ + kSnapshotDelay;
      if (now >= snapshot_at) {
        written_generation_ = generation_;
        const bool has_settle = has_settled_;
        const double tts = time_to_settle_ms_;
        lock.unlock();
        write_capture_unlocked("running", tts, has_settle);
        lock.lock();
        continue;
      }
      if (!have_deadline || snapshot_at < deadline) {
        deadline = snapshot_at;
        have_deadline = true;
      }
    }
    if (have_deadline) {
      cv_.wait_until(lock, deadline);
    } else {
      cv_.wait(lock);
    }
  }
}

void Session::settle_locked(std::unique_lock<std::mutex> & lock)
{
  settled_generation_ = generation_;
  written_generation_ = generation_;
  has_settled_ = true;
  time_to_settle_ms_ = ms_between(t0_, Clock::now());
  const double tts = time_to_settle_ms_;
  lock.unlock();
  write_capture_unlocked("settled", tts, true);
  if (config_.exit_on_settle) {
    if (config_.verbose) {
      std::fprintf(
        stderr, "[rmw_introspect] settled after %.1f ms: exiting (RMW_INTROSPECT_EXIT=1)\n", tts);
    }
    flush_python_streams();
    std::fflush(nullptr);
    _exit(0);
  }
  lock.lock();
}

void Session::on_shutdown()
{
  write_capture("shutdown");
}

bool Session::exiting()
{
  std::lock_guard<std::mutex> lock(mutex_);
  return exiting_;
}

void Session::on_process_exit()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!initialized_) {
      return;
    }
    exiting_ = true;
  }
  cv_.notify_all();
  write_capture("exit");
}

void Session::write_capture(const char * state)
{
  bool has_settle = false;
  double tts = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!initialized_) {
      return;
    }
    has_settle = has_settled_;
    tts = time_to_settle_ms_;
    written_generation_ = generation_;
  }
  write_capture_unlocked(state, tts, has_settle);
}

void Session::write_capture_unlocked(const char * state, double time_to_settle_ms, bool has_settle)
{
  if (!config_.auto_export) {
    return;
  }
  std::lock_guard<std::mutex> write_lock(write_mutex_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // Once the exit capture is being written, nothing may replace it.
    if (exiting_ && std::strcmp(state, "exit") != 0) {
      return;
    }
  }
  // Leaked on purpose: a function-local static would be destroyed before our atexit handler.
  static const std::vector<std::string> * argv = new std::vector<std::string>(read_process_argv());
  CaptureHeader header;
  header.pid = static_cast<long>(getpid());
  header.argv = *argv;
  header.state = state;
  header.settle_ms = config_.settle_ms;
  header.has_time_to_settle = has_settle;
  header.time_to_settle_ms = time_to_settle_ms;
  header.elapsed_ms = ms_between(t0_, Clock::now());
  const std::string content =
    render_capture(config_.format, header, Recorder::instance().snapshot());
  std::string error;
  if (!write_file_atomically(config_.output_path, content, &error)) {
    std::fprintf(stderr, "[rmw_introspect] cannot write capture: %s\n", error.c_str());
  } else if (config_.verbose) {
    std::fprintf(
      stderr, "[rmw_introspect] wrote %s capture to %s\n", state, config_.output_path.c_str());
  }
}

}  // namespace rmw_introspect
