// fibonacci_server: an rclcpp_action server `fibonacci` (test_msgs/action/Fibonacci, a type
// the PyPI wheels carry). Accepts every goal and computes the sequence up to its `order`.
#include <memory>
#include <thread>

#include "rclcpp/rclcpp.hpp"
#include "rclcpp_action/rclcpp_action.hpp"
#include "test_msgs/action/fibonacci.hpp"

using Fibonacci = test_msgs::action::Fibonacci;
using GoalHandle = rclcpp_action::ServerGoalHandle<Fibonacci>;

class FibonacciServer : public rclcpp::Node
{
public:
  FibonacciServer()
  : Node("fibonacci_server")
  {
    server_ = rclcpp_action::create_server<Fibonacci>(
      this, "fibonacci",
      [](const rclcpp_action::GoalUUID &, std::shared_ptr<const Fibonacci::Goal> goal) {
        return goal->order < 0 ? rclcpp_action::GoalResponse::REJECT :
                                 rclcpp_action::GoalResponse::ACCEPT_AND_EXECUTE;
      },
      [](const std::shared_ptr<GoalHandle>) { return rclcpp_action::CancelResponse::ACCEPT; },
      [](const std::shared_ptr<GoalHandle> handle) { std::thread(execute, handle).detach(); });
  }

private:
  static void execute(const std::shared_ptr<GoalHandle> handle)
  {
    auto result = std::make_shared<Fibonacci::Result>();
    auto feedback = std::make_shared<Fibonacci::Feedback>();
    const int32_t order = handle->get_goal()->order;
    for (int32_t i = 0; i < order; ++i) {
      if (handle->is_canceling()) {
        handle->canceled(result);
        return;
      }
      const int32_t next = i < 2 ? i : feedback->sequence[i - 1] + feedback->sequence[i - 2];
      feedback->sequence.push_back(next);
      handle->publish_feedback(feedback);
    }
    result->sequence = feedback->sequence;
    handle->succeed(result);
  }

  rclcpp_action::Server<Fibonacci>::SharedPtr server_;
};

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  rclcpp::spin(std::make_shared<FibonacciServer>());
  rclcpp::shutdown();
  return 0;
}
