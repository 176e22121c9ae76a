// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__PYTHON_HPP_
#define DETAIL__PYTHON_HPP_

namespace rmw_introspect
{

/// True when this is a Python process whose interpreter is finalizing (found at run time
/// with dlsym: the library does not link libpython).
bool python_is_finalizing();

/// If this is a Python process, flush sys.stdout/sys.stderr (text written with print() sits
/// in Python's buffers, which _exit would drop). Never blocks the exit for long: a watchdog
/// ends the process if the interpreter lock cannot be had.
void flush_python_streams();

}  // namespace rmw_introspect

#endif  // DETAIL__PYTHON_HPP_
