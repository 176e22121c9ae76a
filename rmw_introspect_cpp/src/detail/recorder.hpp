// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__RECORDER_HPP_
#define DETAIL__RECORDER_HPP_

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rmw/types.h"

#include "detail/node_probe.hpp"
#include "detail/type_description.hpp"

namespace rmw_introspect
{

using Gid = std::array<uint8_t, RMW_GID_STORAGE_SIZE>;

enum class EndpointKind { Publisher, Subscription, Service, Client };

const char * endpoint_kind_to_string(EndpointKind kind);

/// When an entity was created (or destroyed): its process's virtual and real age (ms since the
/// first rmw_init).
struct CreationTime
{
  double virtual_ms = 0.0;
  double real_ms = 0.0;
};

struct NodeRecord
{
  uint64_t id = 0;
  uint64_t seq = 0;
  std::string name;
  std::string namespace_;
  std::string fqn;
  std::string enclave;
  CreationTime created;
  bool destroyed = false;  // destroyed while the process was running (reported)
  bool alive = true;       // not destroyed at all, teardown included (graph queries)
  uint64_t destroyed_event = 0;  // place of the destruction in the event sequence
  CreationTime destroyed_at;     // when it was destroyed (reported destructions only)
  bool in_teardown = false;      // destroyed in the final run of destructions (snapshot)
  /// What the middleware learnt from the node's own services (NULL: not asked).
  std::shared_ptr<const NodeProbe> probe;
  /// The lifecycle transition the middleware drove on it last ("" = none).
  std::string transition;
};

struct EndpointRecord
{
  uint64_t id = 0;
  uint64_t seq = 0;
  EndpointKind kind = EndpointKind::Publisher;
  uint64_t node_id = 0;
  std::string node_name;
  std::string node_namespace;
  std::string node_fqn;
  std::string name;
  std::string type;
  std::string type_hash;
  std::string typesupport;
  TypeDescriptionsPtr types;  // the capture's `types` table is made of these (may be null)
  rmw_qos_profile_t qos{};         // as requested: what the capture reports
  rmw_qos_profile_t actual_qos{};  // as resolved (rmw_*_get_actual_qos): what matching uses
  Gid gid{};
  CreationTime created;
  bool destroyed = false;  // destroyed while the process was running (reported)
  bool alive = true;       // not destroyed at all, teardown included (graph queries)
  uint64_t destroyed_event = 0;  // place of the destruction in the event sequence
  CreationTime destroyed_at;     // when it was destroyed (reported destructions only)
  bool in_teardown = false;      // destroyed in the final run of destructions (snapshot)
  /// What the middleware was doing when it was created: the stimulus it was delivering
  /// ("stimulus:/camera_info", until the process settled again), else the lifecycle
  /// transition it had driven last on its node ("configure", "activate"); "" = none.
  std::string created_in;
};

/// A consistent copy of everything recorded, for writers and graph queries.
struct RecorderSnapshot
{
  uint64_t generation = 0;
  std::vector<NodeRecord> nodes;
  std::vector<EndpointRecord> endpoints;
};

/// "/" + name, or namespace + "/" + name.
std::string make_fqn(const std::string & namespace_, const std::string & name);

/// Thread-safe model of the nodes and endpoints of this process, in creation order.
/// Every string is copied: callers may free theirs right after the call.
class Recorder
{
public:
  Recorder();
  Recorder(const Recorder &) = delete;
  Recorder & operator=(const Recorder &) = delete;

  /// Called (without the recorder lock held) after every change.
  void set_change_listener(std::function<void()> listener);

  uint64_t add_node(
    const char * name, const char * namespace_, const char * enclave,
    const CreationTime & created = CreationTime());
  /// Mark a node destroyed, and every endpoint of it not destroyed yet. A `teardown`
  /// destruction (after rmw_shutdown of its context, or while the process/interpreter exits)
  /// only removes them from the graph: the capture keeps `destroyed: false`, since it says
  /// nothing about the node's interface.
  /// `when`: the process's age at the destruction (kept for a reported destruction: the
  /// capture lists what the program destroyed, with its age, as part of its interface).
  bool destroy_node(
    uint64_t node_id, bool teardown = false, const CreationTime & when = CreationTime());

  /// Adds an endpoint of a live node; fills id, seq, gid and the node fields.
  /// Returns 0 when the node is unknown.
  uint64_t add_endpoint(EndpointRecord record);
  bool destroy_endpoint(
    uint64_t endpoint_id, bool teardown = false, const CreationTime & when = CreationTime());

  /// Keep what the middleware learnt from node `node_id`'s own services. Not a change of
  /// the graph (no listener call): the next capture written carries it.
  bool set_node_probe(uint64_t node_id, const NodeProbe & probe);
  /// The middleware drives lifecycle transition `label` on node `node_id`: the endpoints
  /// the node creates from now on record it as their created_in. Not a change either.
  bool set_node_transition(uint64_t node_id, const std::string & label);
  /// The middleware is delivering stimulus `label` to the process ("" = nothing): endpoints
  /// created meanwhile, on any node, record it as their created_in (before their node's
  /// transition). Not a change either.
  void set_cause(const std::string & label);

  /// With `mark_teardown` (captures written as the process ends): the entities destroyed in
  /// the trailing run of destructions - the longest suffix of the creation/destruction event
  /// sequence without a creation - get `in_teardown`.
  RecorderSnapshot snapshot(bool mark_teardown = false) const;
  uint64_t generation() const;

  /// Run `fn(nodes, endpoints)` under the lock (for graph queries that only read). A template,
  /// not a std::function: a matched count must not allocate (test_rmw_implementation checks
  /// rmw_publisher_count_matched_subscriptions under osrf_testing_tools_cpp's memory checks).
  template<typename Fn>
  void visit(Fn && fn) const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    fn(
      static_cast<const std::vector<NodeRecord> &>(nodes_),
      static_cast<const std::vector<EndpointRecord> &>(endpoints_));
  }

  Gid new_gid();

private:
  void notify();

  mutable std::mutex mutex_;
  std::vector<NodeRecord> nodes_;
  std::vector<EndpointRecord> endpoints_;
  uint64_t seq_ = 0;
  uint64_t event_ = 0;           // creations and (reported) destructions
  uint64_t last_creation_event_ = 0;
  uint64_t generation_ = 0;
  uint64_t gid_counter_ = 0;
  std::string cause_;  // set_cause
  std::array<uint8_t, 8> gid_prefix_{};
  std::mutex listener_mutex_;
  std::function<void()> listener_;
};

}  // namespace rmw_introspect

#endif  // DETAIL__RECORDER_HPP_
