// A TUM RGB-D style folder: rgb.txt lists "timestamp path" a line, paths relative to the folder.
#include "core/image_list.h"
#include "core/sequence_format.h"

namespace fs = std::filesystem;

namespace slamcmp {

namespace {

class TumFormat : public SequenceFormat {
 public:
  std::string name() const override { return "tum"; }
  bool detect(const fs::path& path) const override {
    std::error_code ec;
    return fs::is_directory(path, ec) && pathExists(path / "rgb.txt");
  }
  Sequence open(const fs::path& path, const SequenceOpenOptions& options) const override {
    std::vector<ImageEntry> entries = readImageList(
        path / "rgb.txt", {"timestamp path", ' ', 1.0, path, options.stop_on_interrupt, options.read_images});
    const double fps = medianRate(entries);
    return imageListSequence(std::move(entries), fps, options.read_images);
  }
};

}  // namespace

const SequenceFormat& tumFormat() {
  static const TumFormat format;
  return format;
}

}  // namespace slamcmp
