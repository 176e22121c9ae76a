// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__TYPE_TEXT_CACHE_HPP_
#define DETAIL__TYPE_TEXT_CACHE_HPP_

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "detail/recorder.hpp"
#include "detail/type_description.hpp"

namespace rmw_introspect
{

/// The capture's `types` table with each entry rendered once: an endpoint's TypeDescriptions
/// are immutable once made (shared_ptr<const>), so the text of each is rendered the first
/// time a snapshot shows the list and reused by every later capture.
///
/// Keyed by the list's address; the cache holds a reference to each list it keys, so that
/// address cannot be freed and reused for another list while its texts are cached. Lists the
/// last snapshot no longer had are dropped; the recorder never forgets an endpoint, so in the
/// middleware this holds what the recorder holds anyway. Equal texts are stored once: the
/// texts are bounded by the distinct types the process ever describes.
///
/// Not thread-safe: one caller at a time (the runtime renders under its write_mutex_).
class TypeTextCache
{
public:
  /// Renders one type's entry (its value, not its name) onto the end of the string.
  using Render = std::function<void(const TypeDescription &, std::string *)>;

  struct Entry
  {
    std::string_view name;
    const std::string * text;
  };

  explicit TypeTextCache(Render render);
  TypeTextCache(const TypeTextCache &) = delete;
  TypeTextCache & operator=(const TypeTextCache &) = delete;

  /// Every type the snapshot's endpoints refer to, once per name (the first endpoint listing
  /// it wins), sorted by name. Valid until the next call.
  const std::vector<Entry> & table(const RecorderSnapshot & snapshot);

  size_t list_count() const { return lists_.size(); }
  size_t text_count() const { return texts_.size(); }
  /// How many type descriptions were rendered so far.
  uint64_t renders() const { return renders_; }

private:
  struct List
  {
    TypeDescriptionsPtr keep;  // pins the key's address
    std::vector<const std::string *> texts;  // one per description, in list order
    uint64_t seen = 0;  // the last table() call that saw it
  };

  List & list_for(const TypeDescriptionsPtr & types);

  Render render_;
  std::unordered_map<const TypeDescriptions *, List> lists_;
  std::unordered_set<std::string> texts_;  // node-based: element addresses are stable
  std::vector<Entry> table_;
  uint64_t pass_ = 0;
  uint64_t renders_ = 0;
};

}  // namespace rmw_introspect

#endif  // DETAIL__TYPE_TEXT_CACHE_HPP_
