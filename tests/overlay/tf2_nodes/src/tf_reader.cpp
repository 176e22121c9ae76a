// A node that reads TF the way most C++ nodes do: a tf2_ros::Buffer and a TransformListener
// with its default dedicated spin thread, which creates a node of its own named
// transform_listener_impl_<address of the listener>. `--two` adds a second listener (two such
// nodes in one process). Its own node, "tf_reader", looks a transform up once a second.
#include <chrono>
#include <cstring>
#include <memory>

#include "rclcpp/rclcpp.hpp"
#include "tf2_ros/buffer.h"
#include "tf2_ros/transform_listener.h"

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  bool two = false;
  for (int i = 1; i < argc; ++i) {
    two = two || std::strcmp(argv[i], "--two") == 0;
  }
  auto node = std::make_shared<rclcpp::Node>("tf_reader");
  tf2_ros::Buffer buffer(node->get_clock());
  tf2_ros::TransformListener listener(buffer);
  std::unique_ptr<tf2_ros::TransformListener> second;
  if (two) {
    second = std::make_unique<tf2_ros::TransformListener>(buffer);
  }
  auto timer = node->create_wall_timer(std::chrono::seconds(1), [&buffer]() {
      (void)buffer.canTransform("map", "base_link", tf2::TimePointZero);
    });
  rclcpp::spin(node);
  rclcpp::shutdown();
  return 0;
}
