// The bounded stage between the render thread and the JPEG encode pool. At most `workers` frames
// are with the pool at a time (so its own queue never grows); the others wait here, at most
// `capacity` of them. A frame that arrives while the queue is full pushes out the oldest waiting
// one, which is dropped: the newest views are the ones worth sending, and the daemon's memory
// stays bounded whatever the sessions do.
#pragma once

#include "net/render_loop.h"

#include <deque>
#include <functional>
#include <mutex>

namespace hdof::net {

class FrameEncoder {
 public:
  // Encodes the image at the quality on some thread, then calls done (on any thread).
  using Encode =
      std::function<void(ImageRgba8 image, int quality, std::function<void(EncodedJpeg)> done)>;
  // A frame with its jpeg set (bytes empty when the encode failed), on the encoding thread.
  using Encoded = std::function<void(StreamFrame)>;
  // A frame that will never be encoded, on the thread that submitted the newer frame or called
  // shutdown().
  using Dropped = std::function<void(StreamFrame)>;

  FrameEncoder(Encode encode, unsigned workers, size_t capacity, Encoded onEncoded,
               Dropped onDropped);
  FrameEncoder(const FrameEncoder&) = delete;
  FrameEncoder& operator=(const FrameEncoder&) = delete;

  void submit(StreamFrame frame);
  // Drops the waiting frames and hands nothing more to the encoder; frames being encoded still
  // come back through onEncoded.
  void shutdown();

  size_t waiting() const;

 private:
  void handOver(StreamFrame frame);
  void finished(StreamFrame frame, EncodedJpeg jpeg);

  Encode encode_;
  const unsigned workers_;
  const size_t capacity_;
  Encoded onEncoded_;
  Dropped onDropped_;

  mutable std::mutex mutex_;
  std::deque<StreamFrame> waiting_;
  unsigned busy_ = 0;  // frames with the encoder
  bool stopped_ = false;
};

}  // namespace hdof::net
