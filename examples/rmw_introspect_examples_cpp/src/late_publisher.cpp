// late_publisher: creates its publisher `late_status` (std_msgs/msg/String, depth 5) from a
// one-shot timer 2 s after start, the way drivers that wait for hardware do. A capture sees it
// only when it lasts long enough (or with virtual time).
#include <chrono>
#include <memory>

#include "rclcpp/rclcpp.hpp"
#include "std_msgs/msg/string.hpp"

using namespace std::chrono_literals;

class LatePublisher : public rclcpp::Node
{
public:
  LatePublisher()
  : Node("late_publisher")
  {
    timer_ = create_wall_timer(2s, [this]() { on_ready(); });
  }

private:
  void on_ready()
  {
    timer_->cancel();
    publisher_ = create_publisher<std_msgs::msg::String>("late_status", 5);
    std_msgs::msg::String message;
    message.data = "ready";
    publisher_->publish(message);
  }

  rclcpp::Publisher<std_msgs::msg::String>::SharedPtr publisher_;
  rclcpp::TimerBase::SharedPtr timer_;
};

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  rclcpp::spin(std::make_shared<LatePublisher>());
  rclcpp::shutdown();
  return 0;
}
