// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/node_probe.hpp"

namespace rmw_introspect
{

const char * parameter_type_name(uint8_t type)
{
  switch (type) {
    case kParameterBool: return "bool";
    case kParameterInteger: return "integer";
    case kParameterDouble: return "double";
    case kParameterString: return "string";
    case kParameterByteArray: return "byte_array";
    case kParameterBoolArray: return "bool_array";
    case kParameterIntegerArray: return "integer_array";
    case kParameterDoubleArray: return "double_array";
    case kParameterStringArray: return "string_array";
    default: return nullptr;
  }
}

}  // namespace rmw_introspect
