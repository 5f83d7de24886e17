// A plain folder of images: the frames in file name order, timestamped at a rate the user gives.
#include <algorithm>

#include "core/error.h"
#include "core/image_list.h"
#include "core/sequence_format.h"
#include "core/text_file.h"

namespace fs = std::filesystem;

namespace slamcmp {

namespace {

bool isImageFile(const fs::path& p) {
  const std::string ext = lowerExtension(p.string());
  static const char* kExt[] = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm", ".webp"};
  return std::any_of(std::begin(kExt), std::end(kExt), [&](const char* e) { return ext == e; });
}

std::vector<ImageEntry> listImageFolder(const fs::path& dir, double fps) {
  std::vector<std::string> files;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code entry_ec;  // e.g. a dangling link: not an image, not an error
    if (it->is_regular_file(entry_ec) && isImageFile(it->path())) files.push_back(it->path().string());
  }
  if (ec) throw InputError(dir.string(), "cannot be listed: " + ec.message());
  if (files.empty()) throw InputError(dir.string(), "holds no rgb.txt and no image files");
  std::sort(files.begin(), files.end());
  std::vector<ImageEntry> entries;
  for (size_t i = 0; i < files.size(); ++i) entries.push_back({i / fps, files[i]});
  return entries;
}

// Any folder: asked after the formats that recognise a folder by a list in it.
class ImageFolderFormat : public SequenceFormat {
 public:
  std::string name() const override { return "images"; }
  bool detect(const fs::path& path) const override {
    std::error_code ec;
    return fs::is_directory(path, ec);
  }
  Sequence open(const fs::path& path, const SequenceOpenOptions& options) const override {
    return imageListSequence(listImageFolder(path, options.images_fps), options.images_fps);
  }
};

}  // namespace

const SequenceFormat& imageFolderFormat() {
  static const ImageFolderFormat format;
  return format;
}

}  // namespace slamcmp
