#include "net/access_policy.h"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace hdof::net {
namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// 1 to 65535, digits only.
std::optional<int> parsePort(std::string_view text) {
  int port = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), port);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || port < 1 ||
      port > 65535)
    return std::nullopt;
  return port;
}

bool isIpv4Loopback(std::string_view host) {
  int parts = 0;
  int first = -1;
  for (size_t start = 0; start <= host.size(); ++parts) {
    size_t dot = std::min(host.find('.', start), host.size());
    std::string_view part = host.substr(start, dot - start);
    int value = -1;
    auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (part.empty() || part.size() > 3 || error != std::errc() ||
        end != part.data() + part.size() || value > 255)
      return false;
    if (parts == 0) first = value;
    start = dot + 1;
  }
  return parts == 4 && first == 127;
}

// The scheme's port when the origin writes none.
int defaultPort(std::string_view scheme) { return scheme == "https" ? 443 : 80; }

}  // namespace

std::optional<Authority> parseAuthority(std::string_view text) {
  Authority authority;
  std::string_view port;
  if (text.starts_with('[')) {
    size_t close = text.find(']');
    if (close == std::string_view::npos) return std::nullopt;
    authority.host = lower(text.substr(1, close - 1));
    std::string_view rest = text.substr(close + 1);
    if (!rest.empty()) {
      if (!rest.starts_with(':')) return std::nullopt;
      port = rest.substr(1);
      if (port.empty()) return std::nullopt;
    }
  } else {
    size_t colon = text.find(':');
    if (colon != std::string_view::npos && text.find(':', colon + 1) != std::string_view::npos)
      return std::nullopt;  // an IPv6 address must be bracketed
    authority.host = lower(text.substr(0, colon));
    if (colon != std::string_view::npos) {
      port = text.substr(colon + 1);
      if (port.empty()) return std::nullopt;
    }
  }
  if (authority.host.empty()) return std::nullopt;
  for (char c : authority.host)
    if (std::isspace(static_cast<unsigned char>(c)) || c == '/' || c == '@' || c == '\\')
      return std::nullopt;
  if (!port.empty()) {
    std::optional<int> number = parsePort(port);
    if (!number) return std::nullopt;
    authority.port = *number;
  }
  return authority;
}

bool isLoopbackHost(std::string_view host) {
  std::string name = lower(host);
  if (name.ends_with('.')) name.pop_back();  // localhost. is localhost
  return name == "localhost" || name.ends_with(".localhost") || name == "::1" ||
         isIpv4Loopback(name);
}

bool isLoopbackBind(std::string_view bind) { return bind == "lo" || isLoopbackHost(bind); }

AccessPolicy AccessPolicy::forServer(const std::string& bind, int port,
                                     std::vector<std::string> allowedOrigins,
                                     std::vector<std::string> allowedHosts) {
  AccessPolicy policy;
  policy.allowedOrigins = std::move(allowedOrigins);
  for (const std::string& host : allowedHosts) policy.allowedHosts.push_back(lower(host));
  policy.checkHost = isLoopbackBind(bind) || !policy.allowedHosts.empty();
  policy.port = port;
  return policy;
}

bool AccessPolicy::hostAllowed(const std::optional<std::string>& host) const {
  if (!checkHost || !host) return true;
  std::optional<Authority> authority = parseAuthority(*host);
  if (!authority) return false;
  if (isLoopbackHost(authority->host)) return true;
  return std::find(allowedHosts.begin(), allowedHosts.end(), authority->host) != allowedHosts.end();
}

bool AccessPolicy::originAllowed(const std::optional<std::string>& origin,
                                 const std::optional<std::string>& host) const {
  if (!allowedOrigins.empty())
    return origin &&
           std::find(allowedOrigins.begin(), allowedOrigins.end(), *origin) != allowedOrigins.end();
  if (!origin) return true;  // not a browser page
  size_t separator = origin->find("://");
  if (separator == std::string::npos) return false;  // "null" (a sandboxed or file: page), junk
  std::string scheme = lower(std::string_view(*origin).substr(0, separator));
  if (scheme != "http" && scheme != "https") return false;
  std::optional<Authority> from = parseAuthority(std::string_view(*origin).substr(separator + 3));
  if (!from) return false;
  int fromPort = from->port ? from->port : defaultPort(scheme);
  if (isLoopbackHost(from->host) && fromPort == port) return true;
  if (!host) return false;
  std::optional<Authority> to = parseAuthority(*host);
  // The Host header names no scheme: without a port, the page's scheme's default is the port
  // the browser connected to.
  return to && to->host == from->host && (to->port ? to->port : defaultPort(scheme)) == fromPort;
}

}  // namespace hdof::net
