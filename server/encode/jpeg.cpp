#include "encode/jpeg.h"

#include <turbojpeg.h>

#include <climits>
#include <memory>
#include <stdexcept>
#include <string>

namespace hdof {
namespace {

struct TjHandleDeleter {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using TjHandle = std::unique_ptr<void, TjHandleDeleter>;

// Streaming encodes every frame on a worker pool: a compressor and an output buffer per thread
// spare an allocation of both per frame, and TurboJPEG handles must not be shared across threads.
struct ThreadCompressor {
  TjHandle handle;
  std::vector<unsigned char> scratch;
};

}  // namespace

std::vector<uint8_t> encodeJpeg(const ImageRgba8& image, int quality, bool subsample420) {
  if (image.width == 0 || image.height == 0 || image.width > INT_MAX / 4 || image.height > INT_MAX)
    throw std::invalid_argument("encodeJpeg: cannot encode a " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " image");
  if (image.pixels.size() != size_t{image.width} * image.height * 4)
    throw std::invalid_argument("encodeJpeg: pixel buffer does not match the image size");
  if (quality < 1 || quality > 100)
    throw std::invalid_argument("encodeJpeg: quality " + std::to_string(quality) +
                                " is not in 1..100");

  thread_local ThreadCompressor compressor;
  if (!compressor.handle) compressor.handle.reset(tjInitCompress());
  if (!compressor.handle)
    throw std::runtime_error(std::string("TurboJPEG: cannot create a compressor: ") +
                             tjGetErrorStr2(nullptr));
  const int width = static_cast<int>(image.width), height = static_cast<int>(image.height);
  const int subsampling = subsample420 ? TJSAMP_420 : TJSAMP_444;
  const unsigned long capacity = tjBufSize(width, height, subsampling);
  if (capacity == static_cast<unsigned long>(-1))
    throw std::runtime_error(std::string("TurboJPEG: ") + tjGetErrorStr2(nullptr));
  if (compressor.scratch.size() < capacity) compressor.scratch.resize(capacity);

  // tjBufSize is the worst case, so with TJFLAG_NOREALLOC TurboJPEG writes into our buffer.
  unsigned char* output = compressor.scratch.data();
  unsigned long size = capacity;
  if (tjCompress2(compressor.handle.get(), image.pixels.data(), width, width * 4, height, TJPF_RGBA,
                  &output, &size, subsampling, quality, TJFLAG_NOREALLOC) != 0)
    throw std::runtime_error(std::string("TurboJPEG: ") + tjGetErrorStr2(compressor.handle.get()));
  return {output, output + size};
}

ImageRgba8 decodeJpeg(std::span<const uint8_t> jpeg) {
  TjHandle handle(tjInitDecompress());
  if (!handle) throw std::runtime_error("TurboJPEG: cannot create a decompressor");
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(handle.get(), jpeg.data(), jpeg.size(), &width, &height, &subsampling,
                          &colorspace) != 0 ||
      width <= 0 || height <= 0)
    throw std::invalid_argument(std::string("not a JPEG: ") + tjGetErrorStr2(handle.get()));
  ImageRgba8 image;
  image.width = uint32_t(width);
  image.height = uint32_t(height);
  image.pixels.resize(size_t(width) * height * 4);
  if (tjDecompress2(handle.get(), jpeg.data(), jpeg.size(), image.pixels.data(), width, width * 4,
                    height, TJPF_RGBA, 0) != 0)
    throw std::invalid_argument(std::string("corrupt JPEG: ") + tjGetErrorStr2(handle.get()));
  return image;
}

}  // namespace hdof
