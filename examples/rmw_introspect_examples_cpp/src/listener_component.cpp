// rmw_introspect_examples_cpp::Listener as a component of talker_listener_components
#include "listener.hpp"
#include "rclcpp_components/register_node_macro.hpp"

RCLCPP_COMPONENTS_REGISTER_NODE(rmw_introspect_examples_cpp::Listener)
