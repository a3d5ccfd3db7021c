#include "net/lingering_close.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace hdof::net {
namespace {

// Reads and drops what the socket holds; true while the peer may still send (no end of input, no
// error).
bool stillOpen(int fd) {
  char buffer[4096];
  while (true) {
    ssize_t n = recv(fd, buffer, sizeof(buffer), MSG_DONTWAIT);
    if (n > 0) continue;
    if (n < 0 && errno == EINTR) continue;
    return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK);
  }
}

}  // namespace

LingeringClose::~LingeringClose() {
  for (const Socket& socket : sockets_) close(socket.fd);
}

void LingeringClose::add(int fd) {
  int copy = fd >= 0 ? dup(fd) : -1;
  if (copy < 0) return;  // the caller's close is then the end
  shutdown(copy, SHUT_WR);
  if (sockets_.size() >= kMaxSockets) {
    close(sockets_.front().fd);
    sockets_.erase(sockets_.begin());
  }
  sockets_.push_back({copy, Clock::now() + kLingerLimit});
}

void LingeringClose::drain() {
  Clock::time_point now = Clock::now();
  std::erase_if(sockets_, [&](const Socket& socket) {
    if (stillOpen(socket.fd) && now < socket.until) return false;
    close(socket.fd);
    return true;
  });
}

void LingeringClose::finish(std::chrono::milliseconds within) {
  Clock::time_point deadline = Clock::now() + within;
  drain();
  while (!sockets_.empty()) {
    auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) break;
    std::vector<pollfd> fds;
    for (const Socket& socket : sockets_) fds.push_back({socket.fd, POLLIN, 0});
    if (poll(fds.data(), fds.size(), int(left)) < 0 && errno != EINTR) break;
    drain();
  }
  for (const Socket& socket : sockets_) close(socket.fd);
  sockets_.clear();
}

}  // namespace hdof::net
