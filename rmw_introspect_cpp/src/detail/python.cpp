// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/python.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

#include "detail/real_sleep.hpp"

namespace rmw_introspect
{

namespace
{

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

}  // namespace

bool python_is_finalizing()
{
  using IntFn = int (*)();
  static IntFn fn = []() {
    IntFn f = lookup_symbol<IntFn>("Py_IsFinalizing");  // Python >= 3.13
    return f != nullptr ? f : lookup_symbol<IntFn>("_Py_IsFinalizing");
  }();
  return fn != nullptr && fn() != 0;
}

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
  std::thread([]() {
    // For real: the interposed sleep (src/sleep.cpp) would jump virtual time in the warp.
    real_sleep_ns(std::chrono::duration_cast<std::chrono::nanoseconds>(kFlushWatchdog).count());
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

}  // namespace rmw_introspect
