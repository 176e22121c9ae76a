// wall_rate_loop: a 2 Hz rclcpp::WallRate loop (publish, spin_some, rate.sleep()): it sleeps
// on the real clock, which virtual time does not reach.
#include <memory>

#include "rclcpp/rclcpp.hpp"
#include "std_msgs/msg/string.hpp"

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  auto node = std::make_shared<rclcpp::Node>("wall_rate_loop");
  auto publisher = node->create_publisher<std_msgs::msg::String>("rate_chatter", 10);
  rclcpp::WallRate rate(2.0);
  std_msgs::msg::String message;
  message.data = "tick";
  while (rclcpp::ok()) {
    publisher->publish(message);
    rclcpp::spin_some(node);
    rate.sleep();
  }
  rclcpp::shutdown();
  return 0;
}
