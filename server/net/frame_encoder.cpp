#include "net/frame_encoder.h"

#include <algorithm>
#include <memory>
#include <optional>

namespace hdof::net {

FrameEncoder::FrameEncoder(Encode encode, unsigned workers, size_t capacity, Encoded onEncoded,
                           Dropped onDropped)
    : encode_(std::move(encode)),
      workers_(std::max(1u, workers)),
      capacity_(std::max<size_t>(1, capacity)),
      onEncoded_(std::move(onEncoded)),
      onDropped_(std::move(onDropped)) {}

void FrameEncoder::submit(StreamFrame frame) {
  std::optional<StreamFrame> dropped;
  bool encodeNow = false;
  {
    std::lock_guard lock(mutex_);
    if (stopped_) {
      dropped = std::move(frame);
    } else if (busy_ < workers_) {
      ++busy_;
      encodeNow = true;
    } else {
      if (waiting_.size() >= capacity_) {
        dropped = std::move(waiting_.front());
        waiting_.pop_front();
      }
      waiting_.push_back(std::move(frame));
    }
  }
  if (dropped) onDropped_(std::move(*dropped));
  if (encodeNow) handOver(std::move(frame));
}

void FrameEncoder::handOver(StreamFrame frame) {
  ImageRgba8 image = std::move(frame.image);
  int quality = frame.plan.jpegQuality;
  // The frame rides along in the callback (shared: std::function needs a copyable callable).
  auto held = std::make_shared<StreamFrame>(std::move(frame));
  encode_(std::move(image), quality,
          [this, held](EncodedJpeg jpeg) { finished(std::move(*held), std::move(jpeg)); });
}

void FrameEncoder::finished(StreamFrame frame, EncodedJpeg jpeg) {
  frame.jpeg = std::move(jpeg);
  onEncoded_(std::move(frame));
  std::optional<StreamFrame> next;
  {
    std::lock_guard lock(mutex_);
    if (!stopped_ && !waiting_.empty()) {
      next = std::move(waiting_.front());
      waiting_.pop_front();
    } else {
      --busy_;
    }
  }
  if (next) handOver(std::move(*next));
}

void FrameEncoder::shutdown() {
  std::deque<StreamFrame> dropped;
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
    dropped.swap(waiting_);
  }
  for (StreamFrame& frame : dropped) onDropped_(std::move(frame));
}

size_t FrameEncoder::waiting() const {
  std::lock_guard lock(mutex_);
  return waiting_.size();
}

}  // namespace hdof::net
