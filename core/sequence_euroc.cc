// A EuRoC MAV folder: mav0/cam0/data.csv lists "timestamp,filename" (ns, names under cam0/data),
// cam0/sensor.yaml holds the camera, state_groundtruth_estimate0/data.csv the body's poses.
#include <cmath>

#include "core/error.h"
#include "core/image_list.h"
#include "core/sequence_format.h"
#include "core/yaml.h"

namespace fs = std::filesystem;

namespace slamcmp {

namespace {

// The camera folder (mav0/cam0, or cam0 when the user names mav0 itself); empty if none.
fs::path eurocCameraFolder(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return {};
  for (const fs::path& cam : {path / "mav0" / "cam0", path / "cam0"})
    if (pathExists(cam / "data.csv")) return cam;
  return {};
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

// sensor.yaml: intrinsics [fu, fv, cu, cv], distortion_coefficients [k1 k2 p1 p2], resolution
// [w, h], T_BS (camera in body frame).
CameraModel readEurocCamera(const std::string& path, SE3* T_body_camera) {
  YamlFile f(path);
  // Kalibr's other models (a fisheye's equidistant distortion, the double sphere camera) read as a
  // pinhole with radial-tangential distortion would put every ray elsewhere.
  for (const auto& [key, model] : {std::pair<const char*, const char*>{"camera_model", "pinhole"},
                                   {"distortion_model", "radial-tangential"}}) {
    if (!f.has(key)) continue;
    const std::string given = f.getString(key);
    if (given != model && !(std::string(key) == "distortion_model" && given == "radtan"))
      throw InputError(path + ": " + key, "'" + given + "' is not read: only a " + model +
                                              " camera (EuRoC's), or give a camera.yaml with --camera");
  }
  const auto k = readNumberList(f, "intrinsics", 4);
  const auto d = readNumberList(f, "distortion_coefficients", 4);
  const auto r = readNumberList(f, "resolution", 2);
  for (const double side : r)  // converted to int below: a fraction or 1e300 would not survive it
    if (!(side >= 1 && side <= 100000) || side != std::floor(side))
      throw InputError(path + ": resolution", "must be two whole numbers of pixels in [1, 100000], got " +
                                                  std::to_string(r[0]) + ", " + std::to_string(r[1]));
  CameraModel c;
  c.width = static_cast<int>(r[0]);
  c.height = static_cast<int>(r[1]);
  c.fx = k[0], c.fy = k[1], c.cx = k[2], c.cy = k[3];
  c.num_distortion = 4;
  for (int i = 0; i < 4; ++i) c.distortion[i] = d[i];
  checkPlausibleIntrinsics(c, path, "intrinsics");  // first: its messages name this file's field
  c.check(path);
  const auto T = readNumberList(f, "T_BS", 16);
  Mat3 R;
  R << T[0], T[1], T[2], T[4], T[5], T[6], T[8], T[9], T[10];
  // Projected onto the nearest rotation below, so a rounded one is fine; all zeros, a reflection
  // or a scaled matrix is not a camera pose in the body frame.
  const double orthogonality = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (orthogonality > 1e-2 || R.determinant() < 0.9)
    throw InputError(path + ": T_BS", "its 3x3 part is not a rotation (det " + std::to_string(R.determinant()) +
                                          ", |R^T R - I| up to " + std::to_string(orthogonality) + ")");
  if (T[12] != 0 || T[13] != 0 || T[14] != 0 || T[15] != 1)
    throw InputError(path + ": T_BS", "its last row must be 0 0 0 1");
  *T_body_camera = SE3(nearestRotation(R), Vec3(T[3], T[7], T[11]));
  return c;
}

class EurocFormat : public SequenceFormat {
 public:
  std::string name() const override { return "euroc"; }
  bool detect(const fs::path& path) const override { return !eurocCameraFolder(path).empty(); }
  Sequence open(const fs::path& path, const SequenceOpenOptions& options) const override {
    const fs::path cam = eurocCameraFolder(path);
    std::vector<ImageEntry> entries =
        readImageList(cam / "data.csv", {"timestamp,filename", ',', 1e9, cam / "data", options.stop_on_interrupt,
                                          options.read_images});
    const double fps = medianRate(entries);
    Sequence seq = imageListSequence(std::move(entries), fps, options.read_images);
    SE3 T_body_camera;
    if (options.read_camera && options.camera_path.empty() && pathExists(cam / "sensor.yaml")) {
      seq.camera_path = (cam / "sensor.yaml").string();
      seq.camera = readEurocCamera(seq.camera_path, &T_body_camera);
    }
    const fs::path gt = cam.parent_path() / "state_groundtruth_estimate0" / "data.csv";
    if (pathExists(gt)) {
      seq.groundtruth_path = gt.string();
      seq.groundtruth = readTrajectory(gt.string(), TrajectoryFormat::Euroc);
      for (auto& pose : *seq.groundtruth) pose.T_world_camera = pose.T_world_camera * T_body_camera;
    }
    return seq;
  }
};

}  // namespace

const SequenceFormat& eurocFormat() {
  static const EurocFormat format;
  return format;
}

}  // namespace slamcmp
