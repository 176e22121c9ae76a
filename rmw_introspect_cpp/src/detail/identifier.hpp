// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__IDENTIFIER_HPP_
#define DETAIL__IDENTIFIER_HPP_

namespace rmw_introspect
{
// One pointer for the whole library: RMW_CHECK_TYPE_IDENTIFIERS_MATCH compares pointers.
extern const char * const kIdentifier;
extern const char * const kSerializationFormat;
}  // namespace rmw_introspect

#endif  // DETAIL__IDENTIFIER_HPP_
