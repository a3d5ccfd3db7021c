// libFuzzer target for the client message parser: whatever the bytes, parseClientMessage must
// return (a message or an error naming why), never crash, throw or read out of bounds. Built
// with clang only (-fsanitize=fuzzer,address: the sanitizer build, see tests/CMakeLists.txt).
#include "net/message_codec.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const hdof::net::Limits limits;
  std::string_view text(reinterpret_cast<const char*>(data), size);
  hdof::net::ParsedMessage parsed = hdof::net::parseClientMessage(text, limits);
  // A rejected message always says why.
  if (!parsed.ok() && parsed.error.message.empty()) std::abort();
  return 0;
}
