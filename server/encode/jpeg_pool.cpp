#include "encode/jpeg_pool.h"

#include "encode/jpeg.h"

#include <chrono>

namespace hdof {

JpegPool::JpegPool(unsigned threads) {
  for (unsigned i = 0; i < std::max(1u, threads); ++i) workers_.emplace_back([this] { work(); });
}

JpegPool::~JpegPool() { shutdown(); }

void JpegPool::shutdown() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (std::thread& worker : workers_) worker.join();
  workers_.clear();
}

void JpegPool::submit(ImageRgba8 image, int quality, Done done) {
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back({std::move(image), quality, std::move(done)});
  }
  wake_.notify_one();
}

void JpegPool::work() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) return;  // stopping, and nothing left to do
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    EncodedJpeg result;
    auto start = std::chrono::steady_clock::now();
    try {
      result.bytes = encodeJpeg(job.image, job.quality);
    } catch (const std::exception& e) {
      result.error = e.what();
    }
    result.encodeMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    job.done(std::move(result));
  }
}

}  // namespace hdof
