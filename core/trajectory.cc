#include "core/trajectory.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <utility>

#include "core/error.h"
#include "core/format_string.h"
#include "core/text_file.h"

namespace slamcmp {

bool parseNumbers(const std::string& line, std::vector<double>* out) {
  out->clear();
  const char* p = line.c_str();
  while (*p) {
    while (*p == ' ' || *p == '\t' || *p == ',' || *p == '\r') ++p;
    if (!*p) break;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(p, &end);
    if (end == p) return false;
    if (*end && *end != ' ' && *end != '\t' && *end != ',' && *end != '\r') return false;
    out->push_back(v);
    p = end;
  }
  return true;
}

void checkPlausibleSeconds(double seconds, const std::string& where) {
  constexpr double kMaxSeconds = 1e11;
  if (!std::isfinite(seconds)) throw InputError(where, "timestamp is not finite");
  if (std::abs(seconds) <= kMaxSeconds) return;
  std::string why = formatString("timestamp %g is not plausible as seconds (beyond %g s)", seconds, kMaxSeconds);
  // Another unit since 1970 (1e8 s is 1973) if one brings it there.
  for (const auto& [factor, unit] : {std::pair{1e9, "nanoseconds"}, {1e6, "microseconds"}, {1e3, "milliseconds"}})
    if (std::abs(seconds) / factor >= 1e8 && std::abs(seconds) / factor <= kMaxSeconds) {
      why += std::string(": it looks like ") + unit +
             formatString(" (%g s); the file must be in seconds", seconds / factor);
      break;
    }
  throw InputError(where, why);
}

namespace {

// Beyond 1e100 the squared errors of ATE and RPE, summed over a trajectory, overflow to inf and
// their statistics to NaN (1e200 printed NaN with exit 0). Any real trajectory, in metres or a
// scale-free run's units, is far inside.
void checkPlausiblePosition(const Vec3& p, const std::string& where) {
  constexpr double kMaxMetres = 1e100;
  for (int k = 0; k < 3; ++k)
    if (std::abs(p[k]) > kMaxMetres)
      throw InputError(where, formatString("position %c %g is not plausible (beyond %g: its square overflows)", "xyz"[k], p[k],
                                           kMaxMetres));
}

bool isCommentOrBlank(const std::string& line) {
  for (char c : line) {
    if (c == '#' || c == '%') return true;
    if (c != ' ' && c != '\t' && c != '\r') return false;
  }
  return true;
}


// Reads data lines as numbers; calls f(numbers, line_number) for each.
template <class F>
void forEachDataLine(const std::string& path, F&& f) {
  std::ifstream in = openTextFile(path);
  std::string line;
  std::vector<double> v;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line_number == 1) dropByteOrderMark(&line);
    if (isCommentOrBlank(line)) continue;
    if (!parseNumbers(line, &v)) throw InputError(atLine(path, line_number), "a field is not a number");
    for (double x : v)
      if (!std::isfinite(x)) throw InputError(atLine(path, line_number), "NaN or infinite value");
    f(v, line_number);
  }
}

Quat checkedQuat(double w, double x, double y, double z, const std::string& where) {
  Quat q(w, x, y, z);
  const double n = q.norm();
  if (std::abs(n - 1.0) > 0.05)
    throw InputError(where, "quaternion norm is " + std::to_string(n) + ", not 1");
  return q.normalized();
}

// A repeated timestamp is kept, in file order, as evo keeps it: published ground truth holds a
// few (TUM fr2_desk, evo's EuRoC V1_02 estimate).
void checkIncreasing(const Trajectory& t, const std::string& where) {
  if (t.size() >= 2 && !(t.back().timestamp >= t[t.size() - 2].timestamp))
    throw InputError(where, "timestamp goes back in time");
}

std::vector<double> readKittiTimes(const std::string& path) {
  std::vector<double> times;
  forEachDataLine(path, [&](const std::vector<double>& v, int n) {
    if (v.size() != 1) throw InputError(atLine(path, n), "expected one timestamp");
    checkPlausibleSeconds(v[0], atLine(path, n));
    if (!times.empty() && v[0] < times.back())
      throw InputError(atLine(path, n), "timestamp goes back in time");
    times.push_back(v[0]);
  });
  return times;
}

}  // namespace

TrajectoryFormat detectTrajectoryFormat(const std::string& path) {
  const bool csv = lowerExtension(path) == ".csv";
  std::ifstream in = openTextFile(path);
  std::string line;
  std::vector<double> v;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (n == 1) dropByteOrderMark(&line);
    if (isCommentOrBlank(line)) continue;
    // EuRoC's .csv is comma-separated; a TUM file saved as .csv (spaces) read as EuRoC would have
    // its seconds taken for nanoseconds and pair poses far apart without a word.
    if (csv && line.find(',') != std::string::npos) return TrajectoryFormat::Euroc;
    if (!parseNumbers(line, &v)) throw InputError(atLine(path, n), "a field is not a number");
    if (v.size() == 8) return TrajectoryFormat::Tum;
    if (v.size() == 12) return TrajectoryFormat::Kitti;
    throw InputError(atLine(path, n), "has " + std::to_string(v.size()) +
                                          " fields: expected 8 (TUM) or 12 (KITTI)");
  }
  throw InputError(path, "holds no pose");
}

TrajectoryFormat parseTrajectoryFormat(const std::string& name) {
  if (name == "auto") return TrajectoryFormat::Auto;
  if (name == "tum") return TrajectoryFormat::Tum;
  if (name == "euroc") return TrajectoryFormat::Euroc;
  if (name == "kitti") return TrajectoryFormat::Kitti;
  throw InputError("--format", "unknown trajectory format '" + name + "' (auto, tum, euroc, kitti)");
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format,
                          const std::string& kitti_times_path) {
  if (format == TrajectoryFormat::Auto) format = detectTrajectoryFormat(path);
  Trajectory out;
  std::vector<double> times;
  if (format == TrajectoryFormat::Kitti && !kitti_times_path.empty())
    times = readKittiTimes(kitti_times_path);

  forEachDataLine(path, [&](const std::vector<double>& v, int n) {
    const std::string where = atLine(path, n);
    StampedPose p;
    switch (format) {
      case TrajectoryFormat::Tum:
        if (v.size() != 8)
          throw InputError(where, "has " + std::to_string(v.size()) +
                                      " fields: TUM needs 8 (timestamp tx ty tz qx qy qz qw)");
        p.timestamp = v[0];
        p.T_world_camera = SE3(checkedQuat(v[7], v[4], v[5], v[6], where), Vec3(v[1], v[2], v[3]));
        break;
      case TrajectoryFormat::Euroc:
        if (v.size() < 8)
          throw InputError(where, "has " + std::to_string(v.size()) +
                                      " fields: EuRoC needs at least 8 (ns px py pz qw qx qy qz)");
        p.timestamp = v[0] / 1e9;  // correctly rounded, as evo (x * 1e-9 is off by 1 ulp at times)
        p.T_world_camera = SE3(checkedQuat(v[4], v[5], v[6], v[7], where), Vec3(v[1], v[2], v[3]));
        break;
      case TrajectoryFormat::Kitti: {
        if (v.size() != 12)
          throw InputError(where, "has " + std::to_string(v.size()) + " fields: KITTI needs 12 (3x4)");
        Mat3 R;
        R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
        if ((R.transpose() * R - Mat3::Identity()).norm() > 1e-2 || R.determinant() < 0)
          throw InputError(where, "the 3x3 part is not a rotation");
        const size_t index = out.size();
        if (!times.empty() && index >= times.size())
          throw InputError(kitti_times_path, "has fewer timestamps than " + path + " has poses");
        p.timestamp = times.empty() ? static_cast<double>(index) : times[index];
        // Kept as written when orthonormal to print precision, as evo keeps it (its RPE on KITTI
        // files moves by 5e-5 relative otherwise); projected onto SO(3) when further off.
        const bool orthonormal =
            (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-5;
        p.T_world_camera = SE3(orthonormal ? R : nearestRotation(R), Vec3(v[3], v[7], v[11]));
        break;
      }
      case TrajectoryFormat::Auto:
        break;
    }
    checkPlausibleSeconds(p.timestamp, where);
    checkPlausiblePosition(p.T_world_camera.t(), where);
    out.push_back(p);
    checkIncreasing(out, where);
  });
  if (out.empty()) throw InputError(path, "holds no pose");
  if (!times.empty() && times.size() != out.size())
    throw InputError(kitti_times_path, "has " + std::to_string(times.size()) + " timestamps but " +
                                           path + " has " + std::to_string(out.size()) + " poses");
  return out;
}

StampedPose readSingleTumPose(const std::string& path) {
  const Trajectory poses = readTrajectory(path, TrajectoryFormat::Tum);
  if (poses.size() > 1) {
    int data_lines = 0;
    forEachDataLine(path, [&](const std::vector<double>&, int n) {
      if (++data_lines == 2)
        throw InputError(atLine(path, n), "a second pose: the file must hold only the first camera's (it holds " +
                                              std::to_string(poses.size()) + ")");
    });
  }
  return poses.front();
}

std::string formatTumLine(const StampedPose& p) {
  const Quat q = p.T_world_camera.quat();
  const Vec3& t = p.T_world_camera.t();
  return formatString("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f", p.timestamp, t.x(), t.y(), t.z(), q.x(),
                      q.y(), q.z(), q.w());
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory) {
  std::ofstream out(path);
  if (!out) throw InputError(path, "cannot be written");
  out << "# timestamp tx ty tz qx qy qz qw (T_world_camera)\n";
  for (const auto& p : trajectory) out << formatTumLine(p) << '\n';
  if (!out) throw InputError(path, "write failed");
}

}  // namespace slamcmp
