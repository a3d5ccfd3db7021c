// The end of a connection the daemon closes: the peer reads everything sent before the close and
// then the end of the stream, even with its own input unread at the daemon's end (closed at once,
// the kernel resets such a connection and drops what is still queued for the peer).
#include "net/lingering_close.h"

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <vector>

namespace hdof::net {
namespace {

// A connected TCP pair on the loopback interface: the daemon's end and the peer's.
struct Connection {
  int daemon = -1, peer = -1;
};

Connection connectLoopback() {
  int listener = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof(address);
  EXPECT_EQ(bind(listener, reinterpret_cast<sockaddr*>(&address), length), 0);
  EXPECT_EQ(listen(listener, 1), 0);
  EXPECT_EQ(getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length), 0);
  Connection c;
  c.peer = socket(AF_INET, SOCK_STREAM, 0);
  EXPECT_EQ(connect(c.peer, reinterpret_cast<sockaddr*>(&address), length), 0);
  c.daemon = accept(listener, nullptr, nullptr);
  close(listener);
  return c;
}

// The daemon's end sends until the peer's buffers and its own are full (the peer reads nothing
// yet), while input from the peer waits unread; returns the bytes sent.
size_t fillWithInputUnread(const Connection& c) {
  std::vector<char> input(100, 'a');
  EXPECT_EQ(send(c.peer, input.data(), input.size(), 0), ssize_t(input.size()));
  std::vector<char> block(64 * 1024, 'b');
  size_t sent = 0;
  while (true) {
    ssize_t n = send(c.daemon, block.data(), block.size(), MSG_DONTWAIT);
    if (n <= 0) break;
    sent += size_t(n);
  }
  return sent;
}

// The daemon's end handed over, then closed as libwebsockets closes its own descriptor.
void closeLingering(LingeringClose& lingering, const Connection& c) {
  lingering.add(c.daemon);
  close(c.daemon);
}

// The peer reads to the end: the bytes it got, and whether the stream ended cleanly.
std::pair<size_t, bool> readToEnd(int fd) {
  std::vector<char> buffer(64 * 1024);
  size_t total = 0;
  while (true) {
    ssize_t n = recv(fd, buffer.data(), buffer.size(), 0);
    if (n > 0) {
      total += size_t(n);
      continue;
    }
    return {total, n == 0};
  }
}

// Drains until no socket lingers or `within` passes (less than the sockets' own limit); returns
// how many still linger.
size_t drainFor(LingeringClose& lingering, std::chrono::milliseconds within) {
  auto deadline = std::chrono::steady_clock::now() + within;
  while (lingering.size() > 0 && std::chrono::steady_clock::now() < deadline) {
    lingering.drain();
    usleep(1000);
  }
  return lingering.size();
}

TEST(LingeringClose, ThePeerGetsEverythingSentBeforeTheClose) {
  Connection c = connectLoopback();
  size_t sent = fillWithInputUnread(c);
  ASSERT_GT(sent, 0u);
  LingeringClose lingering;
  closeLingering(lingering, c);
  lingering.drain();
  EXPECT_EQ(lingering.size(), 1u) << "the peer has not received everything yet";
  // More input after the close: still no reset.
  char more[10] = {};
  EXPECT_EQ(send(c.peer, more, sizeof(more), 0), ssize_t(sizeof(more)));
  auto [received, ended] = readToEnd(c.peer);
  EXPECT_EQ(received, sent);
  EXPECT_TRUE(ended) << "the stream ended with an error: " << errno;
  // The peer has it all: the socket goes, though the peer has not closed its side.
  EXPECT_EQ(drainFor(lingering, std::chrono::seconds(2)), 0u);
  close(c.peer);
}

TEST(LingeringClose, ASocketWithNothingInFlightGoesAtOnce) {
  Connection c = connectLoopback();
  LingeringClose lingering;
  closeLingering(lingering, c);
  auto [received, ended] = readToEnd(c.peer);
  EXPECT_EQ(received, 0u);
  EXPECT_TRUE(ended);
  EXPECT_EQ(drainFor(lingering, std::chrono::seconds(2)), 0u);
  close(c.peer);
}

TEST(LingeringClose, FinishGivesUpOnAPeerThatDoesNotRead) {
  Connection c = connectLoopback();
  ASSERT_GT(fillWithInputUnread(c), 0u);
  LingeringClose lingering;
  closeLingering(lingering, c);
  EXPECT_EQ(drainFor(lingering, std::chrono::milliseconds(50)), 1u);
  lingering.finish(std::chrono::milliseconds(100));
  EXPECT_EQ(lingering.size(), 0u);
  close(c.peer);
}

}  // namespace
}  // namespace hdof::net
