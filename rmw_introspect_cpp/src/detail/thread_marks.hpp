// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__THREAD_MARKS_HPP_
#define DETAIL__THREAD_MARKS_HPP_

#include <sys/types.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rmw_introspect
{

/// The generation in which each thread last made an activity call, for up to kCapacity threads,
/// in storage fixed at construction. Marking runs inside calls the rmw API documents as not
/// allocating (rmw_publisher_count_matched_subscriptions and the other counts; real-time
/// executors call them): a std::map here allocated a 48-byte node the first time a thread
/// counted (test_rmw_implementation under memory checks, 2026-11-28), so nothing here may.
///
/// Only "marked in this generation" is ever asked, so a slot marked in an older generation is
/// free to reuse. When kCapacity threads were all active in the current generation a further
/// thread's mark is dropped: that thread then reads as not having used ROS (its sleep does not
/// prove the process idle and the quiet window decides), the safe side.
class ThreadMarks
{
public:
  static constexpr size_t kCapacity = 64;

  void mark(pid_t tid, uint64_t generation)
  {
    Slot * reusable = nullptr;
    for (Slot & slot : slots_) {
      if (slot.tid == tid) {
        slot.generation = generation;
        return;
      }
      if (reusable == nullptr && (slot.tid == 0 || slot.generation != generation)) {
        reusable = &slot;
      }
    }
    if (reusable != nullptr) {
      *reusable = Slot{tid, generation};
    }
  }

  /// Every thread marked in some generation, appended to `*tids` (the monitor asks: it may
  /// allocate).
  void collect(std::vector<pid_t> * tids) const
  {
    for (const Slot & slot : slots_) {
      if (slot.tid != 0) {
        tids->push_back(slot.tid);
      }
    }
  }

  bool marked(pid_t tid, uint64_t generation) const
  {
    for (const Slot & slot : slots_) {
      if (slot.tid == tid) {
        return slot.generation == generation;
      }
    }
    return false;
  }

private:
  struct Slot
  {
    pid_t tid = 0;
    uint64_t generation = 0;
  };
  std::array<Slot, kCapacity> slots_{};
};

}  // namespace rmw_introspect

#endif  // DETAIL__THREAD_MARKS_HPP_
