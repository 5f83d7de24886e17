#include "core/image_list.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/statistics.h"
#include "core/text_file.h"
#include "core/trajectory.h"

namespace fs = std::filesystem;

namespace slamcmp {

namespace {

// A list of image files decoded one by one.
class ImageListSource : public FrameSource {
 public:
  ImageListSource(std::vector<ImageEntry> entries, cv::Size size)
      : entries_(std::move(entries)), size_(size) {}
  int size() const override { return static_cast<int>(entries_.size()); }
  bool claim(Frame* frame) override {
    if (next_ >= entries_.size()) return false;
    const ImageEntry& e = entries_[next_];
    frame->index = static_cast<int>(next_++);
    frame->timestamp = e.timestamp;
    frame->source = e.path;
    frame->grey.release();
    frame->decode_error.clear();
    return true;
  }
  void decode(Frame* frame) const override {
    frame->grey = readGreyImage(frame->source, &frame->decode_error);
    if (!frame->grey.empty() && frame->grey.size() != size_)
      throw InputError(frame->source, "image is " + std::to_string(frame->grey.cols) + "x" +
                                          std::to_string(frame->grey.rows) + ", the sequence's are " +
                                          std::to_string(size_.width) + "x" + std::to_string(size_.height));
  }

 private:
  std::vector<ImageEntry> entries_;
  cv::Size size_;
  size_t next_ = 0;
};

// The fields of a line: runs of blanks separate them for ' '; for another separator, each field
// between two separators with the blanks around it trimmed.
std::vector<std::string> splitFields(const std::string& line, char separator) {
  std::vector<std::string> fields;
  if (separator == ' ') {
    std::istringstream in(line);
    for (std::string field; in >> field;) fields.push_back(field);
    return fields;
  }
  std::istringstream in(line);
  for (std::string field; std::getline(in, field, separator);) {
    const auto first = field.find_first_not_of(" \t");
    const auto last = field.find_last_not_of(" \t");
    fields.push_back(first == std::string::npos ? "" : field.substr(first, last - first + 1));
  }
  if (!line.empty() && line.back() == separator) fields.emplace_back();  // getline drops a last empty field
  return fields;
}

}  // namespace

std::vector<ImageEntry> readImageList(const fs::path& list_path, const ImageListLayout& layout) {
  const std::string list = list_path.string();
  std::ifstream in = openTextFile(list);  // a folder would "list no frames"
  const std::string expected = std::string("expected '") + layout.fields + "'";
  std::vector<ImageEntry> entries;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (layout.stop_on_interrupt && interruptRequested())
      throw Interrupted(atLine(list, n) + ": interrupted while the list was being read");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (n == 1) dropByteOrderMark(&line);
    if (n == 1 && (line.rfind("\xFF\xFE", 0) == 0 || line.rfind("\xFE\xFF", 0) == 0))
      throw InputError(list, "starts with a UTF-16 byte-order mark: save it as UTF-8 or ASCII text");
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::vector<std::string> fields = splitFields(line, layout.separator);
    if (fields.size() < 2 || fields[0].empty() || fields[1].empty()) throw InputError(atLine(list, n), expected);
    if (fields.size() > 2) throw InputError(atLine(list, n), expected + ", found more fields");
    const std::string& stamp = fields[0];
    char* end = nullptr;
    const double value = std::strtod(stamp.c_str(), &end);
    if (end == stamp.c_str() || *end) throw InputError(atLine(list, n), "timestamp '" + stamp + "' is not a number");
    // Divided, not multiplied by the inverse: as the ground truth readers, so that the same
    // nanoseconds give the same seconds.
    const double t = value / layout.units_per_second;
    checkPlausibleSeconds(t, atLine(list, n));
    if (!entries.empty() && !(t > entries.back().timestamp))
      throw InputError(atLine(list, n), t == entries.back().timestamp ? "duplicate timestamp"
                                                                      : "timestamp goes back in time");
    const fs::path image = layout.image_dir / fields[1];
    std::error_code ec;  // e.g. a name too long for the file system: no such file either
    if (layout.images_must_exist && !fs::is_regular_file(image, ec))
      throw InputError(atLine(list, n), "image '" + image.string() + "' does not exist");
    entries.push_back({t, image.string()});
  }
  if (entries.empty()) throw InputError(list, "lists no frames");
  // Timestamps in a larger unit than the list's (seconds in EuRoC's nanosecond list) pass every
  // check above and put the frames nanoseconds apart.
  constexpr double kMaxFps = 1e5;
  if (const double fps = medianRate(entries); fps > kMaxFps) {
    std::ostringstream why;
    why << "timestamps a median " << 1 / fps << " s apart (" << fps << " fps): this list's timestamps are "
        << (layout.units_per_second == 1 ? "seconds" : "nanoseconds") << ", are these "
        << (layout.units_per_second == 1e9 ? "seconds?" : "a larger unit?");
    throw InputError(list, why.str());
  }
  return entries;
}

double medianRate(const std::vector<ImageEntry>& entries) {
  std::vector<double> dt;
  for (size_t i = 1; i < entries.size(); ++i) dt.push_back(entries[i].timestamp - entries[i - 1].timestamp);
  if (dt.empty()) return 30.0;
  return 1.0 / median(dt);  // timestamps strictly increase: dt > 0
}

Sequence imageListSequence(std::vector<ImageEntry> entries, double fps, bool read_images) {
  Sequence seq;
  seq.fps = fps;
  if (!read_images) {
    seq.frames = std::make_unique<ImageListSource>(std::move(entries), seq.image_size);
    return seq;
  }
  std::string why;
  const cv::Mat first = readGreyImage(entries.front().path, &why);
  if (first.empty()) throw InputError(entries.front().path, "cannot be decoded as an image (" + why + ")");
  seq.image_size = first.size();
  seq.frames = std::make_unique<ImageListSource>(std::move(entries), seq.image_size);
  return seq;
}

}  // namespace slamcmp
