// A plain folder of images: the frames in file name order (numbers by value: frame2 before frame10,
// as a file browser lists them; 1403636579.25 before 1403636579.5), timestamped at a rate the user
// gives.
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
  static const char* kExt[] = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm", ".pfm", ".webp"};
  return std::any_of(std::begin(kExt), std::end(kExt), [&](const char* e) { return ext == e; });
}

// Digit runs compared by their value (then by length: 01 after 1), the rest byte by byte; the
// digits after a decimal point (a digit, then '.') as a fraction, byte by byte: 0.25 before 0.5.
bool naturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      const size_t a0 = i, b0 = j;
      while (i < a.size() && digit(a[i])) ++i;
      while (j < b.size() && digit(b[j])) ++j;
      // The same characters precede both runs here, so both are fractions or neither is.
      if (a0 >= 2 && a[a0 - 1] == '.' && digit(a[a0 - 2])) {
        const int c = a.compare(a0, i - a0, b, b0, j - b0);
        if (c != 0) return c < 0;
        continue;
      }
      // Leading zeros aside, the longer run is the larger number; of equal length, the first
      // differing digit decides.
      const size_t az = a.find_first_not_of('0', a0), bz = b.find_first_not_of('0', b0);
      const size_t a_len = i - std::min(az, i), b_len = j - std::min(bz, j);
      if (a_len != b_len) return a_len < b_len;
      const int c = a.compare(i - a_len, a_len, b, j - b_len, b_len);
      if (c != 0) return c < 0;
      if (i - a0 != j - b0) return i - a0 < j - b0;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
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
  std::sort(files.begin(), files.end(), naturalLess);
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
    return imageListSequence(listImageFolder(path, options.images_fps), options.images_fps, options.read_images);
  }
};

}  // namespace

const SequenceFormat& imageFolderFormat() {
  static const ImageFolderFormat format;
  return format;
}

}  // namespace slamcmp
