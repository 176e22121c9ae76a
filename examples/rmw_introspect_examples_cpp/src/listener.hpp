// listener: subscribes to std_msgs/msg/String on `chatter` (depth 10).
// Parameters: `log_every` (integer, 1 to 100 in steps of 1), `prefix` (string, read-only).
// A component (rmw_introspect_examples_cpp::Listener) and, through listener_main.cpp, an executable.
#ifndef LISTENER_HPP_
#define LISTENER_HPP_

#include <memory>
#include <string>

#include "descriptors.hpp"
#include "rclcpp/rclcpp.hpp"
#include "std_msgs/msg/string.hpp"

namespace rmw_introspect_examples_cpp
{

class Listener : public rclcpp::Node
{
public:
  explicit Listener(const rclcpp::NodeOptions & options)
  : Node("listener", options)
  {
    log_every_ = declare_parameter<int64_t>(
      "log_every", 1, in_range("log one message in this many", int64_t{1}, int64_t{100}, 1));
    prefix_ = declare_parameter(
      "prefix", std::string("I heard"), described("written before every message logged", true));

    subscription_ = create_subscription<std_msgs::msg::String>(
      "chatter", 10, [this](const std_msgs::msg::String & message) { on_message(message); });
  }

private:
  void on_message(const std_msgs::msg::String & message)
  {
    if (count_++ % log_every_ == 0) {
      RCLCPP_INFO(get_logger(), "%s: '%s'", prefix_.c_str(), message.data.c_str());
    }
  }

  int64_t log_every_ = 1;
  int64_t count_ = 0;
  std::string prefix_;
  rclcpp::Subscription<std_msgs::msg::String>::SharedPtr subscription_;
};

}  // namespace rmw_introspect_examples_cpp

#endif  // LISTENER_HPP_
