// Issue 50 item 1: threads parked in rmw_wait from the start must not make the main thread look
// idle while it waits on the real clock before it creates the rest. Run with
// `--ros-args -p use_sim_time:=true`, it has all three kinds of parked threads at once:
// rclcpp's sim-time clock thread, a tf2_ros::TransformListener's spin thread and a
// MultiThreadedExecutor spinning another node in a thread of its own. Its main thread then does
// what diagnostic_updater's example does: rclcpp::Rate(2).sleep() (a timed condition wait on the
// system clock, which the middleware does not step), then declares a parameter and creates a
// publisher, and loops on Rate(2).sleep(); publish; spin_some.
#include <chrono>
#include <memory>
#include <thread>

#include "rclcpp/rclcpp.hpp"
#include "std_msgs/msg/bool.hpp"
#include "std_msgs/msg/string.hpp"
#include "tf2_ros/buffer.h"
#include "tf2_ros/transform_listener.h"

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  auto node = std::make_shared<rclcpp::Node>("late_starter");
  tf2_ros::Buffer buffer(node->get_clock());
  tf2_ros::TransformListener listener(buffer);
  auto worker = std::make_shared<rclcpp::Node>("worker");
  auto work = worker->create_subscription<std_msgs::msg::String>(
    "work", 10, [](std_msgs::msg::String::ConstSharedPtr) {});
  rclcpp::executors::MultiThreadedExecutor executor(rclcpp::ExecutorOptions(), 2);
  executor.add_node(worker);
  std::thread spinner([&executor]() { executor.spin(); });
  auto topic1 = node->create_publisher<std_msgs::msg::Bool>("topic1", 1);
  rclcpp::Rate(2).sleep();
  node->declare_parameter("min_freq", 0.5);
  node->declare_parameter("max_freq", 2.0);
  auto later = node->create_publisher<std_msgs::msg::String>("after_rate", 10);
  while (rclcpp::ok()) {
    rclcpp::Rate(2).sleep();
    topic1->publish(std_msgs::msg::Bool());
    rclcpp::spin_some(node);
  }
  executor.cancel();
  spinner.join();
  rclcpp::shutdown();
  return 0;
}
