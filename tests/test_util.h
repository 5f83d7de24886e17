#pragma once
// Helpers shared by the test suites.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "core/camera.h"
#include "core/geometry.h"

namespace slamcmp::test {

// The real data beside the project (../shared/datasets), or "" when absent (a user's clone).
inline std::string sharedDatasets() {
  const std::filesystem::path p = std::filesystem::path(SLAMCMP_SOURCE_DIR) / ".." / "shared" / "datasets";
  return std::filesystem::exists(p) ? p.lexically_normal().string() : std::string();
}

// Use as: SLAMCMP_REQUIRE_SHARED(dir); then dir + "/vamr_checkerboard".
#define SLAMCMP_REQUIRE_SHARED(var)                                                        \
  const std::string var = ::slamcmp::test::sharedDatasets();                               \
  if (var.empty()) GTEST_SKIP() << "../shared/datasets is absent (a fresh clone): skipped"

// A fresh empty temporary folder for one test, removed with the object.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// What running the slamcmp binary printed and returned.
struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
// Runs the slamcmp binary (from ctest's SLAMCMP_BIN) with `args` (a shell-quoted string).
CommandResult runSlamcmp(const std::string& args);

// Writes `text` to `path`.
void writeText(const std::string& path, const std::string& text);
// A sequence folder `dir` that plays the first `rendered` frames of the rendered sequence beside
// it (`../<rendered_name>`, whose camera.yaml and target.yaml it copies) over and over, `frames` in
// all at 10 fps: a run long enough to be still going when a test interrupts it.
void writeLoopedSequence(const std::string& dir, const std::string& rendered_name, int rendered, int frames);
// The lines of a text file (none if it cannot be read).
std::vector<std::string> readLines(const std::string& path);

// Central differences of f: R^n -> R^m at x (m x n), each column from f(x +- step e_c).
Eigen::MatrixXd numericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x, double step = 1e-6);

// Central differences of f: R^n -> R^m at x, compared with the analytic J entry by entry:
// |J - J_numeric| <= tol * max(1, |J_numeric|).
void expectJacobianMatchesNumeric(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                  const Eigen::VectorXd& x, const Eigen::MatrixXd& J,
                                  double tol = 1e-6, double step = 1e-6);

// Where a rolling shutter (CameraModel::rowTime) images p_world, found without the code under
// test: the row v at which the camera T_world_camera_at(rowTime(readout, v)) projects it onto row
// v, by bisection over the image's height (the point must cross it once).
Vec2 rollingShutterProjection(const CameraModel& camera, double readout,
                              const std::function<SE3(double)>& T_world_camera_at, const Vec3& p_world);

}  // namespace slamcmp::test
