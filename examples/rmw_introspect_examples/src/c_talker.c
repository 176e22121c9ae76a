// c_talker: a ROS 2 node in C, written against rcl directly (no rclcpp, no rclc).
//
// Interface:
//   publisher    chatter        std_msgs/msg/String  default QoS (KEEP_LAST 10, RELIABLE, VOLATILE)
//   subscription ~/enable       std_msgs/msg/Bool    default QoS; resolves to /c_talker/enable
// A steady timer publishes every 500 ms while enabled; one rcl_wait loop serves both.
// Command-line --ros-args (remappings, __node, __ns, log levels) work as for any ROS 2 node:
// rcl_init parses them.

#include <signal.h>
#include <stdbool.h>
#include <stdio.h>

#include "rcl/error_handling.h"
#include "rcl/logging.h"
#include "rcl/rcl.h"
#include "rcutils/logging_macros.h"
#include "rosidl_runtime_c/string_functions.h"
#include "std_msgs/msg/bool.h"
#include "std_msgs/msg/string.h"

#define PERIOD_NS RCL_MS_TO_NS(500)
// upper bound on one rcl_wait, so that a signal ends the loop promptly
#define WAIT_TIMEOUT_NS RCL_MS_TO_NS(100)

static volatile sig_atomic_t g_stop = 0;

static void on_signal(int signum)
{
  (void)signum;
  g_stop = 1;
}

static bool ok(rcl_ret_t ret, const char * what)
{
  if (ret == RCL_RET_OK) {
    return true;
  }
  fprintf(stderr, "c_talker: %s failed (%d): %s\n", what, (int)ret, rcl_get_error_string().str);
  rcl_reset_error();
  return false;
}

int main(int argc, char ** argv)
{
  struct sigaction action = {0};
  action.sa_handler = on_signal;
  sigaction(SIGINT, &action, NULL);
  sigaction(SIGTERM, &action, NULL);

  int status = 1;
  rcl_allocator_t allocator = rcl_get_default_allocator();

  // context: rcl_init parses --ros-args
  rcl_init_options_t init_options = rcl_get_zero_initialized_init_options();
  if (!ok(rcl_init_options_init(&init_options, allocator), "rcl_init_options_init")) {
    return 1;
  }
  rcl_context_t context = rcl_get_zero_initialized_context();
  bool initialized = ok(rcl_init(argc, (const char **)argv, &init_options, &context), "rcl_init");
  (void)ok(rcl_init_options_fini(&init_options), "rcl_init_options_fini");
  if (!initialized) {
    return 1;
  }
  // like rclcpp: log to the console, the log file and /rosout
  bool logging = ok(rcl_logging_configure(&context.global_arguments, &allocator),
      "rcl_logging_configure");

  rcl_node_t node = rcl_get_zero_initialized_node();
  rcl_node_options_t node_options = rcl_node_get_default_options();
  if (!ok(rcl_node_init(&node, "c_talker", "", &context, &node_options), "rcl_node_init")) {
    goto fini_context;
  }
  const char * logger = rcl_node_get_logger_name(&node);

  rcl_publisher_t publisher = rcl_get_zero_initialized_publisher();
  rcl_publisher_options_t publisher_options = rcl_publisher_get_default_options();
  if (!ok(rcl_publisher_init(&publisher, &node,
      ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, String), "chatter", &publisher_options),
      "rcl_publisher_init"))
  {
    goto fini_node;
  }

  rcl_subscription_t subscription = rcl_get_zero_initialized_subscription();
  rcl_subscription_options_t subscription_options = rcl_subscription_get_default_options();
  if (!ok(rcl_subscription_init(&subscription, &node,
      ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, Bool), "~/enable", &subscription_options),
      "rcl_subscription_init"))
  {
    goto fini_publisher;
  }

  rcl_clock_t clock;
  if (!ok(rcl_clock_init(RCL_STEADY_TIME, &clock, &allocator), "rcl_clock_init")) {
    goto fini_subscription;
  }
  // no callback: the loop below calls rcl_timer_call() and then publishes itself
  rcl_timer_t timer = rcl_get_zero_initialized_timer();
  if (!ok(rcl_timer_init2(&timer, &clock, &context, PERIOD_NS, NULL, allocator, true),
      "rcl_timer_init2"))
  {
    goto fini_clock;
  }

  rcl_wait_set_t wait_set = rcl_get_zero_initialized_wait_set();
  if (!ok(rcl_wait_set_init(&wait_set, 1, 0, 1, 0, 0, 0, &context, allocator),
      "rcl_wait_set_init"))
  {
    goto fini_timer;
  }

  bool enabled = true;
  unsigned long count = 0;
  std_msgs__msg__String message;
  std_msgs__msg__String__init(&message);
  std_msgs__msg__Bool enable;
  std_msgs__msg__Bool__init(&enable);

  status = 0;
  while (!g_stop && rcl_context_is_valid(&context)) {
    if (!ok(rcl_wait_set_clear(&wait_set), "rcl_wait_set_clear") ||
      !ok(rcl_wait_set_add_subscription(&wait_set, &subscription, NULL), "add subscription") ||
      !ok(rcl_wait_set_add_timer(&wait_set, &timer, NULL), "add timer"))
    {
      status = 1;
      break;
    }
    rcl_ret_t ret = rcl_wait(&wait_set, WAIT_TIMEOUT_NS);
    if (ret == RCL_RET_TIMEOUT) {
      continue;
    }
    if (!ok(ret, "rcl_wait")) {
      status = 1;
      break;
    }
    if (wait_set.subscriptions[0]) {
      ret = rcl_take(&subscription, &enable, NULL, NULL);
      if (ret == RCL_RET_OK) {
        enabled = enable.data;
        RCUTILS_LOG_INFO_NAMED(logger, "publishing %s", enabled ? "enabled" : "disabled");
      } else if (ret != RCL_RET_SUBSCRIPTION_TAKE_FAILED) {
        (void)ok(ret, "rcl_take");
      }
    }
    if (wait_set.timers[0]) {
      ret = rcl_timer_call(&timer);
      if (ret == RCL_RET_OK && enabled) {
        char text[64];
        snprintf(text, sizeof(text), "Hello from C: %lu", count++);
        rosidl_runtime_c__String__assign(&message.data, text);
        RCUTILS_LOG_INFO_NAMED(logger, "Publishing: \"%s\"", text);
        (void)ok(rcl_publish(&publisher, &message, NULL), "rcl_publish");
      } else if (ret != RCL_RET_OK && ret != RCL_RET_TIMER_CANCELED) {
        (void)ok(ret, "rcl_timer_call");
      }
    }
  }

  std_msgs__msg__Bool__fini(&enable);
  std_msgs__msg__String__fini(&message);
  (void)ok(rcl_wait_set_fini(&wait_set), "rcl_wait_set_fini");
fini_timer:
  (void)ok(rcl_timer_fini(&timer), "rcl_timer_fini");
fini_clock:
  (void)ok(rcl_clock_fini(&clock), "rcl_clock_fini");
fini_subscription:
  (void)ok(rcl_subscription_fini(&subscription, &node), "rcl_subscription_fini");
fini_publisher:
  (void)ok(rcl_publisher_fini(&publisher, &node), "rcl_publisher_fini");
fini_node:
  (void)ok(rcl_node_fini(&node), "rcl_node_fini");
fini_context:
  if (logging) {
    (void)ok(rcl_logging_fini(), "rcl_logging_fini");
  }
  (void)ok(rcl_shutdown(&context), "rcl_shutdown");
  (void)ok(rcl_context_fini(&context), "rcl_context_fini");
  return status;
}
