// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__COMPONENT_LOADS_HPP_
#define DETAIL__COMPONENT_LOADS_HPP_

#include <cstdint>
#include <string>
#include <vector>

#include "detail/dynamic_value.hpp"
#include "detail/recorder.hpp"

namespace rmw_introspect
{

/// One composition_interfaces/srv/LoadNode request a launch file makes of a component
/// container (launch_ros's LoadComposableNodes), to be sent to the container's own
/// `~/_container/load_node` service through the Injector: the launch file's requests reach the
/// container without DDS.
struct ComponentLoad
{
  std::string service;  // "/my_container/_container/load_node"
  std::string plugin;   // the request's plugin_name (what the records name)
  std::string node;     // the request's node_name ("" = the component's own)
  DynValue request;     // the LoadNode request's content
};

/// RMW_INTROSPECT_LOAD_NODES names a file of requests, written by the Python side
/// (launch/component_loads.py): UTF-8 lines of tab-separated fields, each field escaped (`\\`,
/// `\t`, `\n`); `#` lines are comments. A request is
///
///   load <TAB> SERVICE
///   package_name | plugin_name | node_name | node_namespace <TAB> TEXT
///   log_level <TAB> NUMBER
///   remap_rule <TAB> RULE                       (once per rule, in order)
///   parameter | extra_argument <TAB> NAME <TAB> TYPE <TAB> VALUE...
///   end
///
/// TYPE is rcl_interfaces/msg/ParameterType's number (1 bool, 2 integer, 3 double, 4 string,
/// 6 bool array, 7 integer array, 8 double array, 9 string array); an array has one VALUE
/// field per item; booleans are `true`/`false`. A line that cannot be read adds a line to
/// `warnings` and leaves its request out.
std::vector<ComponentLoad> read_component_loads(
  const std::string & path, std::vector<std::string> * warnings);
/// The same from the file's text.
std::vector<ComponentLoad> parse_component_loads(
  const std::string & text, std::vector<std::string> * warnings);

/// What one request came to.
struct ComponentLoadRecord
{
  enum class Result {
    kPending,    // not sent yet
    kLoaded,     // the container answered success
    kRefused,    // the container answered failure (error: its error_message)
    kNoAnswer,   // no answer within the answer timeout
    kNoService,  // the process has no such service alive (error says what there is)
    kFailed,     // it could not be sent (error)
  };
  std::string service;
  std::string plugin;
  std::string node;          // the node_name asked for ("" = the component's own)
  Result result = Result::kPending;
  std::string full_node_name;  // the container's answer (loaded)
  std::string error;         // "" = none
};

const char * component_load_result_name(ComponentLoadRecord::Result result);

/// The requests in order, each sent once its turn comes to the service of its name alive in
/// the snapshot: a state machine with no thread, no lock and no middleware in it.
class ComponentLoadPlan
{
public:
  explicit ComponentLoadPlan(std::vector<ComponentLoad> loads);

  /// The next request to send and its service's endpoint id. False when none is left (a
  /// request whose service is not there is recorded kNoService and skipped).
  bool next(const RecorderSnapshot & snapshot, uint64_t * service_id, const ComponentLoad ** load);
  /// The LoadNode response to the request next() returned last.
  void on_answer(const DynValue & response);
  /// The request next() returned last got no answer (`timed_out`) or could not be sent.
  void on_failed(const std::string & why, bool timed_out);

  const std::vector<ComponentLoadRecord> & records() const { return records_; }

private:
  std::vector<ComponentLoad> loads_;
  std::vector<ComponentLoadRecord> records_;
  size_t next_ = 0;
};

}  // namespace rmw_introspect

#endif  // DETAIL__COMPONENT_LOADS_HPP_
