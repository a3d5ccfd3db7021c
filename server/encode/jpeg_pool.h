// JPEG encoding on a pool of worker threads, so that neither the render thread nor the network
// thread waits for an encode. Jobs run in the order they were submitted, several at a time.
#pragma once

#include "image/image.h"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hdof {

struct EncodedJpeg {
  std::vector<uint8_t> bytes;  // empty when the encode failed
  double encodeMs = 0.0;
  std::string error;  // why it failed
};

class JpegPool {
 public:
  using Done = std::function<void(EncodedJpeg)>;

  explicit JpegPool(unsigned threads);
  ~JpegPool();  // shutdown()
  JpegPool(const JpegPool&) = delete;
  JpegPool& operator=(const JpegPool&) = delete;

  // Encodes the image at quality (1..100) on a worker, then calls done there.
  void submit(ImageRgba8 image, int quality, Done done);
  // Finishes the queued jobs and joins the workers; submit() must not be called after it.
  void shutdown();

 private:
  struct Job {
    ImageRgba8 image;
    int quality;
    Done done;
  };
  void work();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> jobs_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace hdof
