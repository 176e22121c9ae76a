// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/recorder.hpp"

#include <unistd.h>

#include <chrono>
#include <cstring>
#include <random>
#include <utility>

namespace rmw_introspect
{

const char * endpoint_kind_to_string(EndpointKind kind)
{
  switch (kind) {
    case EndpointKind::Publisher: return "publisher";
    case EndpointKind::Subscription: return "subscription";
    case EndpointKind::Service: return "service";
    case EndpointKind::Client: return "client";
  }
  return "unknown";
}

std::string make_fqn(const std::string & namespace_, const std::string & name)
{
  if (namespace_.empty() || namespace_ == "/") {
    return "/" + name;
  }
  if (namespace_.back() == '/') {
    return namespace_ + name;
  }
  return namespace_ + "/" + name;
}

Recorder::Recorder()
{
  // GID = 8 bytes unique to this recorder (pid + random) + 8 bytes counter.
  const uint32_t pid = static_cast<uint32_t>(getpid());
  std::random_device rd;
  const uint32_t salt =
    rd() ^ static_cast<uint32_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  std::memcpy(gid_prefix_.data(), &pid, 4);
  std::memcpy(gid_prefix_.data() + 4, &salt, 4);
}

void Recorder::set_change_listener(std::function<void()> listener)
{
  std::lock_guard<std::mutex> lock(listener_mutex_);
  listener_ = std::move(listener);
}

void Recorder::notify()
{
  std::function<void()> listener;
  {
    std::lock_guard<std::mutex> lock(listener_mutex_);
    listener = listener_;
  }
  if (listener) {
    listener();
  }
}

Gid Recorder::new_gid()
{
  std::lock_guard<std::mutex> lock(mutex_);
  Gid gid{};
  const uint64_t counter = ++gid_counter_;
  std::memcpy(gid.data(), gid_prefix_.data(), 8);
  for (size_t i = 0; i < 8; ++i) {
    gid[8 + i] = static_cast<uint8_t>(counter >> (8 * (7 - i)));
  }
  return gid;
}

uint64_t Recorder::add_node(
  const char * name, const char * namespace_, const char * enclave, const CreationTime & created)
{
  NodeRecord record;
  record.name = name ? name : "";
  record.namespace_ = namespace_ ? namespace_ : "";
  record.fqn = make_fqn(record.namespace_, record.name);
  record.enclave = enclave ? enclave : "/";
  record.created = created;
  uint64_t id = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    record.seq = ++seq_;
    last_creation_event_ = ++event_;
    record.id = nodes_.size() + 1;
    id = record.id;
    nodes_.push_back(std::move(record));
    ++generation_;
  }
  notify();
  return id;
}

bool Recorder::destroy_node(uint64_t node_id, bool teardown, const CreationTime & when)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (node_id == 0 || node_id > nodes_.size() || !nodes_[node_id - 1].alive) {
      return false;
    }
    nodes_[node_id - 1].alive = false;
    const uint64_t event = teardown ? 0 : ++event_;
    for (auto & endpoint : endpoints_) {
      if (endpoint.node_id == node_id && endpoint.alive) {
        endpoint.alive = false;
        endpoint.destroyed = !teardown;
        endpoint.destroyed_event = event;
        endpoint.destroyed_at = when;
      }
    }
    if (teardown) {
      return true;  // nothing reported changes
    }
    nodes_[node_id - 1].destroyed = true;
    nodes_[node_id - 1].destroyed_event = event;
    nodes_[node_id - 1].destroyed_at = when;
    ++generation_;
  }
  notify();
  return true;
}

uint64_t Recorder::add_endpoint(EndpointRecord record)
{
  uint64_t id = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (record.node_id == 0 || record.node_id > nodes_.size()) {
      return 0;
    }
    record.destroyed = false;
    record.alive = true;
    const NodeRecord & node = nodes_[record.node_id - 1];
    record.node_name = node.name;
    record.node_namespace = node.namespace_;
    record.node_fqn = node.fqn;
    record.created_in = cause_.empty() ? node.transition : cause_;
    record.seq = ++seq_;
    last_creation_event_ = ++event_;
    record.id = endpoints_.size() + 1;
    id = record.id;
    endpoints_.push_back(std::move(record));
    ++generation_;
  }
  notify();
  return id;
}

bool Recorder::destroy_endpoint(uint64_t endpoint_id, bool teardown, const CreationTime & when)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (endpoint_id == 0 || endpoint_id > endpoints_.size() || !endpoints_[endpoint_id - 1].alive) {
      return false;
    }
    endpoints_[endpoint_id - 1].alive = false;
    if (teardown) {
      return true;
    }
    endpoints_[endpoint_id - 1].destroyed = true;
    endpoints_[endpoint_id - 1].destroyed_event = ++event_;
    endpoints_[endpoint_id - 1].destroyed_at = when;
    ++generation_;
  }
  notify();
  return true;
}

bool Recorder::set_node_probe(uint64_t node_id, const NodeProbe & probe)
{
  auto copy = std::make_shared<const NodeProbe>(probe);
  std::lock_guard<std::mutex> lock(mutex_);
  if (node_id == 0 || node_id > nodes_.size()) {
    return false;
  }
  nodes_[node_id - 1].probe = std::move(copy);
  return true;
}

bool Recorder::set_node_transition(uint64_t node_id, const std::string & label)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (node_id == 0 || node_id > nodes_.size()) {
    return false;
  }
  nodes_[node_id - 1].transition = label;
  return true;
}

void Recorder::set_cause(const std::string & label)
{
  std::lock_guard<std::mutex> lock(mutex_);
  cause_ = label;
}

RecorderSnapshot Recorder::snapshot(bool mark_teardown) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  RecorderSnapshot snap;
  snap.generation = generation_;
  snap.nodes = nodes_;
  snap.endpoints = endpoints_;
  if (mark_teardown) {
    auto mark = [this](auto & records) {
      for (auto & r : records) {
        r.in_teardown = r.destroyed && r.destroyed_event > last_creation_event_;
      }
    };
    mark(snap.nodes);
    mark(snap.endpoints);
  }
  return snap;
}

uint64_t Recorder::generation() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return generation_;
}

}  // namespace rmw_introspect
