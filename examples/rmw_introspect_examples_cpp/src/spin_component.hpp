// main() of an executable that runs one node class until Ctrl-C (or SIGTERM).
#ifndef SPIN_COMPONENT_HPP_
#define SPIN_COMPONENT_HPP_

#include <memory>

#include "rclcpp/rclcpp.hpp"

template<typename NodeT>
int spin_component(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  rclcpp::spin(std::make_shared<NodeT>(rclcpp::NodeOptions()));
  rclcpp::shutdown();
  return 0;
}

#endif  // SPIN_COMPONENT_HPP_
