#pragma once
// Sequences that are lists of image files (TUM, EuRoC, a plain folder): the grammar their lists
// share and the frame source decoding one file a frame.
#include <filesystem>
#include <string>
#include <vector>

#include "core/sequence.h"

namespace slamcmp {

struct ImageEntry {
  double timestamp;  // seconds
  std::string path;  // the image file
};

// How a list spells "this image at this time", one frame a line.
struct ImageListLayout {
  const char* fields;               // the line as messages spell it: "timestamp path"
  char separator;                   // between the two fields: ' ' (any run of blanks) or ','
  double units_per_second;          // of the timestamps: 1 (seconds) or 1e9 (nanoseconds)
  std::filesystem::path image_dir;  // the file names are relative to it
  bool stop_on_interrupt = true;    // an interrupt ends the reading (Interrupted saying so)
  bool images_must_exist = true;    // SequenceOpenOptions::read_images
};

// Every frame of a list: blank lines and '#' comments skipped, timestamps strictly increasing, each
// image an existing file (unless the layout says otherwise). Throws InputError naming the line.
std::vector<ImageEntry> readImageList(const std::filesystem::path& list_path, const ImageListLayout& layout);

// Frames per second from the median spacing of the timestamps (30 for a single frame).
double medianRate(const std::vector<ImageEntry>& entries);

// The images decoded one by one (Sequence::frames, image_size, fps = `fps`). With `read_images`
// the first is decoded here: it sets the size all must have. Throws InputError if it cannot be
// decoded.
Sequence imageListSequence(std::vector<ImageEntry> entries, double fps, bool read_images);

}  // namespace slamcmp
