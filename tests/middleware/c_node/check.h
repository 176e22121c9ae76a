// The C nodes' error check: print rcl's error and return 1 from main.
#ifndef CHECK_H_
#define CHECK_H_

#include <stdio.h>

#include "rcl/error_handling.h"

#define CHECK(call) \
  do { \
    rcl_ret_t rc_ = (call); \
    if (rc_ != RCL_RET_OK) { \
      fprintf(stderr, "%s failed: %s\n", #call, rcl_get_error_string().str); \
      return 1; \
    } \
  } while (0)

#endif  // CHECK_H_
