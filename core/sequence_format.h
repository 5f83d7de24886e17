#pragma once
// The layouts openSequence reads (SPEC section 3), one file each: a TUM list (rgb.txt), EuRoC
// (mav0/cam0/data.csv), a plain folder of images and a video file. A new layout is one file
// defining its SequenceFormat and one entry in sequenceFormats().
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "core/sequence.h"

namespace slamcmp {

class SequenceFormat {
 public:
  virtual ~SequenceFormat() = default;
  // Sequence::kind: "tum", "euroc", "images", "video".
  virtual std::string name() const = 0;
  // Whether `path` (an existing file or folder) is laid out this way.
  virtual bool detect(const std::filesystem::path& path) const = 0;
  // The frames (Sequence::frames, image_size, fps) and what the layout itself holds (EuRoC's camera
  // and ground truth); openSequence fills in the rest. Throws InputError for anything missing or
  // malformed, naming the file and line.
  virtual Sequence open(const std::filesystem::path& path, const SequenceOpenOptions& options) const = 0;
};

const SequenceFormat& tumFormat();          // core/sequence_tum.cc
const SequenceFormat& eurocFormat();        // core/sequence_euroc.cc
const SequenceFormat& imageFolderFormat();  // core/sequence_image_folder.cc
const SequenceFormat& videoFormat();        // core/sequence_video.cc

// Whether `path` exists; a path that cannot be looked at (a symbolic link loop, a folder without
// permission) is an InputError naming it rather than a filesystem_error (exit 1) or "missing".
inline bool pathExists(const std::filesystem::path& path) {
  std::error_code ec;
  const bool exists = std::filesystem::exists(path, ec);
  if (ec) throw InputError(path.string(), "cannot be read: " + ec.message());
  return exists;
}

// In the order openSequence asks them: the first whose detect() says yes opens the path.
const std::vector<const SequenceFormat*>& sequenceFormats();

}  // namespace slamcmp
