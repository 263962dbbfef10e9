#include "fleetnav/vda5050/mqtt_client.hpp"

#include <mosquitto.h>

#include <atomic>
#include <mutex>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/clock.h"

namespace fleetnav::vda5050 {
namespace {

/// libmosquitto's process-wide setup, once (it must precede every client).
void InitLibrary() {
  static std::once_flag once;
  std::call_once(once, [] { mosquitto_lib_init(); });
}

}  // namespace

struct MosquittoClient::Impl {
  mosquitto* client = nullptr;
  MqttMessageHandler on_message;
  MqttConnectHandler on_connect;
  absl::Mutex mutex;
  std::vector<std::pair<std::string, int>> subscriptions ABSL_GUARDED_BY(mutex);
  bool connected ABSL_GUARDED_BY(mutex) = false;
  int connections ABSL_GUARDED_BY(mutex) = 0;
  std::atomic<bool> disconnected{false};  ///< Disconnect() was called (any thread)

  ~Impl() {
    if (client != nullptr) {
      mosquitto_disconnect(client);
      mosquitto_loop_stop(client, /*force=*/false);
      mosquitto_destroy(client);
    }
  }

  static void OnConnect(mosquitto* client, void* self, int result) {
    auto* impl = static_cast<Impl*>(self);
    if (result != 0) return;  // refused: libmosquitto tries again
    std::vector<std::pair<std::string, int>> subscriptions;
    bool reconnected = false;
    {
      absl::MutexLock lock(&impl->mutex);
      impl->connected = true;
      reconnected = impl->connections++ > 0;
      subscriptions = impl->subscriptions;
    }
    for (const auto& [pattern, qos] : subscriptions) {
      mosquitto_subscribe(client, nullptr, pattern.c_str(), qos);
    }
    if (impl->on_connect) impl->on_connect(reconnected);
  }
  static void OnDisconnect(mosquitto* /*client*/, void* self, int /*reason*/) {
    auto* impl = static_cast<Impl*>(self);
    absl::MutexLock lock(&impl->mutex);
    impl->connected = false;
  }
  static void OnMessage(mosquitto* /*client*/, void* self, const mosquitto_message* message) {
    auto* impl = static_cast<Impl*>(self);
    if (impl->on_message == nullptr || message->topic == nullptr) return;
    impl->on_message(message->topic, std::string(static_cast<const char*>(message->payload),
                                                 static_cast<size_t>(message->payloadlen)));
  }
};

MosquittoClient::MosquittoClient(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

MosquittoClient::~MosquittoClient() = default;

absl::StatusOr<std::unique_ptr<MosquittoClient>> MosquittoClient::Connect(
    const MqttOptions& options, MqttMessageHandler on_message, MqttConnectHandler on_connect,
    double wait_s) {
  InitLibrary();
  auto impl = std::make_unique<Impl>();
  impl->on_message = std::move(on_message);
  impl->on_connect = std::move(on_connect);
  impl->client = mosquitto_new(options.client_id.empty() ? nullptr : options.client_id.c_str(),
                               /*clean_session=*/true, impl.get());
  if (impl->client == nullptr) return absl::InternalError("mosquitto_new failed");
  mosquitto_connect_callback_set(impl->client, &Impl::OnConnect);
  mosquitto_disconnect_callback_set(impl->client, &Impl::OnDisconnect);
  mosquitto_message_callback_set(impl->client, &Impl::OnMessage);
  mosquitto_reconnect_delay_set(impl->client, 1, 5, /*exponential=*/true);
  if (options.will) {
    if (mosquitto_will_set(impl->client, options.will->topic.c_str(),
                           static_cast<int>(options.will->payload.size()),
                           options.will->payload.data(), options.will->qos,
                           options.will->retain) != MOSQ_ERR_SUCCESS) {
      return absl::InvalidArgumentError(
          absl::StrCat("MQTT last will on '", options.will->topic, "' refused"));
    }
  }
  const std::string where = absl::StrCat(options.host, ":", options.port);
  if (const int rc = mosquitto_connect_async(impl->client, options.host.c_str(), options.port,
                                             options.keepalive_s);
      rc != MOSQ_ERR_SUCCESS && rc != MOSQ_ERR_ERRNO) {
    return absl::UnavailableError(
        absl::StrCat("cannot reach the MQTT broker at ", where, ": ", mosquitto_strerror(rc)));
  }
  if (mosquitto_loop_start(impl->client) != MOSQ_ERR_SUCCESS) {
    return absl::InternalError("mosquitto_loop_start failed");
  }
  std::unique_ptr<MosquittoClient> client(new MosquittoClient(std::move(impl)));
  const absl::Time deadline = absl::Now() + absl::Seconds(wait_s);
  while (!client->connected()) {
    if (absl::Now() > deadline) {
      return absl::UnavailableError(
          absl::StrCat("cannot reach the MQTT broker at ", where, " within ", wait_s, " s"));
    }
    absl::SleepFor(absl::Milliseconds(20));
  }
  return client;
}

bool MosquittoClient::connected() const {
  absl::MutexLock lock(&impl_->mutex);
  return impl_->connected;
}

absl::Status MosquittoClient::Publish(const std::string& topic, const std::string& payload, int qos,
                                      bool retain) {
  if (impl_->disconnected) return absl::FailedPreconditionError("disconnected");
  const int rc = mosquitto_publish(impl_->client, nullptr, topic.c_str(),
                                   static_cast<int>(payload.size()), payload.data(), qos, retain);
  // While the broker is away libmosquitto keeps QoS 1 and 2 messages and sends them after the
  // reconnection (it says NO_CONN, and queues them).
  if (rc == MOSQ_ERR_SUCCESS || (rc == MOSQ_ERR_NO_CONN && qos > 0)) return absl::OkStatus();
  return absl::UnavailableError(
      absl::StrCat("publishing to '", topic, "': ", mosquitto_strerror(rc)));
}

absl::Status MosquittoClient::Subscribe(const std::string& pattern, int qos) {
  {
    absl::MutexLock lock(&impl_->mutex);
    impl_->subscriptions.emplace_back(pattern, qos);
  }
  const int rc = mosquitto_subscribe(impl_->client, nullptr, pattern.c_str(), qos);
  if (rc == MOSQ_ERR_SUCCESS || rc == MOSQ_ERR_NO_CONN) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat("subscribing to '", pattern, "': ", mosquitto_strerror(rc)));
}

void MosquittoClient::Disconnect() {
  impl_->disconnected = true;
  mosquitto_disconnect(impl_->client);
}

}  // namespace fleetnav::vda5050
