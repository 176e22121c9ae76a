// Copyright 2025 pytest-rmw-introspect contributors. Apache License 2.0.
#include "detail/delivery.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "rcutils/time.h"
#include "rmw/error_handling.h"
#include "rmw/event.h"
#include "rmw/serialized_message.h"

#include "detail/common.hpp"
#include "detail/handles.hpp"
#include "detail/identifier.hpp"
#include "detail/injector.hpp"
#include "detail/members.hpp"
#include "detail/qos.hpp"
#include "detail/wait_hub.hpp"

namespace rmw_introspect
{

namespace
{

int64_t now_ns()
{
  rcutils_time_point_value_t now = 0;
  if (rcutils_system_time_now(&now) != RCUTILS_RET_OK) {
    return 0;
  }
  return now;
}

bool topic_match(const PublisherImpl & publisher, const SubscriptionImpl & subscription)
{
  return publisher.name == subscription.name && publisher.type.name == subscription.type.name &&
    qos_match(publisher.actual_qos, subscription.actual_qos);
}

bool request_match(const ClientImpl & client, const ServiceImpl & service)
{
  return client.name == service.name && client.type.name == service.type.name &&
    qos_match(
           service_actual_qos(client.qos, QosSide::kWriter),
           service_actual_qos(service.qos, QosSide::kReader));
}

bool response_match(const ServiceImpl & service, const ClientImpl & client)
{
  return qos_match(
    service_actual_qos(service.qos, QosSide::kWriter),
    service_actual_qos(client.qos, QosSide::kReader));
}

bool transient_local(const rmw_qos_profile_t & qos)
{
  return qos.durability == RMW_QOS_POLICY_DURABILITY_TRANSIENT_LOCAL;
}

size_t history_depth(const rmw_qos_profile_t & qos)
{
  return qos.history == RMW_QOS_POLICY_HISTORY_KEEP_ALL ? 0u : std::max<size_t>(qos.depth, 1u);
}

/// An initialised instance of a message layout, finalised and freed when it goes.
class TemporaryMessage
{
public:
  explicit TemporaryMessage(const MessageLayout & layout)
  : layout_(layout), memory_(members::create_message(layout.members, layout.is_cpp))
  {
  }
  ~TemporaryMessage() { members::destroy_message(layout_.members, layout_.is_cpp, memory_); }
  TemporaryMessage(const TemporaryMessage &) = delete;
  TemporaryMessage & operator=(const TemporaryMessage &) = delete;

  void * get() const { return memory_; }

private:
  MessageLayout layout_;
  void * memory_ = nullptr;
};

/// Whether a sample passes the subscription's content filter. `ros_message` is the
/// publisher's own message (NULL after a serialized publish): used as it is when both sides
/// have the same type support, otherwise the CDR is read into a message of the subscription's.
bool passes_filter(
  SubscriptionImpl & subscription, const PublisherImpl * publisher, const void * ros_message,
  const uint8_t * data, size_t size)
{
  return subscription.filter.passes([&](const ContentFilter & filter) {
    if (ros_message != nullptr && publisher != nullptr &&
        publisher->layout.members == subscription.layout.members)
    {
      return filter.matches(ros_message);
    }
    TemporaryMessage message(subscription.layout);
    if (message.get() == nullptr) {
      return true;
    }
    std::string error;
    if (!cdr_deserialize(subscription.layout, data, size, message.get(), &error)) {
      return true;
    }
    return filter.matches(message.get());
  });
}

void deliver(SubscriptionImpl & subscription, const Sample & sample)
{
  Sample copy = sample;
  copy.message_info.received_timestamp = now_ns();
  copy.message_info.reception_sequence_number =
    static_cast<uint64_t>(subscription.next_reception.fetch_add(1));
  subscription.inbox.push(std::move(copy));
  subscription.on_new_message.notify(1u);
}

void copy_gid(const Gid & gid, rmw_gid_t * out)
{
  out->implementation_identifier = kIdentifier;
  std::memset(out->data, 0, sizeof(out->data));
  std::memcpy(out->data, gid.data(), std::min(sizeof(out->data), gid.size()));
}

template<typename T>
void erase(std::vector<T *> * items, T * item)
{
  items->erase(std::remove(items->begin(), items->end(), item), items->end());
}

}  // namespace

void Delivery::wake()
{
  wait_hub_.update_and_wake([]() {});
}

void Delivery::change_matched(PublisherImpl & publisher, SubscriptionImpl & subscription, int delta)
{
  publisher.matched.change(delta);
  subscription.matched.change(delta);
  publisher.event_callbacks[RMW_EVENT_PUBLICATION_MATCHED].notify(1u);
  subscription.event_callbacks[RMW_EVENT_SUBSCRIPTION_MATCHED].notify(1u);
}

void Delivery::add(PublisherImpl * publisher)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    publishers_.push_back(publisher);
    publisher->delivered.store(true);
    for (SubscriptionImpl * subscription : subscriptions_) {
      if (topic_match(*publisher, *subscription)) {
        change_matched(*publisher, *subscription, +1);
      }
    }
  }
  wake();
}

void Delivery::remove(PublisherImpl * publisher)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    erase(&publishers_, publisher);
    for (SubscriptionImpl * subscription : subscriptions_) {
      if (topic_match(*publisher, *subscription)) {
        change_matched(*publisher, *subscription, -1);
      }
    }
  }
  wake();
}

void Delivery::add(SubscriptionImpl * subscription)
{
  subscription->inbox.depth = history_depth(subscription->actual_qos);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    subscriptions_.push_back(subscription);
    subscription->delivered.store(true);
    for (PublisherImpl * publisher : publishers_) {
      if (!topic_match(*publisher, *subscription)) {
        continue;
      }
      change_matched(*publisher, *subscription, +1);
      // A late joiner gets what a TRANSIENT_LOCAL publisher kept.
      if (!transient_local(publisher->actual_qos) || !transient_local(subscription->actual_qos) ||
          (subscription->handle.options.ignore_local_publications &&
           publisher->node->context_impl == subscription->node->context_impl))
      {
        continue;
      }
      std::lock_guard<std::mutex> history_lock(publisher->history_mutex);
      for (const Sample & sample : publisher->history) {
        if (passes_filter(*subscription, nullptr, nullptr, sample.data.data(), sample.data.size()))
        {
          deliver(*subscription, sample);
        }
      }
    }
  }
  wake();
}

void Delivery::remove(SubscriptionImpl * subscription)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    erase(&subscriptions_, subscription);
    for (PublisherImpl * publisher : publishers_) {
      if (topic_match(*publisher, *subscription)) {
        change_matched(*publisher, *subscription, -1);
      }
    }
  }
  wake();
}

void Delivery::add(ServiceImpl * service)
{
  service->requests.depth = history_depth(service_actual_qos(service->qos, QosSide::kReader));
  std::lock_guard<std::mutex> lock(mutex_);
  services_.push_back(service);
}

void Delivery::remove(ServiceImpl * service)
{
  std::lock_guard<std::mutex> lock(mutex_);
  erase(&services_, service);
}

void Delivery::add(ClientImpl * client)
{
  client->responses.depth = history_depth(service_actual_qos(client->qos, QosSide::kReader));
  std::lock_guard<std::mutex> lock(mutex_);
  clients_.push_back(client);
}

void Delivery::remove(ClientImpl * client)
{
  std::lock_guard<std::mutex> lock(mutex_);
  erase(&clients_, client);
}

void Delivery::publish(
  PublisherImpl & publisher, const void * ros_message, const uint8_t * data, size_t size)
{
  Sample sample;
  sample.data.assign(data, data + size);
  copy_gid(publisher.gid, &sample.message_info.publisher_gid);
  sample.message_info.publication_sequence_number =
    static_cast<uint64_t>(publisher.next_sequence.fetch_add(1));
  sample.message_info.source_timestamp = now_ns();
  sample.message_info.from_intra_process = false;  // as rmw_fastrtps_cpp says
  bool delivered = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (SubscriptionImpl * subscription : subscriptions_) {
      if (!topic_match(publisher, *subscription)) {
        continue;
      }
      if (subscription->handle.options.ignore_local_publications &&
          publisher.node->context_impl == subscription->node->context_impl)
      {
        continue;  // "local" = the same context (one DDS participant per context)
      }
      if (!passes_filter(*subscription, &publisher, ros_message, data, size)) {
        continue;
      }
      deliver(*subscription, sample);
      delivered = true;
    }
    if (transient_local(publisher.actual_qos)) {
      std::lock_guard<std::mutex> history_lock(publisher.history_mutex);
      const size_t depth = history_depth(publisher.actual_qos);
      const size_t limit = depth > 0 ? depth : Inbox::kKeepAllLimit;
      while (publisher.history.size() >= limit) {
        publisher.history.pop_front();
      }
      publisher.history.push_back(std::move(sample));
    }
  }
  if (delivered) {
    wake();
  }
}

void Delivery::send_request(ClientImpl & client, int64_t sequence, std::vector<uint8_t> && data)
{
  Sample sample;
  sample.data = std::move(data);
  static_assert(
    sizeof(sample.service_info.request_id.writer_guid) == RMW_GID_STORAGE_SIZE,
    "a client's GID is its writer GUID");
  std::memcpy(
    sample.service_info.request_id.writer_guid, client.gid.data(),
    sizeof(sample.service_info.request_id.writer_guid));
  sample.service_info.request_id.sequence_number = sequence;
  sample.service_info.source_timestamp = now_ns();
  bool delivered = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (ServiceImpl * service : services_) {
      if (!request_match(client, *service)) {
        continue;
      }
      Sample copy = sample;
      copy.service_info.received_timestamp = now_ns();
      service->requests.push(std::move(copy));
      service->on_new_request.notify(1u);
      delivered = true;
    }
  }
  if (delivered) {
    wake();
  }
}

void Delivery::send_response(
  ServiceImpl & service, const rmw_request_id_t & request_id, std::vector<uint8_t> && data)
{
  bool delivered = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (ClientImpl * client : clients_) {
      if (std::memcmp(client->gid.data(), request_id.writer_guid, sizeof(request_id.writer_guid)) !=
          0)
      {
        continue;
      }
      if (!response_match(service, *client)) {
        break;
      }
      Sample sample;
      sample.data = std::move(data);
      sample.service_info.request_id = request_id;
      sample.service_info.source_timestamp = now_ns();
      sample.service_info.received_timestamp = sample.service_info.source_timestamp;
      client->responses.push(std::move(sample));
      client->on_new_response.notify(1u);
      delivered = true;
      break;
    }
  }
  if (delivered) {
    wake();
  }
}

namespace
{

rmw_ret_t read_into(
  const MessageLayout & layout, const Sample & sample, void * message, const char * what)
{
  std::string error;
  if (!cdr_deserialize(layout, sample.data.data(), sample.data.size(), message, &error)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("cannot read the %s taken: %s", what, error.c_str());
    return RMW_RET_ERROR;
  }
  return RMW_RET_OK;
}

}  // namespace

rmw_ret_t take_message(
  SubscriptionImpl & subscription, void * ros_message, bool * taken, rmw_message_info_t * info)
{
  *taken = false;
  Sample sample;
  if (!subscription.inbox.pop(&sample)) {
    return RMW_RET_OK;
  }
  const rmw_ret_t ret = read_into(subscription.layout, sample, ros_message, "message");
  if (ret != RMW_RET_OK) {
    return ret;
  }
  if (info != nullptr) {
    *info = sample.message_info;
  }
  *taken = true;
  return RMW_RET_OK;
}

rmw_ret_t take_serialized_message(
  SubscriptionImpl & subscription, rmw_serialized_message_t * serialized_message, bool * taken,
  rmw_message_info_t * info)
{
  *taken = false;
  Sample sample;
  if (!subscription.inbox.pop(&sample)) {
    return RMW_RET_OK;
  }
  if (serialized_message->buffer_capacity < sample.data.size()) {
    const rmw_ret_t ret = rmw_serialized_message_resize(serialized_message, sample.data.size());
    if (ret != RMW_RET_OK) {
      return ret;
    }
  }
  std::memcpy(serialized_message->buffer, sample.data.data(), sample.data.size());
  serialized_message->buffer_length = sample.data.size();
  if (info != nullptr) {
    *info = sample.message_info;
  }
  *taken = true;
  return RMW_RET_OK;
}

rmw_ret_t take_request(
  ServiceImpl & service, rmw_service_info_t * request_header, void * ros_request, bool * taken)
{
  *taken = false;
  Sample sample;
  if (!service.requests.pop(&sample)) {
    return RMW_RET_OK;
  }
  const rmw_ret_t ret = read_into(service.request_layout, sample, ros_request, "request");
  if (ret != RMW_RET_OK) {
    return ret;
  }
  *request_header = sample.service_info;
  *taken = true;
  return RMW_RET_OK;
}

rmw_ret_t take_response(
  ClientImpl & client, rmw_service_info_t * request_header, void * ros_response, bool * taken)
{
  *taken = false;
  Sample sample;
  if (!client.responses.pop(&sample)) {
    return RMW_RET_OK;
  }
  const rmw_ret_t ret = read_into(client.response_layout, sample, ros_response, "response");
  if (ret != RMW_RET_OK) {
    return ret;
  }
  *request_header = sample.service_info;
  *taken = true;
  return RMW_RET_OK;
}

bool can_loan(const MessageLayout & layout)
{
  if (layout.members == nullptr) {
    return false;
  }
  return introspection::with_traits(layout, [](auto traits, const auto * members) {
    return members::is_plain<decltype(traits)>(members);
  });
}

namespace
{

void * lend(Loans & loans, const MessageLayout & layout)
{
  void * message = members::create_message(layout.members, layout.is_cpp);
  if (message != nullptr) {
    std::lock_guard<std::mutex> lock(loans.mutex);
    loans.out.insert(message);
  }
  return message;
}

bool is_lent(Loans & loans, void * message)
{
  std::lock_guard<std::mutex> lock(loans.mutex);
  return loans.out.count(message) != 0u;
}

}  // namespace

rmw_ret_t borrow_loaned_message(PublisherImpl & publisher, void ** ros_message)
{
  *ros_message = lend(publisher.loans, publisher.layout);
  if (*ros_message == nullptr) {
    RMW_SET_ERROR_MSG("failed to allocate a loaned message");
    return RMW_RET_BAD_ALLOC;
  }
  return RMW_RET_OK;
}

rmw_ret_t publish_loaned_message(Delivery & delivery, PublisherImpl & publisher, void * ros_message)
{
  if (!is_lent(publisher.loans, ros_message)) {
    RMW_SET_ERROR_MSG("ros_message was not loaned by this publisher");
    return RMW_RET_INVALID_ARGUMENT;
  }
  std::vector<uint8_t> data;
  std::string error;
  rmw_ret_t ret = RMW_RET_OK;
  if (!cdr_serialize(publisher.layout, ros_message, &data, &error)) {
    RMW_SET_ERROR_MSG_WITH_FORMAT_STRING("cannot serialize the message: %s", error.c_str());
    ret = RMW_RET_ERROR;
  } else {
    delivery.publish(publisher, ros_message, data.data(), data.size());
  }
  // Published or not, the loan ends here (rmw.h: the message must not be used afterwards).
  const rmw_ret_t returned = return_loaned_message(publisher.loans, publisher.layout, ros_message);
  return ret != RMW_RET_OK ? ret : returned;
}

rmw_ret_t take_loaned_message(
  Injector & injector, SubscriptionImpl & subscription, void ** loaned_message, bool * taken,
  rmw_message_info_t * info)
{
  *taken = false;
  if (subscription.inbox.count.load() == 0u && !Injector::ready(&subscription)) {
    return RMW_RET_OK;
  }
  void * message = lend(subscription.loans, subscription.layout);
  if (message == nullptr) {
    RMW_SET_ERROR_MSG("failed to allocate a loaned message");
    return RMW_RET_BAD_ALLOC;
  }
  // A stimulus of the middleware's own first, then what the process sent.
  const rmw_ret_t ret = injector.take_message(&subscription, message, taken, info) ?
    RMW_RET_OK :
    take_message(subscription, message, taken, info);
  if (ret != RMW_RET_OK || !*taken) {
    rmw_introspect::ignore_result(
      return_loaned_message(subscription.loans, subscription.layout, message));
    return ret;
  }
  *loaned_message = message;
  return RMW_RET_OK;
}

rmw_ret_t return_loaned_message(Loans & loans, const MessageLayout & layout, void * message)
{
  {
    std::lock_guard<std::mutex> lock(loans.mutex);
    if (loans.out.erase(message) == 0u) {
      RMW_SET_ERROR_MSG("the message was not loaned by this publisher or subscription");
      return RMW_RET_ERROR;
    }
  }
  members::destroy_message(layout.members, layout.is_cpp, message);
  return RMW_RET_OK;
}

void free_loans(Loans & loans, const MessageLayout & layout)
{
  std::set<void *> out;
  {
    std::lock_guard<std::mutex> lock(loans.mutex);
    out.swap(loans.out);
  }
  for (void * message : out) {
    members::destroy_message(layout.members, layout.is_cpp, message);
  }
}

// A service has something to take: a request of a client of the process (delivery) or one of
// the middleware's own (parameters, lifecycle, stimuli: Injector), which needs no delivery.
namespace
{
bool has_request(const ServiceImpl * service)
{
  return service != nullptr && (service->requests.count.load() > 0u || Injector::ready(service));
}

// A subscription has something to take: a message of a publisher of the process (delivery)
// or a stimulus of the middleware's own (Injector), which needs no delivery.
bool has_message(const SubscriptionImpl * subscription)
{
  return subscription != nullptr &&
    (subscription->inbox.count.load() > 0u || Injector::ready(subscription));
}
}  // namespace

bool any_ready(
  const rmw_subscriptions_t * subscriptions, const rmw_services_t * services,
  const rmw_clients_t * clients, const rmw_events_t * events)
{
  if (subscriptions != nullptr) {
    for (size_t i = 0; i < subscriptions->subscriber_count; ++i) {
      const auto * s = static_cast<const SubscriptionImpl *>(subscriptions->subscribers[i]);
      if (has_message(s)) {
        return true;
      }
    }
  }
  if (services != nullptr) {
    for (size_t i = 0; i < services->service_count; ++i) {
      const auto * s = static_cast<const ServiceImpl *>(services->services[i]);
      if (has_request(s)) {
        return true;
      }
    }
  }
  if (clients != nullptr) {
    for (size_t i = 0; i < clients->client_count; ++i) {
      const auto * c = static_cast<const ClientImpl *>(clients->clients[i]);
      if (c != nullptr && c->responses.count.load() > 0u) {
        return true;
      }
    }
  }
  if (events != nullptr) {
    for (size_t i = 0; i < events->event_count; ++i) {
      const auto * e = static_cast<const rmw_event_t *>(events->events[i]);
      if (e == nullptr || e->data == nullptr) {
        continue;
      }
      if ((e->event_type == RMW_EVENT_PUBLICATION_MATCHED ||
           e->event_type == RMW_EVENT_SUBSCRIPTION_MATCHED) &&
          static_cast<const EventSource *>(e->data)->matched.unread.load())
      {
        return true;
      }
    }
  }
  return false;
}

bool keep_ready(
  rmw_subscriptions_t * subscriptions, rmw_services_t * services, rmw_clients_t * clients,
  rmw_events_t * events)
{
  bool kept = false;
  auto keep = [&kept](void ** entry, bool ready) {
    if (ready) {
      kept = true;
    } else {
      *entry = nullptr;
    }
  };
  if (subscriptions != nullptr && subscriptions->subscribers != nullptr) {
    for (size_t i = 0; i < subscriptions->subscriber_count; ++i) {
      const auto * s = static_cast<const SubscriptionImpl *>(subscriptions->subscribers[i]);
      keep(&subscriptions->subscribers[i], has_message(s));
    }
  }
  if (services != nullptr && services->services != nullptr) {
    for (size_t i = 0; i < services->service_count; ++i) {
      const auto * s = static_cast<const ServiceImpl *>(services->services[i]);
      keep(&services->services[i], has_request(s));
    }
  }
  if (clients != nullptr && clients->clients != nullptr) {
    for (size_t i = 0; i < clients->client_count; ++i) {
      const auto * c = static_cast<const ClientImpl *>(clients->clients[i]);
      keep(&clients->clients[i], c != nullptr && c->responses.count.load() > 0u);
    }
  }
  if (events != nullptr && events->events != nullptr) {
    for (size_t i = 0; i < events->event_count; ++i) {
      const auto * e = static_cast<const rmw_event_t *>(events->events[i]);
      const bool ready = e != nullptr && e->data != nullptr &&
        (e->event_type == RMW_EVENT_PUBLICATION_MATCHED ||
         e->event_type == RMW_EVENT_SUBSCRIPTION_MATCHED) &&
        static_cast<const EventSource *>(e->data)->matched.unread.load();
      keep(&events->events[i], ready);
    }
  }
  return kept;
}

}  // namespace rmw_introspect
