// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#ifndef DETAIL__DELIVERY_HPP_
#define DETAIL__DELIVERY_HPP_

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include "rmw/types.h"

namespace rmw_introspect
{

struct PublisherImpl;
struct SubscriptionImpl;
struct ServiceImpl;
struct ClientImpl;
struct EventSource;
struct Loans;
struct MessageLayout;
class Injector;
class WaitHub;

/// In-process delivery (RMW_INTROSPECT_DELIVERY=1): what a publisher publishes is copied (as
/// CDR, through each side's own type support) to every subscription of this process that
/// matches it - same topic and type, compatible QoS, its content filter passing, not ignoring
/// local publications of the same context - and a request to every matching service, whose
/// response goes back to the client that sent it. TRANSIENT_LOCAL publishers keep their last
/// `depth` samples for TRANSIENT_LOCAL subscriptions that come later. Matched events follow
/// the same matching. Nothing leaves the process: no socket, no shared memory, no thread.
///
/// Endpoints are registered here only when delivery is on, so with it off nothing changes.
/// What it delivers wakes the threads waiting in rmw_wait through `wait_hub`.
class Delivery
{
public:
  explicit Delivery(WaitHub & wait_hub)
  : wait_hub_(wait_hub)
  {
  }
  Delivery(const Delivery &) = delete;
  Delivery & operator=(const Delivery &) = delete;

  void add(PublisherImpl * publisher);
  void remove(PublisherImpl * publisher);
  void add(SubscriptionImpl * subscription);
  void remove(SubscriptionImpl * subscription);
  void add(ServiceImpl * service);
  void remove(ServiceImpl * service);
  void add(ClientImpl * client);
  void remove(ClientImpl * client);

  /// Publish `ros_message` (NULL for a serialized publish) whose CDR is `data`.
  void publish(
    PublisherImpl & publisher, const void * ros_message, const uint8_t * data, size_t size);
  /// A request `data` (CDR) with `sequence` from `client` to every matching service.
  void send_request(ClientImpl & client, int64_t sequence, std::vector<uint8_t> && data);
  /// A response to the client named in `request_id`, if it is still there.
  void send_response(
    ServiceImpl & service, const rmw_request_id_t & request_id, std::vector<uint8_t> && data);

private:
  void change_matched(PublisherImpl & publisher, SubscriptionImpl & subscription, int delta);
  void wake();

  WaitHub & wait_hub_;
  std::mutex mutex_;
  std::vector<PublisherImpl *> publishers_;
  std::vector<SubscriptionImpl *> subscriptions_;
  std::vector<ServiceImpl *> services_;
  std::vector<ClientImpl *> clients_;
};

/// The takes: the oldest sample, read into the caller's message through the taker's own type
/// support; `*taken = false` when there is none (always, with delivery off). RMW_RET_ERROR
/// when the sample cannot be read into that type.
rmw_ret_t take_message(
  SubscriptionImpl & subscription, void * ros_message, bool * taken, rmw_message_info_t * info);
rmw_ret_t take_serialized_message(
  SubscriptionImpl & subscription, rmw_serialized_message_t * serialized_message, bool * taken,
  rmw_message_info_t * info);
rmw_ret_t take_request(
  ServiceImpl & service, rmw_service_info_t * request_header, void * ros_request, bool * taken);
rmw_ret_t take_response(
  ClientImpl & client, rmw_service_info_t * request_header, void * ros_response, bool * taken);

/// Loans, with in-process delivery, for plain types (fixed size: no string, no sequence) as
/// on rmw_fastrtps_cpp: a loaned message is an initialised message of the endpoint's type.
bool can_loan(const MessageLayout & layout);
rmw_ret_t borrow_loaned_message(PublisherImpl & publisher, void ** ros_message);
/// Publish a message borrowed from `publisher` through `delivery` and take it back.
rmw_ret_t publish_loaned_message(
  Delivery & delivery, PublisherImpl & publisher, void * ros_message);
/// Take into a loaned message: a stimulus of `injector`'s first, then what the process sent.
rmw_ret_t take_loaned_message(
  Injector & injector, SubscriptionImpl & subscription, void ** loaned_message, bool * taken,
  rmw_message_info_t * info);
/// Give a loan back (RMW_RET_ERROR when `message` is not one of `loans`).
rmw_ret_t return_loaned_message(Loans & loans, const MessageLayout & layout, void * message);
/// Free the loans still out (the endpoint is being destroyed).
void free_loans(Loans & loans, const MessageLayout & layout);

/// rmw_wait: whether any entry of these arrays has something to take (reads atomics only;
/// a service also counts a request of the middleware's own, which needs no delivery).
bool any_ready(
  const rmw_subscriptions_t * subscriptions, const rmw_services_t * services,
  const rmw_clients_t * clients, const rmw_events_t * events);
/// rmw_wait, after waiting: set every entry that has nothing to take to NULL; true when an
/// entry stays.
bool keep_ready(
  rmw_subscriptions_t * subscriptions, rmw_services_t * services, rmw_clients_t * clients,
  rmw_events_t * events);

}  // namespace rmw_introspect

#endif  // DETAIL__DELIVERY_HPP_
