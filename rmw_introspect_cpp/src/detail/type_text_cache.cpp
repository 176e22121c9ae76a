// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/type_text_cache.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

namespace rmw_introspect
{

TypeTextCache::TypeTextCache(Render render)
: render_(std::move(render))
{
}

TypeTextCache::List & TypeTextCache::list_for(const TypeDescriptionsPtr & types)
{
  const auto found = lists_.find(types.get());
  if (found != lists_.end()) {
    return found->second;
  }
  List list;
  list.keep = types;
  list.texts.reserve(types->size());
  std::string text;
  for (const auto & type : *types) {
    text.clear();
    render_(type, &text);
    ++renders_;
    list.texts.push_back(&*texts_.insert(text).first);
  }
  return lists_.emplace(types.get(), std::move(list)).first->second;
}

const std::vector<TypeTextCache::Entry> & TypeTextCache::table(const RecorderSnapshot & snapshot)
{
  ++pass_;
  size_t seen = 0;
  table_.clear();
  for (const auto & e : snapshot.endpoints) {
    if (!e.types) {
      continue;
    }
    List & list = list_for(e.types);
    if (list.seen == pass_) {
      continue;  // a list shared by endpoints: its entries are in already
    }
    list.seen = pass_;
    ++seen;
    const TypeDescriptions & types = *list.keep;
    for (size_t k = 0; k < types.size(); ++k) {
      table_.push_back(Entry{types[k].name, list.texts[k]});
    }
  }
  // By name; of equal names the first listed stays (stable sort, then unique).
  std::stable_sort(
    table_.begin(), table_.end(), [](const Entry & a, const Entry & b) { return a.name < b.name; });
  table_.erase(
    std::unique(
      table_.begin(), table_.end(),
      [](const Entry & a, const Entry & b) { return a.name == b.name; }),
    table_.end());
  if (lists_.size() > seen) {
    for (auto it = lists_.begin(); it != lists_.end();) {
      it = it->second.seen == pass_ ? std::next(it) : lists_.erase(it);
    }
  }
  return table_;
}

}  // namespace rmw_introspect
