#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace fleetnav::vda5050 {

/// What a client needs from an MQTT broker. Publishes never block on the network; the
/// subscriptions are renewed by the implementation after every reconnection. Thread-safe.
class MqttClient {
 public:
  virtual ~MqttClient() = default;
  virtual absl::Status Publish(const std::string& topic, const std::string& payload, int qos,
                               bool retain) = 0;
  virtual absl::Status Subscribe(const std::string& pattern, int qos) = 0;
};

struct MqttOptions {
  std::string host = "127.0.0.1";
  int port = 1883;
  std::string client_id;
  int keepalive_s = 15;  ///< VDA 5050 §6.14 suggests about 15 s
  /// The last will, published by the broker when this client is lost (VDA 5050 §6.14).
  struct Will {
    std::string topic;
    std::string payload;
    int qos = 1;
    bool retain = true;
  };
  std::optional<Will> will;
};

/// Told every message (topic, payload), on the client's network thread.
using MqttMessageHandler =
    std::function<void(const std::string& topic, const std::string& payload)>;
/// Told each time the connection is (re)established (`reconnected`: not the first time), on the
/// network thread, after the subscriptions were renewed.
using MqttConnectHandler = std::function<void(bool reconnected)>;

/// An MQTT 3.1.1 client on libmosquitto (Debian's libmosquitto1): a network thread of its own
/// (mosquitto_loop_start) that reconnects with back-off from 0.2 s to 5 s whenever the broker
/// goes away, and subscribes again to every pattern it was given. A QoS 1 or 2 message published
/// while the broker is away is kept by libmosquitto and sent after the reconnection; QoS 0 fails
/// UNAVAILABLE.
class MosquittoClient final : public MqttClient {
 public:
  /// Starts connecting; UNAVAILABLE when the broker cannot be reached within `wait_s`.
  static absl::StatusOr<std::unique_ptr<MosquittoClient>> Connect(const MqttOptions& options,
                                                                  MqttMessageHandler on_message,
                                                                  MqttConnectHandler on_connect,
                                                                  double wait_s = 5.0);
  ~MosquittoClient() override;
  MosquittoClient(const MosquittoClient&) = delete;
  MosquittoClient& operator=(const MosquittoClient&) = delete;

  absl::Status Publish(const std::string& topic, const std::string& payload, int qos,
                       bool retain) override;
  absl::Status Subscribe(const std::string& pattern, int qos) override;
  /// Publishes nothing more and disconnects cleanly (the broker then sends no last will).
  void Disconnect();
  bool connected() const;

 private:
  struct Impl;
  explicit MosquittoClient(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace fleetnav::vda5050
