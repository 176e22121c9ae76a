// action_poller: sends one goal to the action `fibonacci` and drives its client with
// `while (!done) rclcpp::spin_some(node);`: every wait is a poll (timeout 0), at 100 % CPU,
// because the goal's answer never comes (nobody serves the action in a capture).
#include <atomic>
#include <memory>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_action/rclcpp_action.hpp"
#include "std_msgs/msg/string.hpp"
#include "test_msgs/action/fibonacci.hpp"

using Fibonacci = test_msgs::action::Fibonacci;

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  auto node = std::make_shared<rclcpp::Node>("action_poller");
  auto status = node->create_publisher<std_msgs::msg::String>("poller_status", 10);
  auto client = rclcpp_action::create_client<Fibonacci>(node, "fibonacci");

  std::atomic<bool> done{false};
  rclcpp_action::Client<Fibonacci>::SendGoalOptions options;
  options.result_callback = [&done](const auto &) {done = true;};
  options.goal_response_callback = [&done](const auto & handle) {
      if (!handle) {
        done = true;  // rejected
      }
    };
  Fibonacci::Goal goal;
  goal.order = 5;
  client->async_send_goal(goal, options);
  while (rclcpp::ok() && !done) {
    rclcpp::spin_some(node);
  }
  rclcpp::shutdown();
  return 0;
}
