// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// GID comparison, QoS compatibility, optional features.

#include <cstring>

#include "rmw/features.h"
#include "rmw/qos_profiles.h"
#include "rmw/rmw.h"

#include "detail/common.hpp"
#include "detail/qos.hpp"

extern "C" {

rmw_ret_t rmw_compare_gids_equal(const rmw_gid_t * gid1, const rmw_gid_t * gid2, bool * result)
{
  // A GID has no implementation data to check, only its identifier.
  RMW_CHECK_ARGUMENT_FOR_NULL(gid1, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    gid1, gid1->implementation_identifier, return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  RMW_CHECK_ARGUMENT_FOR_NULL(gid2, RMW_RET_INVALID_ARGUMENT);
  RMWI_CHECK_IDENTIFIER(
    gid2, gid2->implementation_identifier, return RMW_RET_INCORRECT_RMW_IMPLEMENTATION);
  RMW_CHECK_ARGUMENT_FOR_NULL(result, RMW_RET_INVALID_ARGUMENT);
  *result = std::memcmp(gid1->data, gid2->data, RMW_GID_STORAGE_SIZE) == 0;
  return RMW_RET_OK;
}

rmw_ret_t rmw_qos_profile_check_compatible(
  const rmw_qos_profile_t publisher_profile, const rmw_qos_profile_t subscription_profile,
  rmw_qos_compatibility_type_t * compatibility, char * reason, size_t reason_size)
{
  return rmw_introspect::check_qos_compatible(
    publisher_profile, subscription_profile, compatibility, reason, reason_size);
}

bool rmw_feature_supported(rmw_feature_t feature)
{
  (void)feature;  // no message is ever delivered, so no message-info feature applies
  return false;
}

}  // extern "C"
