#include "net/lingering_close.h"

#include <linux/sockios.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace hdof::net {
namespace {

// Reads and drops what the socket holds; true while the peer may still send (no end of input, no
// error) and has not acknowledged all that was sent (the end of output, FIN, counts as a byte).
bool stillNeeded(int fd) {
  char buffer[4096];
  while (true) {
    ssize_t n = recv(fd, buffer, sizeof(buffer), MSG_DONTWAIT);
    if (n > 0) continue;
    if (n < 0 && errno == EINTR) continue;
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) return false;
    int unacknowledged = 0;
    return ioctl(fd, SIOCOUTQ, &unacknowledged) == 0 && unacknowledged > 0;
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
    if (stillNeeded(socket.fd) && now < socket.until) return false;
    close(socket.fd);
    return true;
  });
}

void LingeringClose::finish(std::chrono::milliseconds within) {
  // Acknowledgements wake no poll: the sockets are looked at every kPollStep.
  constexpr auto kPollStep = std::chrono::milliseconds(10);
  Clock::time_point deadline = Clock::now() + within;
  drain();
  while (!sockets_.empty() && Clock::now() < deadline) {
    std::vector<pollfd> fds;
    for (const Socket& socket : sockets_) fds.push_back({socket.fd, POLLIN, 0});
    poll(fds.data(), fds.size(), int(kPollStep.count()));
    drain();
  }
  for (const Socket& socket : sockets_) close(socket.fd);
  sockets_.clear();
}

}  // namespace hdof::net
