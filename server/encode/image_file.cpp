#include "encode/image_file.h"

#include "encode/jpeg.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

namespace hdof {
namespace {

enum class FileFormat { kPng, kJpeg, kOther };

FileFormat formatFromExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".png") return FileFormat::kPng;
  if (extension == ".jpg" || extension == ".jpeg") return FileFormat::kJpeg;
  return FileFormat::kOther;
}

}  // namespace

void writeImage(const std::string& path, const ImageRgba8& image, int jpegQuality) {
  FileFormat format = formatFromExtension(path);
  if (format == FileFormat::kOther)
    throw ImageError("cannot write '" + path + "': use a .png or .jpg file name");
  if (format == FileFormat::kPng) return writePng(path, image);
  std::vector<uint8_t> bytes;
  try {  // std::invalid_argument (a bad image or quality) is no std::runtime_error: it passes
    bytes = encodeJpeg(image, jpegQuality);
  } catch (const std::runtime_error& e) {
    throw ImageError("cannot write '" + path + "': " + e.what());
  }
  writeImageBytes(path, bytes);
}

}  // namespace hdof
