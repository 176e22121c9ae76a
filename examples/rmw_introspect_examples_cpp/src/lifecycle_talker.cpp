// lifecycle_talker: an rclcpp_lifecycle node. Its publisher `lifecycle_chatter` (std_msgs/msg/String,
// depth 10) exists from `configure` on; it publishes only while active. Parameter `period`
// (double, seconds between messages). Lifecycle services and `transition_event` come with the node.
#include <chrono>
#include <memory>
#include <string>

#include "descriptors.hpp"
#include "rclcpp/rclcpp.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"
#include "std_msgs/msg/string.hpp"

using CallbackReturn = rclcpp_lifecycle::node_interfaces::LifecycleNodeInterface::CallbackReturn;

class LifecycleTalker : public rclcpp_lifecycle::LifecycleNode
{
public:
  LifecycleTalker()
  : LifecycleNode("lifecycle_talker")
  {
    declare_parameter(
      "period", 0.5,
      rmw_introspect_examples_cpp::described("seconds between messages while active"));
  }

  CallbackReturn on_configure(const rclcpp_lifecycle::State &) override
  {
    publisher_ = create_publisher<std_msgs::msg::String>("lifecycle_chatter", 10);
    const double period = get_parameter("period").as_double();
    timer_ = create_wall_timer(std::chrono::duration<double>(period), [this]() { on_timer(); });
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_activate(const rclcpp_lifecycle::State & state) override
  {
    LifecycleNode::on_activate(state);
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_deactivate(const rclcpp_lifecycle::State & state) override
  {
    LifecycleNode::on_deactivate(state);
    return CallbackReturn::SUCCESS;
  }

  CallbackReturn on_cleanup(const rclcpp_lifecycle::State &) override
  {
    timer_.reset();
    publisher_.reset();
    return CallbackReturn::SUCCESS;
  }

private:
  void on_timer()
  {
    if (publisher_ && publisher_->is_activated()) {
      std_msgs::msg::String message;
      message.data = "Lifecycle message " + std::to_string(count_++);
      publisher_->publish(message);
    }
  }

  size_t count_ = 0;
  rclcpp_lifecycle::LifecyclePublisher<std_msgs::msg::String>::SharedPtr publisher_;
  rclcpp::TimerBase::SharedPtr timer_;
};

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  auto node = std::make_shared<LifecycleTalker>();
  rclcpp::spin(node->get_node_base_interface());
  rclcpp::shutdown();
  return 0;
}
