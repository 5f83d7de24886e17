#include "core/sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <utility>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/image.h"
#include "core/sequence_format.h"
#include "core/stderr_capture.h"

namespace fs = std::filesystem;

namespace slamcmp {

namespace {

// A PNG without its IEND chunk or a JPEG without an end-of-image marker near its end was cut short
// (an interrupted copy). Such files are not decoded: libpng and libjpeg would print their own
// complaints to stderr (and libjpeg return a half-grey image).
bool isTruncatedImage(const std::vector<uchar>& bytes) {
  if (bytes.size() < 8) return false;  // too short to tell: left to the decoder
  const std::string head(bytes.begin(), bytes.begin() + 8);
  const bool png = head == "\x89PNG\r\n\x1a\n";
  const bool jpeg = bytes[0] == 0xFF && bytes[1] == 0xD8;
  if (!png && !jpeg) return false;
  const std::string tail(bytes.end() - std::min<size_t>(bytes.size(), png ? 12 : 4096), bytes.end());
  if (png) return tail.compare(4, 4, "IEND") != 0;
  return tail.find("\xFF\xD9") == std::string::npos;
}

// A board that could not be seen whole with squares of at least kMinSquarePx pixels is never
// detected: refused here rather than answered with a run of lost frames.
void checkTargetFitsImages(const ChessboardTarget& target, cv::Size image_size, const std::string& where) {
  constexpr double kMinSquarePx = 4.0;
  const double squares_long = std::max(target.cols, target.rows) + 1.0;
  const double squares_short = std::min(target.cols, target.rows) + 1.0;
  const double diagonal_px = std::hypot(image_size.width, image_size.height);
  if (squares_long * kMinSquarePx > diagonal_px ||
      squares_long * squares_short * kMinSquarePx * kMinSquarePx > image_size.area())
    throw InputError(where, "a board of " + std::to_string(target.cols) + "x" + std::to_string(target.rows) +
                                " inner corners cannot be seen in " + std::to_string(image_size.width) +
                                "x" + std::to_string(image_size.height) +
                                " images: its squares would be under " +
                                std::to_string(static_cast<int>(kMinSquarePx)) + " pixels");
}

// The folder's own name: "." and ".." name the folder they stand for (as given they named every
// trial's render one folder, and hid compare's logs as ".-cslam.log").
std::string lastComponent(const fs::path& p) {
  fs::path q = fs::absolute(p).lexically_normal();
  if (q.filename().empty()) q = q.parent_path();
  const std::string name = q.filename().string();
  return name.empty() ? "sequence" : name;  // the file system's root
}

}  // namespace

cv::Mat readGreyImage(const std::string& path, std::string* why) {
  const auto fail = [why](const std::string& reason) {
    if (why) *why = reason;
    return cv::Mat();
  };
  // One read of the file, then decoding from memory: the truncation check needs the same bytes.
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return fail("the file cannot be opened");
  std::vector<uchar> bytes(static_cast<size_t>(std::max<std::streamoff>(0, in.tellg())));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())) || bytes.empty())
    return fail("the file is empty or unreadable");
  if (isTruncatedImage(bytes)) return fail("the file is cut short");
  cv::Mat img;
  bool threw = false;
  const std::string said = captureStderr([&] {
    try {
      img = cv::imdecode(bytes, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    } catch (const cv::Exception&) {
      threw = true;
    }
  });
  const DecoderMessages messages = sortDecoderMessages(said);
  if (threw || img.empty()) {
    // Whatever was said then is most likely the failing decoder's (libtiff, libwebp, ...).
    const std::string first = messages.others.substr(0, messages.others.find('\n'));
    return fail(!messages.complaint.empty() ? messages.complaint : !first.empty() ? first : "not a format OpenCV reads");
  }
  if (!messages.complaint.empty()) return fail(messages.complaint);
  if (!messages.others.empty()) {
    const std::lock_guard<std::mutex> lock(stderrMutex());
    std::cerr << messages.others << std::flush;
  }
  return toGrey(img);
}

DecoderMessages sortDecoderMessages(const std::string& said) {
  // libjpeg's warnings that mean broken pixels (jerror.h: the image is still returned); its errors
  // fail the decoding.
  static const char* const kComplaints[] = {"libpng error", "Corrupt JPEG data", "Premature end of JPEG file",
                                            "Invalid JPEG", "Not a JPEG file", "Bogus", "Huffman"};
  DecoderMessages m;
  std::istringstream lines(said);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line.rfind("libpng warning:", 0) == 0) continue;
    const bool complaint = std::any_of(std::begin(kComplaints), std::end(kComplaints),
                                       [&](const char* prefix) { return line.rfind(prefix, 0) == 0; });
    if (complaint && m.complaint.empty()) m.complaint = line;
    if (!complaint) m.others += line + "\n";
  }
  return m;
}

std::string implausibleFrameRate(double fps) {
  constexpr double kMinFps = 0.1, kMaxFps = 1000;  // a slide show to a high-speed camera
  if (fps >= kMinFps && fps <= kMaxFps) return "";
  std::ostringstream why;
  why << "the frames' timestamps imply " << fps << " fps";
  for (const auto& [factor, unit] : {std::pair{1e3, "milliseconds"}, {1e6, "microseconds"}, {1e9, "nanoseconds"}})
    if (fps * factor >= kMinFps && fps * factor <= kMaxFps) {
      why << ": they look like " << unit << " (" << factor << " times seconds), not seconds";
      return why.str();
    }
  why << ", outside [" << kMinFps << ", " << kMaxFps << "]";
  return why.str();
}

const std::vector<const SequenceFormat*>& sequenceFormats() {
  static const std::vector<const SequenceFormat*> all{&tumFormat(), &eurocFormat(), &imageFolderFormat(),
                                                      &videoFormat()};
  return all;
}

Sequence openSequence(const std::string& path, const SequenceOpenOptions& options) {
  const fs::path p(path);
  std::error_code ec;
  if (!fs::exists(p, ec)) throw InputError(path, ec ? "cannot be read: " + ec.message() : "does not exist");
  const auto& formats = sequenceFormats();
  const auto format = std::find_if(formats.begin(), formats.end(), [&](const SequenceFormat* f) { return f->detect(p); });
  if (format == formats.end()) throw InputError(path, "is not a sequence in any format slamcmp reads");
  Sequence seq = (*format)->open(p, options);
  seq.path = path;
  seq.kind = (*format)->name();
  // A folder is one sequence; a file (a video) may share its folder with others.
  const bool folder = fs::is_directory(p, ec);
  seq.name = folder ? lastComponent(p) : p.stem().string();
  const fs::path companion_dir = folder ? p : p.parent_path();  // camera.yaml, target.yaml, groundtruth.txt

  // Without read_camera (calibrate's) no camera file is read; a format with its own honours it too.
  if (options.read_camera && !options.camera_path.empty()) {
    seq.camera_path = options.camera_path;
    seq.camera = readCameraYaml(seq.camera_path);
  } else if (options.read_camera && !seq.camera && pathExists(companion_dir / "camera.yaml")) {
    seq.camera_path = (companion_dir / "camera.yaml").string();
    seq.camera = readCameraYaml(seq.camera_path);
  }
  // Without the images (read_images false) their size is unknown: nothing to check against.
  const bool size_known = !seq.image_size.empty();
  if (size_known && seq.camera && (seq.camera->width != seq.image_size.width || seq.camera->height != seq.image_size.height))
    throw InputError(seq.camera_path, "camera is " + std::to_string(seq.camera->width) + "x" +
                                          std::to_string(seq.camera->height) + " but the images are " +
                                          std::to_string(seq.image_size.width) + "x" +
                                          std::to_string(seq.image_size.height));

  seq.target_path = options.target_path;
  if (seq.target_path.empty() && pathExists(companion_dir / "target.yaml"))
    seq.target_path = (companion_dir / "target.yaml").string();
  if (!seq.target_path.empty()) {
    seq.target = readTargetYaml(seq.target_path, options.allow_symmetric_target);
    if (size_known) checkTargetFitsImages(*seq.target, seq.image_size, seq.target_path);
  }

  if (!seq.groundtruth && folder && pathExists(companion_dir / "groundtruth.txt")) {  // one folder, one ground truth
    seq.groundtruth_path = (companion_dir / "groundtruth.txt").string();
    seq.groundtruth = readTrajectory(seq.groundtruth_path, TrajectoryFormat::Tum);
  }
  return seq;
}

}  // namespace slamcmp
