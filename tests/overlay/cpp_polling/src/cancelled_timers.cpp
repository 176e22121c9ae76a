// cancelled_timers: two timers that each fire once and cancel themselves; the second creates
// the publisher `after_timers` first. Both are timers of the node's (ROS) clock, each with a guard
// condition of its own in rcl. Spun by rclcpp::spin (or a MultiThreadedExecutor, `multi`): with every timer cancelled there
// is nothing left for the executor to wait for.
#include <chrono>
#include <memory>
#include <string>

#include "rclcpp/rclcpp.hpp"
#include "std_msgs/msg/string.hpp"

using namespace std::chrono_literals;

class CancelledTimers : public rclcpp::Node
{
public:
  CancelledTimers()
  : Node("cancelled_timers")
  {
    first_ = create_timer(100ms, [this]() {first_->cancel();});
    second_ = create_timer(
      250ms, [this]() {
        second_->cancel();
        after_ = create_publisher<std_msgs::msg::String>("after_timers", 10);
      });
  }

private:
  rclcpp::TimerBase::SharedPtr first_;
  rclcpp::TimerBase::SharedPtr second_;
  rclcpp::Publisher<std_msgs::msg::String>::SharedPtr after_;
};

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  auto node = std::make_shared<CancelledTimers>();
  // `multi`: spun by a MultiThreadedExecutor of two threads instead
  if (argc > 1 && std::string(argv[1]) == "multi") {
    rclcpp::executors::MultiThreadedExecutor executor(rclcpp::ExecutorOptions(), 2);
    executor.add_node(node);
    executor.spin();
  } else {
    rclcpp::spin(node);
  }
  rclcpp::shutdown();
  return 0;
}
