#include "fleetnav/scenario/link_proxy.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"

namespace fleetnav::scenario {
namespace {

void SetNonBlocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL, 0) | O_NONBLOCK); }

sockaddr_in Loopback(int port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(static_cast<uint16_t>(port));
  return address;
}

/// One forwarded connection: the agent's side, the server's side and what each has sent that
/// the other has not yet taken.
struct Pair {
  int agent_fd = -1;
  int server_fd = -1;
  std::string to_server;
  std::string to_agent;
  bool closed = false;
};

/// Reads what `from` has (when nothing is pending for `to`); false when `from` has closed.
bool ReadInto(int from, std::string* pending) {
  if (!pending->empty()) return true;
  std::array<char, 65536> buffer;
  const ssize_t n = read(from, buffer.data(), buffer.size());
  if (n > 0) {
    pending->assign(buffer.data(), static_cast<size_t>(n));
    return true;
  }
  return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR);
}

/// Writes what is pending to `to`; false when `to` has failed.
bool WriteFrom(int to, std::string* pending) {
  if (pending->empty()) return true;
  const ssize_t n = write(to, pending->data(), pending->size());
  if (n > 0) {
    pending->erase(0, static_cast<size_t>(n));
    return true;
  }
  return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR);
}

void ClosePair(Pair* pair) {
  if (pair->closed) return;
  close(pair->agent_fd);
  close(pair->server_fd);
  pair->closed = true;
}

}  // namespace

absl::StatusOr<std::unique_ptr<LinkProxy>> LinkProxy::Start(int target_port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return absl::InternalError(absl::StrCat("link proxy: socket: ", strerror(errno)));
  sockaddr_in address = Loopback(0);
  socklen_t length = sizeof(address);
  if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 ||
      listen(fd, 16) != 0 || getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    const std::string why = strerror(errno);
    close(fd);
    return absl::InternalError(absl::StrCat("link proxy: cannot listen on loopback: ", why));
  }
  SetNonBlocking(fd);
  int wake[2];
  if (pipe(wake) != 0) {
    close(fd);
    return absl::InternalError(absl::StrCat("link proxy: pipe: ", strerror(errno)));
  }
  SetNonBlocking(wake[0]);
  SetNonBlocking(wake[1]);
  return std::unique_ptr<LinkProxy>(
      new LinkProxy(fd, ntohs(address.sin_port), target_port, wake[0], wake[1]));
}

LinkProxy::LinkProxy(int listen_fd, int port, int target_port, int wake_read_fd, int wake_write_fd)
    : listen_fd_(listen_fd),
      port_(port),
      target_port_(target_port),
      wake_read_fd_(wake_read_fd),
      wake_write_fd_(wake_write_fd),
      thread_([this] { Loop(); }) {}

LinkProxy::~LinkProxy() {
  stop_.store(true);
  Wake();
  thread_.join();
  close(listen_fd_);
  close(wake_read_fd_);
  close(wake_write_fd_);
}

void LinkProxy::Wake() {
  const char byte = 1;
  (void)!write(wake_write_fd_, &byte, 1);
}

void LinkProxy::Cut() {
  cut_.store(true);
  Wake();
}

void LinkProxy::Restore() {
  cut_.store(false);
  Wake();
}

void LinkProxy::Loop() {
  std::vector<Pair> pairs;
  while (!stop_.load()) {
    if (cut_.load()) {
      for (Pair& pair : pairs) ClosePair(&pair);
    }
    std::erase_if(pairs, [](const Pair& p) { return p.closed; });
    std::vector<pollfd> fds{{listen_fd_, POLLIN, 0}, {wake_read_fd_, POLLIN, 0}};
    for (const Pair& pair : pairs) {
      // Read a side only when what it sent before is written on; write when something waits.
      fds.push_back({pair.agent_fd,
                     static_cast<short>((pair.to_server.empty() ? POLLIN : 0) |
                                        (pair.to_agent.empty() ? 0 : POLLOUT)),
                     0});
      fds.push_back({pair.server_fd,
                     static_cast<short>((pair.to_agent.empty() ? POLLIN : 0) |
                                        (pair.to_server.empty() ? 0 : POLLOUT)),
                     0});
    }
    if (poll(fds.data(), fds.size(), 500) < 0 && errno != EINTR) return;
    if (fds[1].revents != 0) {
      char drain[64];
      while (read(wake_read_fd_, drain, sizeof(drain)) > 0) {
      }
    }
    for (size_t i = 0; i < pairs.size(); ++i) {
      Pair& pair = pairs[i];
      const short agent_events = fds[2 + 2 * i].revents;
      const short server_events = fds[3 + 2 * i].revents;
      bool ok = true;
      if (agent_events & (POLLIN | POLLHUP | POLLERR))
        ok = ok && ReadInto(pair.agent_fd, &pair.to_server);
      if (server_events & (POLLIN | POLLHUP | POLLERR))
        ok = ok && ReadInto(pair.server_fd, &pair.to_agent);
      if (ok)
        ok = WriteFrom(pair.server_fd, &pair.to_server) && WriteFrom(pair.agent_fd, &pair.to_agent);
      if (!ok) ClosePair(&pair);
    }
    if (fds[0].revents & POLLIN) {
      while (true) {
        const int agent_fd = accept(listen_fd_, nullptr, nullptr);
        if (agent_fd < 0) break;
        const int server_fd = cut_.load() ? -1 : socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in target = Loopback(target_port_);
        if (server_fd < 0 ||
            connect(server_fd, reinterpret_cast<sockaddr*>(&target), sizeof(target)) != 0) {
          // Cut, or the server is away: the agent sees its connection close at once.
          if (server_fd >= 0) close(server_fd);
          close(agent_fd);
          continue;
        }
        const int one = 1;
        setsockopt(agent_fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
        setsockopt(server_fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
        SetNonBlocking(agent_fd);
        SetNonBlocking(server_fd);
        pairs.push_back(Pair{agent_fd, server_fd, "", "", false});
      }
    }
  }
  for (Pair& pair : pairs) ClosePair(&pair);
}

}  // namespace fleetnav::scenario
