#include "fleetnav/server/rpc/tls_front_door.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "fleetnav/server/rpc/grpc_log_tap.hpp"

namespace fleetnav::server {
namespace {

/// The first byte of a TLS record that carries a handshake message (RFC 8446, 5.1).
constexpr unsigned char kTlsHandshakeRecord = 0x16;
/// A refusal gRPC reports is matched to a connection that ends this soon after it.
constexpr absl::Duration kReportMatchWindow = absl::Seconds(2);

/// "ipv4:127.0.0.1:5555" or "ipv6:[::1]:5555", as gRPC names peers.
std::string PeerName(const sockaddr_storage& address) {
  std::array<char, INET6_ADDRSTRLEN> host{};
  if (address.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&address);
    inet_ntop(AF_INET, &v4->sin_addr, host.data(), host.size());
    return absl::StrCat("ipv4:", host.data(), ":", ntohs(v4->sin_port));
  }
  const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&address);
  inet_ntop(AF_INET6, &v6->sin6_addr, host.data(), host.size());
  return absl::StrCat("ipv6:[", host.data(), "]:", ntohs(v6->sin6_port));
}

void Watch(int epoll_fd, int fd, uint32_t events) {
  epoll_event event{};
  event.events = events;
  event.data.fd = fd;
  epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &event);
}

}  // namespace

std::optional<std::string> HandshakeRefusalReason(const std::string& grpc_log_message) {
  // ssl_transport_security.cc: "Handshake failed with fatal error SSL_ERROR_SSL: error:0A000086:
  // SSL routines::certificate verify failed."
  constexpr std::string_view kFailed = "Handshake failed with fatal error SSL_ERROR_SSL";
  if (grpc_log_message.find(kFailed) == std::string::npos) return std::nullopt;
  std::string openssl = grpc_log_message.substr(grpc_log_message.rfind(':') + 1);
  while (!openssl.empty() && (openssl.back() == '.' || openssl.back() == ' ')) openssl.pop_back();
  if (openssl == "certificate verify failed") {
    return "the client certificate did not verify against the robot CA (another CA, expired or "
           "not yet valid)";
  }
  if (openssl == "wrong version number" || openssl == "http request") {
    return "not TLS (a plaintext client?)";
  }
  return openssl;
}

TlsFrontDoor::~TlsFrontDoor() { Stop(); }

absl::StatusOr<int> TlsFrontDoor::Open(grpc::ServerBuilder* builder,
                                       std::shared_ptr<grpc::ServerCredentials> credentials) {
  const std::string& address = params_.listen_address;
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos || colon + 1 == address.size()) {
    return absl::InvalidArgumentError(
        absl::StrCat("listen address '", address, "': expected HOST:PORT"));
  }
  std::string host = address.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string port = address.substr(colon + 1);
  if (getaddrinfo(host.empty() ? nullptr : host.c_str(), port.c_str(), &hints, &found) != 0 ||
      found == nullptr) {
    return absl::InvalidArgumentError(
        absl::StrCat("listen address '", address, "': no such host or port"));
  }
  listen_fd_ = socket(found->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  const int yes = 1;
  // SO_REUSEADDR only: the port must be this server's alone (no SO_REUSEPORT, as for gRPC).
  const bool bound = listen_fd_ >= 0 &&
                     setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes)) == 0 &&
                     bind(listen_fd_, found->ai_addr, found->ai_addrlen) == 0 &&
                     listen(listen_fd_, SOMAXCONN) == 0;
  freeaddrinfo(found);
  if (!bound) {
    const std::string why = std::strerror(errno);
    if (listen_fd_ >= 0) close(listen_fd_);
    listen_fd_ = -1;
    return absl::UnavailableError(absl::StrCat("cannot listen on ", address, ": ", why));
  }
  sockaddr_storage bound_address{};
  socklen_t length = sizeof(bound_address);
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound_address), &length);
  acceptor_ = builder->experimental().AddExternalConnectionAcceptor(
      grpc::ServerBuilder::experimental_type::ExternalConnectionType::FROM_FD,
      std::move(credentials));
  return bound_address.ss_family == AF_INET
             ? ntohs(reinterpret_cast<sockaddr_in*>(&bound_address)->sin_port)
             : ntohs(reinterpret_cast<sockaddr_in6*>(&bound_address)->sin6_port);
}

void TlsFrontDoor::Start() {
  if (listen_fd_ < 0 || thread_.joinable()) return;
  epoll_fd_ = epoll_create1(EPOLL_CLOEXEC);
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  Watch(epoll_fd_, listen_fd_, EPOLLIN);
  Watch(epoll_fd_, wake_fd_, EPOLLIN);
  log_subscription_ =
      GrpcLogTap::Subscribe([this](const std::string& message) { OnGrpcLog(message); });
  thread_ = std::thread([this] { Loop(); });
}

void TlsFrontDoor::Stop() {
  if (stopping_.exchange(true)) return;
  if (log_subscription_ != 0) GrpcLogTap::Unsubscribe(log_subscription_);
  if (wake_fd_ >= 0) {
    const uint64_t one = 1;
    (void)write(wake_fd_, &one, sizeof(one));
  }
  if (thread_.joinable()) thread_.join();
  for (const auto& [fd, waiting] : waiting_) close(fd);
  for (const auto& [fd, peer] : handed_) close(fd);
  waiting_.clear();
  handed_.clear();
  for (int* fd : {&listen_fd_, &epoll_fd_, &wake_fd_}) {
    if (*fd >= 0) close(*fd);
    *fd = -1;
  }
}

void TlsFrontDoor::Loop() {
  std::array<epoll_event, 64> events{};
  while (!stopping_.load()) {
    const int ready = epoll_wait(epoll_fd_, events.data(), events.size(), 1000);
    const absl::Time now = absl::Now();
    for (int i = 0; i < ready; ++i) {
      const int fd = events[static_cast<size_t>(i)].data.fd;
      if (fd == listen_fd_) {
        Accept();
      } else if (fd == wake_fd_) {
        uint64_t count = 0;
        (void)read(wake_fd_, &count, sizeof(count));
      } else if (waiting_.contains(fd)) {
        FirstBytes(fd);
      } else if (handed_.contains(fd)) {
        Ended(fd);
      }
    }
    MatchReports(now);
    // Connections that never said anything are closed; no TLS client waits that long.
    for (auto it = waiting_.begin(); it != waiting_.end();) {
      if (now - it->second.accepted > absl::Seconds(params_.first_bytes_timeout_s)) {
        close(it->first);
        it = waiting_.erase(it);
      } else {
        ++it;
      }
    }
  }
}

void TlsFrontDoor::Accept() {
  while (true) {
    sockaddr_storage peer{};
    socklen_t length = sizeof(peer);
    const int fd = accept4(listen_fd_, reinterpret_cast<sockaddr*>(&peer), &length,
                           SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;  // EAGAIN: none left (or a transient error: the next wake retries)
    waiting_.emplace(fd, Waiting{PeerName(peer), absl::Now()});
    Watch(epoll_fd_, fd, EPOLLIN | EPOLLRDHUP);
  }
}

void TlsFrontDoor::FirstBytes(int fd) {
  const Waiting waiting = waiting_.at(fd);
  waiting_.erase(fd);
  epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
  unsigned char first = 0;
  const ssize_t peeked = recv(fd, &first, 1, MSG_PEEK);
  if (peeked <= 0) {  // closed before a word (a port probe): nothing was refused
    close(fd);
    return;
  }
  if (first != kTlsHandshakeRecord) {
    Refuse(waiting.peer, "not TLS (a plaintext client?)");
    close(fd);
    return;
  }
  // A duplicate tells when gRPC shuts the connection, for the refusal it may report.
  const int watch = dup(fd);
  if (watch >= 0) {
    handed_.emplace(watch, waiting.peer);
    Watch(epoll_fd_, watch, EPOLLRDHUP);
  }
  // gRPC sets TCP_NODELAY only on sockets it accepts itself. Without it a small message (a
  // lockstep TickAck) waits for the peer's delayed ACK: about 40 ms a round trip.
  const int yes = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof(yes));
  grpc::experimental::ExternalConnectionAcceptor::NewConnectionParameters connection;
  connection.listener_fd = listen_fd_;
  connection.fd = fd;
  acceptor_->HandleNewConnection(&connection);
}

void TlsFrontDoor::Ended(int watch_fd) {
  ended_.push_back(handed_.at(watch_fd));
  handed_.erase(watch_fd);
  epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, watch_fd, nullptr);
  close(watch_fd);
}

void TlsFrontDoor::OnGrpcLog(const std::string& message) {
  std::optional<std::string> reason = HandshakeRefusalReason(message);
  if (!reason) return;
  {
    absl::MutexLock lock(&reports_mutex_);
    reports_.push_back({*std::move(reason), absl::Now()});
  }
  const uint64_t one = 1;
  (void)write(wake_fd_, &one, sizeof(one));
}

void TlsFrontDoor::MatchReports(absl::Time now) {
  std::vector<std::pair<std::string, std::string>> refused;  // peer, reason
  {
    absl::MutexLock lock(&reports_mutex_);
    // A report older than the window belongs to no connection of this door (a handshake of
    // this process as a client, or of another server in it).
    while (!reports_.empty() && now - reports_.front().at > kReportMatchWindow) {
      reports_.pop_front();
    }
    // gRPC reports before it shuts the socket: a connection that ended with no report pending
    // ended normally.
    for (; !ended_.empty() && !reports_.empty(); ended_.pop_front(), reports_.pop_front()) {
      refused.emplace_back(ended_.front(), reports_.front().reason);
    }
    ended_.clear();
  }
  for (const auto& [peer, reason] : refused) Refuse(peer, reason);
}

void TlsFrontDoor::Refuse(const std::string& peer, const std::string& reason) {
  refused_.fetch_add(1, std::memory_order_relaxed);
  if (params_.on_refusal) {
    params_.on_refusal(absl::StrCat("UNAUTHENTICATED: TLS handshake from ", peer, ": ", reason));
  }
}

}  // namespace fleetnav::server
