// talker: publishes std_msgs/msg/String on `chatter` (depth 10: KEEP_LAST 10, RELIABLE, VOLATILE).
// Parameters: `rate_hz` (double, 0.1 to 50.0), `frame_id` (string, read-only).
// A component (rmw_introspect_examples_cpp::Talker) and, through talker_main.cpp, an executable.
#ifndef TALKER_HPP_
#define TALKER_HPP_

#include <chrono>
#include <memory>
#include <string>

#include "descriptors.hpp"
#include "rclcpp/rclcpp.hpp"
#include "std_msgs/msg/string.hpp"

namespace rmw_introspect_examples_cpp
{

class Talker : public rclcpp::Node
{
public:
  explicit Talker(const rclcpp::NodeOptions & options)
  : Node("talker", options)
  {
    const double rate_hz =
      declare_parameter("rate_hz", 2.0, in_range("messages per second", 0.1, 50.0));
    frame_id_ = declare_parameter(
      "frame_id", std::string("base_link"), described("frame written into every message", true));

    publisher_ = create_publisher<std_msgs::msg::String>("chatter", 10);
    timer_ =
      create_wall_timer(std::chrono::duration<double>(1.0 / rate_hz), [this]() { on_timer(); });
  }

private:
  void on_timer()
  {
    std_msgs::msg::String message;
    message.data = "Hello World from " + frame_id_ + ": " + std::to_string(count_++);
    publisher_->publish(message);
  }

  std::string frame_id_;
  size_t count_ = 0;
  rclcpp::Publisher<std_msgs::msg::String>::SharedPtr publisher_;
  rclcpp::TimerBase::SharedPtr timer_;
};

}  // namespace rmw_introspect_examples_cpp

#endif  // TALKER_HPP_
