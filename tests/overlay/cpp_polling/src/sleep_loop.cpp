// sleep_loop: `publish; sleep_for(10ms); spin_some` - a loop on the program's own (real) clock,
// with no timer at all.
#include <chrono>
#include <memory>
#include <thread>

#include "rclcpp/rclcpp.hpp"
#include "std_msgs/msg/string.hpp"

using namespace std::chrono_literals;

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  auto node = std::make_shared<rclcpp::Node>("sleep_loop");
  auto publisher = node->create_publisher<std_msgs::msg::String>("sleep_chatter", 10);
  auto subscription = node->create_subscription<std_msgs::msg::String>(
    "sleep_commands", 10, [](const std_msgs::msg::String &) {});
  std_msgs::msg::String message;
  message.data = "tick";
  while (rclcpp::ok()) {
    publisher->publish(message);
    std::this_thread::sleep_for(10ms);
    rclcpp::spin_some(node);
  }
  rclcpp::shutdown();
  return 0;
}
