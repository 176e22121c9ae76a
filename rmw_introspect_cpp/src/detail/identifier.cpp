// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/identifier.hpp"

namespace rmw_introspect
{
const char * const kIdentifier = "rmw_introspect_cpp";
// Nothing is ever serialized on a wire; "cdr" is what the DDS middlewares report and what
// rmw_serialize produces (see rmw_serialize.cpp).
const char * const kSerializationFormat = "cdr";
}  // namespace rmw_introspect
