// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
// TypeTextCache: each list of type descriptions rendered once, never a stale text.

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "detail/recorder.hpp"
#include "detail/type_text_cache.hpp"

using rmw_introspect::RecorderSnapshot;
using rmw_introspect::TypeDescription;
using rmw_introspect::TypeDescriptions;
using rmw_introspect::TypeTextCache;

namespace
{
// Renders "<name>:<first field's name>" and counts its calls.
struct CountingRender
{
  int * calls;
  void operator()(const TypeDescription & type, std::string * out) const
  {
    ++*calls;
    *out += type.name + ":" + (type.fields.empty() ? "" : type.fields[0].name);
  }
};

TypeDescription message(const std::string & name, const std::string & field)
{
  TypeDescription type;
  type.name = name;
  type.fields = {{field, "int8", rmw_introspect::FieldArray::None, 0, 0}};
  return type;
}

std::shared_ptr<const TypeDescriptions> list(std::vector<TypeDescription> types)
{
  return std::make_shared<const TypeDescriptions>(std::move(types));
}

RecorderSnapshot snapshot_of(const std::vector<std::shared_ptr<const TypeDescriptions>> & lists)
{
  RecorderSnapshot snapshot;
  for (const auto & types : lists) {
    rmw_introspect::EndpointRecord e;
    e.types = types;
    snapshot.endpoints.push_back(e);
  }
  snapshot.endpoints.emplace_back();  // an endpoint without descriptions
  return snapshot;
}

std::string joined(const std::vector<TypeTextCache::Entry> & table)
{
  std::string out;
  for (const auto & entry : table) {
    out += std::string(entry.name) + "=" + *entry.text + ";";
  }
  return out;
}
}  // namespace

TEST(TypeTextCache, sorted_once_per_name_first_listing_wins)
{
  int calls = 0;
  TypeTextCache cache(CountingRender{&calls});
  const auto a = list({message("pkg/msg/B", "b"), message("pkg/msg/A", "a1")});
  const auto b = list({message("pkg/msg/A", "a2"), message("pkg/msg/C", "c")});
  EXPECT_EQ(
    "pkg/msg/A=pkg/msg/A:a1;pkg/msg/B=pkg/msg/B:b;pkg/msg/C=pkg/msg/C:c;",
    joined(cache.table(snapshot_of({a, b}))));
  EXPECT_EQ(
    "pkg/msg/A=pkg/msg/A:a2;pkg/msg/B=pkg/msg/B:b;pkg/msg/C=pkg/msg/C:c;",
    joined(cache.table(snapshot_of({b, a}))));
  EXPECT_EQ(4, calls);
  EXPECT_TRUE(cache.table(RecorderSnapshot{}).empty());
}

TEST(TypeTextCache, each_list_rendered_once_equal_texts_stored_once)
{
  int calls = 0;
  TypeTextCache cache(CountingRender{&calls});
  const auto a = list({message("pkg/msg/A", "x")});
  const auto same_content = list({message("pkg/msg/A", "x")});
  const std::string first = joined(cache.table(snapshot_of({a, a, same_content})));
  EXPECT_EQ("pkg/msg/A=pkg/msg/A:x;", first);
  EXPECT_EQ(2, calls);  // a (listed twice) and same_content
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(first, joined(cache.table(snapshot_of({a, a, same_content}))));
  }
  EXPECT_EQ(2, calls);
  EXPECT_EQ(2u, cache.list_count());
  EXPECT_EQ(1u, cache.text_count());
  EXPECT_EQ(2u, cache.renders());
}

TEST(TypeTextCache, keeps_what_it_keys_on_and_drops_lists_no_longer_shown)
{
  int calls = 0;
  TypeTextCache cache(CountingRender{&calls});
  auto kept = list({message("pkg/msg/A", "old")});
  const std::weak_ptr<const TypeDescriptions> watch = kept;
  cache.table(snapshot_of({kept}));
  kept.reset();
  // The cache holds the list it keys on: its address cannot be reused while it is cached.
  EXPECT_FALSE(watch.expired());
  const auto other = list({message("pkg/msg/A", "new"), message("pkg/msg/B", "b")});
  EXPECT_EQ(
    "pkg/msg/A=pkg/msg/A:new;pkg/msg/B=pkg/msg/B:b;", joined(cache.table(snapshot_of({other}))));
  // A list the last snapshot did not show is dropped.
  EXPECT_TRUE(watch.expired());
  EXPECT_EQ(1u, cache.list_count());
  EXPECT_EQ(3, calls);
}
