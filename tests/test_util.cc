#include "tests/test_util.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/wait.h>
#include <random>

namespace slamcmp::test {

TempDir::TempDir() {
  std::random_device rd;
  const auto base = std::filesystem::temp_directory_path();
  for (;;) {
    const auto p = base / ("slamcmp-test-" + std::to_string(rd()));
    if (std::filesystem::create_directory(p)) {
      path_ = p.string();
      break;
    }
  }
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

namespace {
std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

CommandResult runSlamcmp(const std::string& args) {
  const char* bin = std::getenv("SLAMCMP_BIN");
  CommandResult r;
  if (!bin) {
    ADD_FAILURE() << "SLAMCMP_BIN is not set (run the tests through ctest)";
    return r;
  }
  TempDir tmp;
  const std::string cmd = std::string(bin) + " " + args + " > " + tmp.file("out") + " 2> " +
                          tmp.file("err") + " < /dev/null";
  const int status = std::system(cmd.c_str());
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readAll(tmp.file("out"));
  r.err = readAll(tmp.file("err"));
  return r;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

void writeLoopedSequence(const std::string& dir, const std::string& rendered_name, int rendered, int frames) {
  const std::filesystem::path source = std::filesystem::path(dir).parent_path() / rendered_name;
  std::filesystem::create_directories(dir);
  for (const char* f : {"camera.yaml", "target.yaml"}) std::filesystem::copy_file(source / f, dir + "/" + f);
  std::ostringstream list;
  for (int i = 0; i < frames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.png", i % rendered);
    list << 0.1 * i << " ../" << rendered_name << "/rgb/" << name << "\n";
  }
  writeText(dir + "/rgb.txt", list.str());
}

Eigen::MatrixXd numericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                const Eigen::VectorXd& x, double step) {
  Eigen::MatrixXd J(f(x).size(), x.size());
  for (int c = 0; c < x.size(); ++c) {
    Eigen::VectorXd xp = x, xm = x;
    xp[c] += step;
    xm[c] -= step;
    J.col(c) = (f(xp) - f(xm)) / (2 * step);
  }
  return J;
}

void expectJacobianMatchesNumeric(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                  const Eigen::VectorXd& x, const Eigen::MatrixXd& J, double tol,
                                  double step) {
  const Eigen::MatrixXd numeric = numericJacobian(f, x, step);
  ASSERT_EQ(J.rows(), numeric.rows());
  ASSERT_EQ(J.cols(), numeric.cols());
  for (int c = 0; c < numeric.cols(); ++c)
    for (int r = 0; r < numeric.rows(); ++r)
      EXPECT_NEAR(J(r, c), numeric(r, c), tol * std::max(1.0, std::abs(numeric(r, c))))
          << "d f[" << r << "] / d x[" << c << "]";
}

std::vector<std::string> readLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

Vec2 rollingShutterProjection(const CameraModel& camera, double readout,
                              const std::function<SE3(double)>& T_world_camera_at, const Vec3& p_world) {
  auto row_gap = [&](double v) {
    return camera.project(T_world_camera_at(camera.rowTime(readout, v)).inverse() * p_world).y() - v;
  };
  double lo = 0, hi = camera.height - 1.0;
  EXPECT_LT(row_gap(lo) * row_gap(hi), 0.0) << "the point does not cross the image's rows once";
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (row_gap(lo) * row_gap(mid) <= 0 ? hi : lo) = mid;
  }
  return camera.project(T_world_camera_at(camera.rowTime(readout, lo)).inverse() * p_world);
}

}  // namespace slamcmp::test
