// A ROS 2 node in plain C on rcl with an rcl timer: node "c_timer" in namespace "/c"; a
// 2 s steady-clock timer whose callback creates a publisher on "timed" (once), then it
// waits on a wait set holding the timer, like an executor (rcl_wait derives the timeout
// from the timer). Virtual time makes the 2 s pass at once.
// Modes (first argument):
//   destroy  node "c_timer" also publishes "doomed" from the start; the timer fires after 8 s
//            and destroys that publisher instead (a program that destroys what it offered);
//   poll     as without a mode, but the loop polls: rcl_wait with a zero timeout, never
//            blocking (a zero-timeout polling rcl node). `poll N`: after its N-th poll
//            the loop also creates a publisher on "after_polls" (a bounded loop of polls
//            that ends in a new interface), then polls on.
//   sleep    no wait at all: a loop that publishes on "looped" and sleeps 0.1 s (nanosleep and
//            usleep by turns, the C library's sleeps), and after its 30th sleep (3 s) also
//            creates a publisher on "after_sleeps", then loops on.
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "rcl/error_handling.h"
#include "rcl/rcl.h"
#include "rcl/timer.h"
#include "rcutils/allocator.h"
#include "rosidl_runtime_c/message_type_support_struct.h"
#include "std_msgs/msg/string.h"

#include "check.h"

static rcl_node_t g_node;
static rcl_publisher_t g_publisher;
static bool g_created = false;
static rcl_publisher_t g_doomed;
static bool g_doomed_alive = false;

static void create_publisher(rcl_publisher_t * publisher, const char * topic)
{
  *publisher = rcl_get_zero_initialized_publisher();
  rcl_publisher_options_t options = rcl_publisher_get_default_options();
  const rosidl_message_type_support_t * ts = ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, String);
  if (rcl_publisher_init(publisher, &g_node, ts, topic, &options) != RCL_RET_OK) {
    fprintf(stderr, "rcl_publisher_init failed: %s\n", rcl_get_error_string().str);
    exit(1);
  }
}

static void on_timer(rcl_timer_t * timer, int64_t last_call_time)
{
  (void)timer;
  (void)last_call_time;
  if (g_doomed_alive) {
    if (rcl_publisher_fini(&g_doomed, &g_node) != RCL_RET_OK) {
      fprintf(stderr, "rcl_publisher_fini failed: %s\n", rcl_get_error_string().str);
      exit(1);
    }
    g_doomed_alive = false;
    g_created = true;  // the destroy mode creates nothing later
    return;
  }
  if (g_created) {
    return;
  }
  create_publisher(&g_publisher, "timed");
  g_created = true;
}

int main(int argc, char ** argv)
{
  rcl_allocator_t allocator = rcl_get_default_allocator();
  rcl_init_options_t init_options = rcl_get_zero_initialized_init_options();
  CHECK(rcl_init_options_init(&init_options, allocator));
  rcl_context_t context = rcl_get_zero_initialized_context();
  CHECK(rcl_init(argc, (const char * const *)argv, &init_options, &context));

  g_node = rcl_get_zero_initialized_node();
  rcl_node_options_t node_options = rcl_node_get_default_options();
  CHECK(rcl_node_init(&g_node, "c_timer", "/c", &context, &node_options));
  const bool destroy = argc > 1 && strcmp(argv[1], "destroy") == 0;
  const bool poll = argc > 1 && strcmp(argv[1], "poll") == 0;
  const long polls_before_publisher = poll && argc > 2 ? strtol(argv[2], NULL, 10) : -1;
  long polls = 0;
  rcl_publisher_t after_polls;
  if (destroy) {
    g_doomed = rcl_get_zero_initialized_publisher();
    rcl_publisher_options_t options = rcl_publisher_get_default_options();
    CHECK(rcl_publisher_init(
        &g_doomed, &g_node, ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, String), "doomed", &options));
    g_doomed_alive = true;
  }

  if (argc > 1 && strcmp(argv[1], "sleep") == 0) {
    rcl_publisher_t looped;
    rcl_publisher_t after_sleeps;
    create_publisher(&looped, "looped");
    std_msgs__msg__String message;
    std_msgs__msg__String__init(&message);
    for (long sleeps = 1; ; ++sleeps) {
      CHECK(rcl_publish(&looped, &message, NULL));
      if (sleeps % 2 == 0) {
        const struct timespec tenth = {0, 100 * 1000 * 1000};
        nanosleep(&tenth, NULL);
      } else {
        usleep(100 * 1000);
      }
      if (sleeps == 30) {
        create_publisher(&after_sleeps, "after_sleeps");
      }
    }
  }

  rcl_clock_t clock;
  CHECK(rcl_clock_init(RCL_STEADY_TIME, &clock, &allocator));
  rcl_timer_t timer = rcl_get_zero_initialized_timer();
  CHECK(rcl_timer_init2(
      &timer, &clock, &context, RCL_S_TO_NS(destroy ? 8 : 2), on_timer, allocator, true));

  rcl_wait_set_t wait_set = rcl_get_zero_initialized_wait_set();
  CHECK(rcl_wait_set_init(&wait_set, 0, 0, 1, 0, 0, 0, &context, allocator));
  for (;;) {
    CHECK(rcl_wait_set_clear(&wait_set));
    CHECK(rcl_wait_set_add_timer(&wait_set, &timer, NULL));
    rcl_ret_t ret = rcl_wait(&wait_set, poll ? 0 : -1);
    if (++polls == polls_before_publisher) {
      create_publisher(&after_polls, "after_polls");
    }
    if (ret == RCL_RET_TIMEOUT) {
      continue;
    }
    if (ret != RCL_RET_OK) {
      fprintf(stderr, "rcl_wait failed: %s\n", rcl_get_error_string().str);
      return 1;
    }
    if (wait_set.timers[0] != NULL) {
      ret = rcl_timer_call(&timer);
      if (ret != RCL_RET_OK && ret != RCL_RET_TIMER_CANCELED) {
        fprintf(stderr, "rcl_timer_call failed: %s\n", rcl_get_error_string().str);
        return 1;
      }
    }
  }
  return 0;
}
