// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__INBOX_HPP_
#define DETAIL__INBOX_HPP_

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

#include "rmw/events_statuses/matched.h"
#include "rmw/types.h"

namespace rmw_introspect
{

/// One message, request or response on its way inside the process: CDR bytes (see cdr.hpp)
/// and what the taker is told about it.
struct Sample
{
  std::vector<uint8_t> data;
  rmw_message_info_t message_info{};   // messages
  rmw_service_info_t service_info{};   // requests and responses
};

/// What a subscription, service or client has received and not taken yet. `count` mirrors
/// the queue's size for rmw_wait, which must not take the mutex.
struct Inbox
{
  std::mutex mutex;
  std::deque<Sample> samples;
  std::atomic<size_t> count{0};
  size_t depth = 0;  // KEEP_LAST depth; 0 = KEEP_ALL (bounded by kKeepAllLimit)

  static constexpr size_t kKeepAllLimit = 100000;

  /// Queue a sample, the oldest going when the history is full.
  void push(Sample && sample)
  {
    std::lock_guard<std::mutex> lock(mutex);
    const size_t limit = depth > 0 ? depth : kKeepAllLimit;
    while (samples.size() >= limit) {
      samples.pop_front();
    }
    samples.push_back(std::move(sample));
    count.store(samples.size());
  }
  /// The oldest sample, if any.
  bool pop(Sample * out)
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (samples.empty()) {
      return false;
    }
    *out = std::move(samples.front());
    samples.pop_front();
    count.store(samples.size());
    return true;
  }
  void clear()
  {
    std::lock_guard<std::mutex> lock(mutex);
    samples.clear();
    count.store(0);
  }
};

/// A publisher's PUBLICATION_MATCHED or a subscription's SUBSCRIPTION_MATCHED status: the
/// changes accumulate until rmw_take_event reads and resets them.
struct MatchedState
{
  std::mutex mutex;
  rmw_matched_status_t status{};
  std::atomic<bool> unread{false};

  void change(int delta)
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (delta > 0) {
      status.total_count += static_cast<size_t>(delta);
      status.total_count_change += static_cast<size_t>(delta);
    }
    status.current_count = static_cast<size_t>(static_cast<int64_t>(status.current_count) + delta);
    status.current_count_change += delta;
    unread.store(true);
  }
  rmw_matched_status_t take()
  {
    std::lock_guard<std::mutex> lock(mutex);
    const rmw_matched_status_t result = status;
    status.total_count_change = 0;
    status.current_count_change = 0;
    unread.store(false);
    return result;
  }
};

}  // namespace rmw_introspect

#endif  // DETAIL__INBOX_HPP_
