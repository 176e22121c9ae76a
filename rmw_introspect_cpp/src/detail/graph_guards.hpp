// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__GRAPH_GUARDS_HPP_
#define DETAIL__GRAPH_GUARDS_HPP_

#include <mutex>
#include <set>

#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

/// The graph guard conditions of the live nodes: all are triggered on every local graph
/// change (a real middleware triggers them on discovery; here only this process changes).
class GraphGuards
{
public:
  void add(GuardCondition * gc);
  void remove(GuardCondition * gc);
  /// Trigger every registered guard condition through `hub`.
  void trigger_all(WaitHub & hub);

private:
  std::mutex mutex_;
  std::set<GuardCondition *> guards_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__GRAPH_GUARDS_HPP_
