// The end of a WebSocket connection: once libwebsockets has sent the last frames (the close frame
// among them) and lets go of the socket, the socket stays open here, sending side shut, its input
// read and dropped, while what was sent has not all reached the peer: until the peer acknowledges
// it, closes its side too, or kLingerLimit passes. A socket closed while input from the peer is
// unread, or before more arrives (acks, camera updates and its close frame, sent before it saw
// the daemon's), is reset by the kernel, which drops what is still queued for the peer: a slow
// reader's last frames and the close frame behind them. The peer then sees the connection lost
// (1006) instead of the daemon's close code. Once the peer has everything, a reset loses nothing.
#pragma once

#include <chrono>
#include <vector>

namespace hdof::net {

class LingeringClose {
 public:
  LingeringClose() = default;
  LingeringClose(const LingeringClose&) = delete;
  LingeringClose& operator=(const LingeringClose&) = delete;
  ~LingeringClose();  // closes what is left

  // Keeps the socket open past the caller's close (a duplicate of fd; the caller closes fd itself)
  // and shuts down its sending side. At most kMaxSockets linger: the oldest goes first.
  void add(int fd);
  // Reads what arrived and drops it; closes a socket whose peer has everything sent (or has
  // closed, or failed), or whose time is up.
  void drain();
  // Drains until no socket is left or `within` passes, then closes what is left.
  void finish(std::chrono::milliseconds within);
  size_t size() const { return sockets_.size(); }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr auto kLingerLimit = std::chrono::seconds(5);
  static constexpr size_t kMaxSockets = 256;
  struct Socket {
    int fd;
    Clock::time_point until;
  };
  std::vector<Socket> sockets_;
};

}  // namespace hdof::net
