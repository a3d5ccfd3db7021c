#include "net/ws_client.h"

#include <libwebsockets.h>

#include <cstring>
#include <stdexcept>

namespace hdof::net {

struct WsClientCallbacks {
  static int event(lws* wsi, lws_callback_reasons reason, void*, void* in, size_t len) {
    auto* client = static_cast<WsClient*>(lws_context_user(lws_get_context(wsi)));
    return client ? client->onEvent(wsi, reason, in, len) : 0;
  }
};

WsClient::WsClient(const WsClientOptions& options) {
  lws_set_log_level(LLL_ERR, nullptr);
  protocolName_ = options.protocol;
  protocols_ = std::make_unique<lws_protocols[]>(2);  // zeroed: the second ends the list
  protocols_[0] = {protocolName_.c_str(), WsClientCallbacks::event, 0, 65536, 0, nullptr, 0};

  lws_context_creation_info info{};
  info.port = CONTEXT_PORT_NO_LISTEN;
  info.protocols = protocols_.get();
  info.user = this;
  context_ = lws_create_context(&info);
  if (!context_) throw std::runtime_error("WsClient: cannot create a libwebsockets context");

  lws_client_connect_info connect{};
  connect.context = context_;
  connect.address = options.host.c_str();
  connect.port = options.port;
  connect.path = options.path.c_str();
  // The Host header names the port too (RFC 9110), as a browser's does.
  bool ipv6 = options.host.find(':') != std::string::npos;
  hostHeader_ =
      (ipv6 ? "[" + options.host + "]" : options.host) + ":" + std::to_string(options.port);
  connect.host = hostHeader_.c_str();
  connect.origin = options.origin.empty() ? nullptr : options.origin.c_str();
  connect.protocol = protocolName_.c_str();
  connect.pwsi = &wsi_;
  if (!lws_client_connect_via_info(&connect)) {
    state_ = State::Closed;
    incoming_.push_back({WsMessage::Kind::Closed, "", {}, 0, "cannot connect"});
  }
  thread_ = std::thread([this] {
    for (;;) {
      {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
      }
      lws_service(context_, 0);
    }
  });
}

WsClient::~WsClient() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  lws_cancel_service(context_);
  thread_.join();
  lws_context_destroy(context_);
}

bool WsClient::connected(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return state_ != State::Connecting; });
  return opened_;
}

void WsClient::sendText(std::string text) {
  {
    std::lock_guard lock(mutex_);
    outgoing_.push_back({std::vector<uint8_t>(text.begin(), text.end()), false});
  }
  lws_cancel_service(context_);
}

void WsClient::sendBinary(std::vector<uint8_t> data) {
  {
    std::lock_guard lock(mutex_);
    outgoing_.push_back({std::move(data), true});
  }
  lws_cancel_service(context_);
}

void WsClient::close() {
  {
    std::lock_guard lock(mutex_);
    closeRequested_ = true;
  }
  lws_cancel_service(context_);
}

std::optional<WsMessage> WsClient::receive(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  if (!changed_.wait_for(lock, timeout, [&] { return !incoming_.empty(); })) return std::nullopt;
  WsMessage message = std::move(incoming_.front());
  incoming_.pop_front();
  return message;
}

void WsClient::push(WsMessage message) {
  {
    std::lock_guard lock(mutex_);
    if (message.kind == WsMessage::Kind::Closed) state_ = State::Closed;
    incoming_.push_back(std::move(message));
  }
  changed_.notify_all();
}

int WsClient::onEvent(lws* wsi, int reason, void* in, size_t len) {
  switch (reason) {
    case LWS_CALLBACK_CLIENT_ESTABLISHED: {
      {
        std::lock_guard lock(mutex_);
        state_ = State::Open;
        opened_ = true;
      }
      changed_.notify_all();
      lws_callback_on_writable(wsi);
      return 0;
    }
    case LWS_CALLBACK_CLIENT_CONNECTION_ERROR:
      wsi_ = nullptr;
      push({WsMessage::Kind::Closed,
            "",
            {},
            0,
            in ? std::string(static_cast<const char*>(in)) : "connection failed"});
      return 0;
    case LWS_CALLBACK_CLIENT_RECEIVE: {
      const auto* bytes = static_cast<const uint8_t*>(in);
      partial_.insert(partial_.end(), bytes, bytes + len);
      if (!lws_is_final_fragment(wsi)) return 0;
      WsMessage message;
      if (lws_frame_is_binary(wsi)) {
        message.kind = WsMessage::Kind::Binary;
        message.binary = std::move(partial_);
      } else {
        message.text.assign(partial_.begin(), partial_.end());
      }
      partial_.clear();
      push(std::move(message));
      return 0;
    }
    case LWS_CALLBACK_WS_PEER_INITIATED_CLOSE:
      if (len >= 2) {
        const auto* bytes = static_cast<const uint8_t*>(in);
        closeCode_ = bytes[0] << 8 | bytes[1];
        closeReason_.assign(reinterpret_cast<const char*>(bytes + 2), len - 2);
      }
      return 0;
    case LWS_CALLBACK_CLIENT_CLOSED:
      wsi_ = nullptr;
      push({WsMessage::Kind::Closed, "", {}, closeCode_, closeReason_});
      return 0;
    case LWS_CALLBACK_EVENT_WAIT_CANCELLED:
      if (wsi_) lws_callback_on_writable(wsi_);
      return 0;
    case LWS_CALLBACK_CLIENT_WRITEABLE: {
      Outgoing next;
      bool more = false;
      {
        std::lock_guard lock(mutex_);
        if (closeRequested_) {
          lws_close_reason(wsi, LWS_CLOSE_STATUS_NORMAL, nullptr, 0);
          return -1;
        }
        if (outgoing_.empty()) return 0;
        next = std::move(outgoing_.front());
        outgoing_.pop_front();
        more = !outgoing_.empty();
      }
      std::vector<uint8_t> buffer(LWS_PRE + next.data.size());
      if (!next.data.empty())
        std::memcpy(buffer.data() + LWS_PRE, next.data.data(), next.data.size());
      int written = lws_write(wsi, buffer.data() + LWS_PRE, next.data.size(),
                              next.binary ? LWS_WRITE_BINARY : LWS_WRITE_TEXT);
      if (written < int(next.data.size())) return -1;
      if (more) lws_callback_on_writable(wsi);
      return 0;
    }
    default:
      return 0;
  }
}

}  // namespace hdof::net
