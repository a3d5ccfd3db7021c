// Who may use the daemon from a browser: the Host header check (against DNS rebinding) and the
// Origin check of WebSocket sessions (against cross-site WebSocket hijacking). Pure functions over
// header values, no network.
//
// - Host: checked when the daemon listens on a loopback address, or when allowed_hosts is set.
//   Loopback names (localhost, *.localhost, 127.0.0.0/8, ::1) and the allowed_hosts pass; a
//   request without a Host header (HTTP/1.0, not a browser) passes too.
// - Origin: with allowed_origins set, the Origin must be one of them exactly. Without it (the
//   default), only the daemon's own pages: an Origin whose host and port are those of the Host
//   header (same origin), or a loopback Origin on the daemon's port. A request without an Origin
//   comes from a program, not a browser page (browsers always send one with a WebSocket), and
//   passes unless allowed_origins is set; a token is what keeps programs out.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hdof::net {

// host[:port] of a Host header or an origin; the host lowercased, an IPv6 address without its
// brackets; port 0 when none is written.
struct Authority {
  std::string host;
  int port = 0;
};
std::optional<Authority> parseAuthority(std::string_view text);

// localhost, NAME.localhost, 127.0.0.0/8, ::1.
bool isLoopbackHost(std::string_view host);
// A bind address that only this machine reaches: a loopback host or the interface "lo".
bool isLoopbackBind(std::string_view bind);

struct AccessPolicy {
  std::vector<std::string> allowedOrigins;  // exact Origin values; empty: same origin only
  std::vector<std::string> allowedHosts;    // Host names accepted besides loopback ones
  bool checkHost = false;                   // bound to loopback, or allowedHosts set
  int port = 0;                             // the port the daemon listens on

  static AccessPolicy forServer(const std::string& bind, int port,
                                std::vector<std::string> allowedOrigins,
                                std::vector<std::string> allowedHosts);

  // host: the Host header's value, nothing when the request has none.
  bool hostAllowed(const std::optional<std::string>& host) const;
  // origin, host: the headers' values, nothing when absent.
  bool originAllowed(const std::optional<std::string>& origin,
                     const std::optional<std::string>& host) const;
};

}  // namespace hdof::net
