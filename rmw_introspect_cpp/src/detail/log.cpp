// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/log.hpp"

#include <cstdarg>
#include <cstdio>

#include "detail/runtime.hpp"

namespace rmw_introspect
{

void verbose_log(const char * format, ...)
{
  if (!Runtime::instance().config().verbose) {
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
