// The client's JSON text messages to validated C++ values: a pure function (no network, no GPU)
// that never throws, whatever the bytes, so it can be fuzzed on its own.
#pragma once

#include "net/protocol.h"

#include <string_view>

namespace hdof::net {

struct ParsedMessage {
  std::optional<ClientMessage> message;  // set when the text is a valid message
  ProtocolError error;                   // otherwise, why not

  bool ok() const { return message.has_value(); }
};

// Checks the text against the v1 schemas (protocol/schemas/) and `limits`: a JSON object with a
// known `type`, only the listed fields, each of its type, finite and in range.
ParsedMessage parseClientMessage(std::string_view text, const Limits& limits);

// A mode a session may stream (pinhole, postprocess, raytrace, hybrid), or nothing.
std::optional<RenderMode> parseStreamingMode(const std::string& name);

}  // namespace hdof::net
