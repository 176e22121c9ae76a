// The talker executable: rmw_introspect_examples_cpp::Talker in a process of its own
#include "talker.hpp"
#include "spin_component.hpp"

int main(int argc, char ** argv)
{
  return spin_component<rmw_introspect_examples_cpp::Talker>(argc, argv);
}
