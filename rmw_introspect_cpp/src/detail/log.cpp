// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/log.hpp"

#include <atomic>
#include <cstdarg>
#include <cstdio>

namespace rmw_introspect
{

namespace
{
std::atomic<bool> g_verbose{false};
}  // namespace

void set_verbose_log(bool verbose)
{
  g_verbose.store(verbose);
}

void verbose_log(const char * format, ...)
{
  if (!g_verbose.load()) {
    return;
  }
  char buffer[1024];
  va_list args;
  va_start(args, format);
  vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  std::fprintf(stderr, "[rmw_introspect] %s\n", buffer);
}

}  // namespace rmw_introspect
