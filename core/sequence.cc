#include "core/sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/image.h"
#include "core/media_plugin.h"
#include "core/yaml.h"

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

}  // namespace

cv::Mat readGreyImage(const std::string& path) {
  // One read of the file, then decoding from memory: the truncation check needs the same bytes.
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return {};
  std::vector<uchar> bytes(static_cast<size_t>(std::max<std::streamoff>(0, in.tellg())));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())) ||
      bytes.empty() || isTruncatedImage(bytes))
    return {};
  cv::Mat img;
  try {
    img = cv::imdecode(bytes, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception&) {
    return {};
  }
  return img.empty() ? img : toGrey(img);
}

namespace {

struct ImageEntry {
  double timestamp;
  std::string path;
};

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
    return true;
  }
  void decode(Frame* frame) const override {
    frame->grey = readGreyImage(frame->source);
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

class VideoSource : public FrameSource {
 public:
  VideoSource(const std::string& path, std::unique_ptr<VideoReader> video, int count, double fps)
      : path_(path), video_(std::move(video)), count_(count), fps_(fps) {}
  int size() const override { return count_; }
  bool claim(Frame* frame) override {  // decodes too: a video's frames come in order
    cv::Mat img;
    if (!video_->read(img)) return false;
    frame->index = index_;
    frame->timestamp = index_ / fps_;
    frame->source = path_ + " frame " + std::to_string(index_);
    ++index_;
    // A fresh image each frame: converting into frame->grey would overwrite, in place, the
    // previous frame a caller still holds (e.g. for optical flow).
    frame->grey = toGrey(img);
    return true;
  }

 private:
  std::string path_;
  std::unique_ptr<VideoReader> video_;
  int count_;
  double fps_;
  int index_ = 0;
};

bool isImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  static const char* kExt[] = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm", ".webp"};
  return std::any_of(std::begin(kExt), std::end(kExt), [&](const char* e) { return ext == e; });
}

std::vector<ImageEntry> readRgbList(const fs::path& list_path) {
  const std::string list = list_path.string();
  std::ifstream in(list);
  if (!in) throw InputError(list, "cannot be opened (missing or unreadable)");
  std::vector<ImageEntry> entries;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ss(line);
    std::string stamp, file, extra;
    ss >> stamp >> file;
    if (file.empty()) throw InputError(atLine(list, n), "expected 'timestamp path'");
    if (ss >> extra) throw InputError(atLine(list, n), "expected 'timestamp path', found more fields");
    char* end = nullptr;
    const double t = std::strtod(stamp.c_str(), &end);
    if (end == stamp.c_str() || *end) throw InputError(atLine(list, n), "timestamp '" + stamp + "' is not a number");
    if (!std::isfinite(t)) throw InputError(atLine(list, n), "timestamp is not finite");
    if (!entries.empty() && !(t > entries.back().timestamp))
      throw InputError(atLine(list, n), t == entries.back().timestamp ? "duplicate timestamp"
                                                                      : "timestamp goes back in time");
    const fs::path image = list_path.parent_path() / file;
    std::error_code ec;  // e.g. a name too long for the file system: no such file either
    if (!fs::is_regular_file(image, ec))
      throw InputError(atLine(list, n), "image '" + image.string() + "' does not exist");
    entries.push_back({t, image.string()});
  }
  if (entries.empty()) throw InputError(list, "lists no frames");
  return entries;
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

// EuRoC cam0/data.csv: "#timestamp [ns],filename".
std::vector<ImageEntry> readEurocCameraList(const fs::path& cam_dir) {
  const std::string list = (cam_dir / "data.csv").string();
  std::ifstream in(list);
  if (!in) throw InputError(list, "cannot be opened (missing or unreadable)");
  std::vector<ImageEntry> entries;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const auto comma = line.find(',');
    if (comma == std::string::npos) throw InputError(atLine(list, n), "expected 'timestamp,filename'");
    char* end = nullptr;
    const std::string stamp = line.substr(0, comma);
    const double ns = std::strtod(stamp.c_str(), &end);
    if (end == stamp.c_str() || *end || !std::isfinite(ns))
      throw InputError(atLine(list, n), "timestamp '" + stamp + "' is not a number");
    std::string file = line.substr(comma + 1);
    file.erase(0, file.find_first_not_of(' '));
    const double t = ns / 1e9;  // as the ground truth reader: the same ns give the same seconds
    if (!entries.empty() && !(t > entries.back().timestamp))
      throw InputError(atLine(list, n), "timestamps must increase");
    const fs::path image = cam_dir / "data" / file;
    std::error_code ec;  // e.g. a name too long for the file system: no such file either
    if (!fs::is_regular_file(image, ec))
      throw InputError(atLine(list, n), "image '" + image.string() + "' does not exist");
    entries.push_back({t, image.string()});
  }
  if (entries.empty()) throw InputError(list, "lists no frames");
  return entries;
}

std::vector<double> readNumberList(const YamlFile& f, const std::string& key, size_t count) {
  const cv::FileNode n = f.node(key);
  const std::string where = f.path() + ": " + key;
  if (n.empty()) throw InputError(where, "missing field");
  std::vector<double> v;
  if (n.isSeq()) {
    for (const auto& e : n) v.push_back(readDouble(e, where));
  } else if (n.isMap()) {  // Kalibr/EuRoC T_BS: {rows, cols, data}
    for (const auto& e : n["data"]) v.push_back(readDouble(e, where));
  }
  if (count && v.size() != count)
    throw InputError(where, "expected " + std::to_string(count) + " numbers, got " + std::to_string(v.size()));
  return v;
}

// EuRoC sensor.yaml: intrinsics [fu, fv, cu, cv], distortion_coefficients [k1 k2 p1 p2],
// resolution [w, h], T_BS (camera in body frame).
CameraModel readEurocCamera(const std::string& path, SE3* T_body_camera) {
  YamlFile f(path);
  const auto k = readNumberList(f, "intrinsics", 4);
  const auto d = readNumberList(f, "distortion_coefficients", 4);
  const auto r = readNumberList(f, "resolution", 2);
  CameraModel c;
  c.width = static_cast<int>(r[0]);
  c.height = static_cast<int>(r[1]);
  c.fx = k[0], c.fy = k[1], c.cx = k[2], c.cy = k[3];
  c.num_distortion = 4;
  for (int i = 0; i < 4; ++i) c.distortion[i] = d[i];
  c.check(path);
  const auto T = readNumberList(f, "T_BS", 16);
  Mat3 R;
  R << T[0], T[1], T[2], T[4], T[5], T[6], T[8], T[9], T[10];
  *T_body_camera = SE3(nearestRotation(R), Vec3(T[3], T[7], T[11]));
  return c;
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

// Frames per second from the median spacing of the timestamps (30 for a single frame).
double medianRate(const std::vector<ImageEntry>& entries) {
  std::vector<double> dt;
  for (size_t i = 1; i < entries.size(); ++i) dt.push_back(entries[i].timestamp - entries[i - 1].timestamp);
  if (dt.empty()) return 30.0;
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return 1.0 / dt[dt.size() / 2];  // timestamps strictly increase: dt > 0
}

std::string lastComponent(const fs::path& p) {
  fs::path q = p;
  if (q.filename().empty()) q = q.parent_path();
  return q.filename().string();
}

}  // namespace

Sequence openSequence(const std::string& path, const SequenceOpenOptions& options) {
  Sequence seq;
  seq.path = path;
  const fs::path p(path);
  std::error_code ec;
  if (!fs::exists(p, ec)) throw InputError(path, ec ? "cannot be read: " + ec.message() : "does not exist");
  seq.name = lastComponent(p);

  fs::path companion_dir;  // where camera.yaml / target.yaml / groundtruth.txt are looked for
  std::vector<ImageEntry> entries;
  if (fs::is_directory(p)) {
    companion_dir = p;
    fs::path euroc_cam;
    if (fs::exists(p / "mav0" / "cam0" / "data.csv")) euroc_cam = p / "mav0" / "cam0";
    else if (fs::exists(p / "cam0" / "data.csv")) euroc_cam = p / "cam0";
    if (fs::exists(p / "rgb.txt")) {
      seq.kind = "tum";
      entries = readRgbList(p / "rgb.txt");
    } else if (!euroc_cam.empty()) {
      seq.kind = "euroc";
      entries = readEurocCameraList(euroc_cam);
      SE3 T_body_camera;
      if (options.camera_path.empty() && fs::exists(euroc_cam / "sensor.yaml")) {
        seq.camera_path = (euroc_cam / "sensor.yaml").string();
        seq.camera = readEurocCamera(seq.camera_path, &T_body_camera);
      }
      const fs::path gt = euroc_cam.parent_path() / "state_groundtruth_estimate0" / "data.csv";
      if (fs::exists(gt)) {
        seq.groundtruth_path = gt.string();
        seq.groundtruth = readTrajectory(gt.string(), TrajectoryFormat::Euroc);
        for (auto& pose : *seq.groundtruth) pose.T_world_camera = pose.T_world_camera * T_body_camera;
      }
    } else {
      seq.kind = "images";
      entries = listImageFolder(p, options.images_fps);
    }
    seq.fps = medianRate(entries);
    const cv::Mat first = readGreyImage(entries.front().path);
    if (first.empty()) throw InputError(entries.front().path, "cannot be decoded as an image");
    seq.image_size = first.size();
    seq.frames = std::make_unique<ImageListSource>(std::move(entries), seq.image_size);
  } else {
    companion_dir = p.parent_path();
    seq.name = p.stem().string();
    auto video = mediaPlugin(path).openVideo(path);
    if (!video) throw InputError(path, "is neither a sequence folder nor a video OpenCV can open");
    const double fps = video->fps();
    const int count = video->frameCount();
    seq.image_size = video->frameSize();
    if (seq.image_size.area() <= 0) throw InputError(path, "video has no frames");
    seq.kind = "video";
    seq.fps = fps > 0 && std::isfinite(fps) ? fps : 30.0;
    seq.frames = std::make_unique<VideoSource>(path, std::move(video), count > 0 ? count : -1, seq.fps);
  }

  if (!options.camera_path.empty()) {
    seq.camera_path = options.camera_path;
    seq.camera = readCameraYaml(seq.camera_path);
  } else if (!seq.camera && fs::exists(companion_dir / "camera.yaml")) {
    seq.camera_path = (companion_dir / "camera.yaml").string();
    seq.camera = readCameraYaml(seq.camera_path);
  }
  if (seq.camera && (seq.camera->width != seq.image_size.width || seq.camera->height != seq.image_size.height))
    throw InputError(seq.camera_path, "camera is " + std::to_string(seq.camera->width) + "x" +
                                          std::to_string(seq.camera->height) + " but the images are " +
                                          std::to_string(seq.image_size.width) + "x" +
                                          std::to_string(seq.image_size.height));

  seq.target_path = options.target_path;
  if (seq.target_path.empty() && fs::exists(companion_dir / "target.yaml"))
    seq.target_path = (companion_dir / "target.yaml").string();
  if (!seq.target_path.empty()) {
    seq.target = readTargetYaml(seq.target_path, options.allow_symmetric_target);
    checkTargetFitsImages(*seq.target, seq.image_size, seq.target_path);
  }

  if (!seq.groundtruth && seq.kind != "video" && fs::exists(companion_dir / "groundtruth.txt")) {
    seq.groundtruth_path = (companion_dir / "groundtruth.txt").string();
    seq.groundtruth = readTrajectory(seq.groundtruth_path, TrajectoryFormat::Tum);
  }
  return seq;
}

}  // namespace slamcmp
