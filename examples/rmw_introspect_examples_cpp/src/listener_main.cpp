// The listener executable: rmw_introspect_examples_cpp::Listener in a process of its own
#include "listener.hpp"
#include "spin_component.hpp"

int main(int argc, char ** argv)
{
  return spin_component<rmw_introspect_examples_cpp::Listener>(argc, argv);
}
