// A ROS 2 node in plain C on rcl: node "c_talker" in namespace "/c", a std_msgs/String
// publisher on "chatter" and a subscription on "/commands", then it waits on a wait set
// (timeout: forever) like an executor would. Uses rosidl_typesupport_c handles.
// Built with NODE_NAME_WITH_PID (rmwi_c_pid_node): the node is "c_talker_<pid>", a name that
// changes every run; `rmwi_c_pid_node NAME` names it "NAME_<pid>" (a real rename).
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rcl/error_handling.h"
#include "rcl/rcl.h"
#include "rcutils/allocator.h"
#include "rosidl_runtime_c/message_type_support_struct.h"
#include "std_msgs/msg/string.h"

#include "check.h"

int main(int argc, char ** argv)
{
  rcl_allocator_t allocator = rcl_get_default_allocator();
  rcl_init_options_t init_options = rcl_get_zero_initialized_init_options();
  CHECK(rcl_init_options_init(&init_options, allocator));
  rcl_context_t context = rcl_get_zero_initialized_context();
  CHECK(rcl_init(argc, (const char * const *)argv, &init_options, &context));

  rcl_node_t node = rcl_get_zero_initialized_node();
  rcl_node_options_t node_options = rcl_node_get_default_options();
#ifdef NODE_NAME_WITH_PID
  char node_name[64];
  const char * base = (argc > 1 && argv[1][0] != '-') ? argv[1] : "c_talker";
  snprintf(node_name, sizeof(node_name), "%s_%ld", base, (long)getpid());
#else
  const char * node_name = "c_talker";
#endif
  CHECK(rcl_node_init(&node, node_name, "/c", &context, &node_options));

  const rosidl_message_type_support_t * ts = ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, String);
  rcl_publisher_t publisher = rcl_get_zero_initialized_publisher();
  rcl_publisher_options_t pub_options = rcl_publisher_get_default_options();
  CHECK(rcl_publisher_init(&publisher, &node, ts, "chatter", &pub_options));

  rcl_subscription_t subscription = rcl_get_zero_initialized_subscription();
  rcl_subscription_options_t sub_options = rcl_subscription_get_default_options();
  sub_options.qos.reliability = RMW_QOS_POLICY_RELIABILITY_BEST_EFFORT;
  sub_options.qos.depth = 3;
  CHECK(rcl_subscription_init(&subscription, &node, ts, "/commands", &sub_options));

  std_msgs__msg__String msg;
  std_msgs__msg__String__init(&msg);
  CHECK(rcl_publish(&publisher, &msg, NULL));
  std_msgs__msg__String__fini(&msg);

  rcl_guard_condition_t guard = rcl_get_zero_initialized_guard_condition();
  CHECK(rcl_guard_condition_init(&guard, &context, rcl_guard_condition_get_default_options()));

  rcl_wait_set_t wait_set = rcl_get_zero_initialized_wait_set();
  CHECK(rcl_wait_set_init(&wait_set, 1, 1, 0, 0, 0, 0, &context, allocator));
  for (;;) {
    CHECK(rcl_wait_set_clear(&wait_set));
    CHECK(rcl_wait_set_add_subscription(&wait_set, &subscription, NULL));
    CHECK(rcl_wait_set_add_guard_condition(&wait_set, &guard, NULL));
    rcl_ret_t ret = rcl_wait(&wait_set, -1);
    if (ret != RCL_RET_OK && ret != RCL_RET_TIMEOUT) {
      fprintf(stderr, "rcl_wait failed: %s\n", rcl_get_error_string().str);
      return 1;
    }
  }
  return 0;
}
