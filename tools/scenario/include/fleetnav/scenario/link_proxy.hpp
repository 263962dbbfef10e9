#pragma once

#include <atomic>
#include <memory>
#include <thread>

#include "absl/status/statusor.h"

namespace fleetnav::scenario {

/// A TCP proxy on loopback between one robot's agent and fleetnavd, so that a scenario can cut
/// that robot's link and restore it (the `cut_link` fault) while the agent, the server and the
/// simulator run on. Bytes are forwarded both ways as they come, with back-pressure (a side is
/// read only once what it sent before has been written on). While cut, every open connection is
/// closed and new ones are accepted and closed at once, as a link that drops would. One thread
/// polls every socket; Cut/Restore are thread-safe.
class LinkProxy {
 public:
  /// Listens on 127.0.0.1 (an ephemeral port) and forwards to 127.0.0.1:target_port.
  static absl::StatusOr<std::unique_ptr<LinkProxy>> Start(int target_port);
  LinkProxy(const LinkProxy&) = delete;
  LinkProxy& operator=(const LinkProxy&) = delete;
  ~LinkProxy();

  int port() const { return port_; }
  void Cut();
  void Restore();
  bool cut() const { return cut_.load(); }

 private:
  LinkProxy(int listen_fd, int port, int target_port, int wake_read_fd, int wake_write_fd);
  void Loop();
  void Wake();

  int listen_fd_;
  int port_;
  int target_port_;
  int wake_read_fd_;
  int wake_write_fd_;
  std::atomic<bool> cut_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace fleetnav::scenario
