// main() of an executable that runs one node class until Ctrl-C (or SIGTERM).
// `--exit-after-setup` (before any --ros-args) constructs the node and ends the process at once
// without teardown, the way the recording middleware ends a settled process: the program's own
// set-up cost, which bench/bench_cpp_talker.py measures as its floor.
#ifndef SPIN_COMPONENT_HPP_
#define SPIN_COMPONENT_HPP_

#include <cstdlib>
#include <cstring>
#include <memory>

#include "rclcpp/rclcpp.hpp"

template<typename NodeT>
int spin_component(int argc, char ** argv)
{
  const bool setup_only = argc > 1 && std::strcmp(argv[1], "--exit-after-setup") == 0;
  rclcpp::init(argc, argv);
  auto node = std::make_shared<NodeT>(rclcpp::NodeOptions());
  if (setup_only) {
    std::_Exit(0);
  }
  rclcpp::spin(node);
  node.reset();
  rclcpp::shutdown();
  return 0;
}

#endif  // SPIN_COMPONENT_HPP_
