#include "image/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <memory>
#include <system_error>

namespace hdof {
namespace {

struct FileCloser {
  void operator()(FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<FILE, FileCloser>;

std::string osReason(int error) { return std::generic_category().message(error); }

std::vector<uint8_t> readFile(const std::string& path) {
  File file(std::fopen(path.c_str(), "rb"));
  if (!file) throw ImageError("cannot read '" + path + "': " + osReason(errno));
  std::vector<uint8_t> bytes;
  uint8_t chunk[1 << 16];
  size_t got;
  while ((got = std::fread(chunk, 1, sizeof chunk, file.get())) > 0)
    bytes.insert(bytes.end(), chunk, chunk + got);
  if (std::ferror(file.get())) throw ImageError("cannot read '" + path + "': " + osReason(errno));
  return bytes;
}

// stb_image decodes more formats than PNG and JPEG; the signature check keeps the contract.
bool hasPngOrJpegSignature(const std::vector<uint8_t>& bytes) {
  static const uint8_t kPng[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  static const uint8_t kJpeg[] = {0xff, 0xd8, 0xff};
  auto startsWith = [&](const auto& signature) {
    return bytes.size() >= sizeof signature &&
           std::equal(std::begin(signature), std::end(signature), bytes.begin());
  };
  return startsWith(kPng) || startsWith(kJpeg);
}

}  // namespace

std::vector<uint8_t> encodePng(const ImageRgba8& image) {
  if (image.width == 0 || image.height == 0 || image.width > (1u << 24) ||
      image.height > (1u << 24) || image.pixels.size() != size_t{image.width} * image.height * 4)
    throw std::invalid_argument("encodePng: not a valid " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " RGBA8 image");
  std::vector<uint8_t> bytes;
  auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &bytes, static_cast<int>(image.width),
                              static_cast<int>(image.height), 4, image.pixels.data(),
                              static_cast<int>(image.width * 4)))
    throw std::runtime_error("PNG encoding failed");
  return bytes;
}

void writeImageBytes(const std::string& path, std::span<const uint8_t> bytes) {
  File file(std::fopen(path.c_str(), "wb"));
  if (!file) throw ImageError("cannot write '" + path + "': " + osReason(errno));
  if (std::fwrite(bytes.data(), 1, bytes.size(), file.get()) != bytes.size())
    throw ImageError("cannot write '" + path + "': " + osReason(errno));
  // A full disk often shows only when the buffered tail is flushed.
  if (std::fclose(file.release()) != 0)
    throw ImageError("cannot write '" + path + "': " + osReason(errno));
}

void writePng(const std::string& path, const ImageRgba8& image) {
  std::vector<uint8_t> bytes;
  try {
    bytes = encodePng(image);
  } catch (const std::runtime_error& e) {
    throw ImageError("cannot write '" + path + "': " + e.what());
  }
  writeImageBytes(path, bytes);
}

ImageRgba8 readImage(const std::string& path) {
  std::vector<uint8_t> bytes = readFile(path);
  if (bytes.size() > INT_MAX) throw ImageError("cannot read '" + path + "': file too large");
  if (!hasPngOrJpegSignature(bytes))
    throw ImageError("cannot read '" + path + "': not a PNG or JPEG file");
  int width = 0, height = 0, channels = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &width, &height,
                            &channels, 4),
      stbi_image_free);
  if (!pixels)
    throw ImageError("cannot read '" + path + "': corrupt image (" + stbi_failure_reason() + ")");
  ImageRgba8 image;
  image.width = static_cast<uint32_t>(width);
  image.height = static_cast<uint32_t>(height);
  image.pixels.assign(pixels.get(), pixels.get() + size_t{image.width} * image.height * 4);
  return image;
}

}  // namespace hdof
