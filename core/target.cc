#include "core/target.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/yaml.h"

namespace slamcmp {

namespace {

std::string formatNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

std::vector<Vec3> ChessboardTarget::cornersWorld() const {
  std::vector<Vec3> out;
  out.reserve(numCorners());
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) out.push_back(cornerWorld(i, j));
  return out;
}

std::vector<Vec3> ChessboardTarget::outerCornersWorld() const {
  return {cornerWorld(0, 0), cornerWorld(cols - 1, 0), cornerWorld(cols - 1, rows - 1),
          cornerWorld(0, rows - 1)};
}

void ChessboardTarget::check(const std::string& where, bool allow_symmetric) const {
  // Fewer than 3 corners along a side give no independent line to fit a homography or a
  // distortion to (and findChessboardCorners refuses them).
  if (cols < 3)
    throw InputError(where + ": inner_corners_cols", "a chessboard needs at least 3x3 inner corners, got " +
                                                         std::to_string(cols) + "x" + std::to_string(rows));
  if (rows < 3)
    throw InputError(where + ": inner_corners_rows", "a chessboard needs at least 3x3 inner corners, got " +
                                                         std::to_string(cols) + "x" + std::to_string(rows));
  if (symmetric() && !allow_symmetric)
    throw InputError(where, "inner corner counts " + std::to_string(cols) + "x" +
                                std::to_string(rows) +
                                " are both " + (cols % 2 ? "odd" : "even") +
                                ": exactly one must be odd, or the board's orientation is ambiguous");
  if (!(square_size > 0) || !std::isfinite(square_size))
    throw InputError(where + ": square_size", "must be positive and finite (metres)");
  // Metres: a printed board's squares are millimetres to decimetres; outside 0.1 mm .. 10 m the
  // number is in another unit (e.g. 40 for 40 mm) or a typo.
  if (square_size < 1e-4 || square_size > 10)
    throw InputError(where + ": square_size", "is " + formatNumber(square_size) +
                                                  " m, outside the plausible 0.0001 to 10 m (the unit is metres)");
}

ChessboardTarget readTargetYaml(const std::string& path, bool allow_symmetric) {
  YamlFile file(path);
  if (file.has("type")) {
    const std::string type = file.getString("type");
    if (type != "chessboard")
      throw InputError(path + ": type", "only 'chessboard' is supported, got '" + type + "'");
  }
  ChessboardTarget t;
  t.cols = file.getInt("inner_corners_cols");
  t.rows = file.getInt("inner_corners_rows");
  t.square_size = file.getDouble("square_size");
  t.check(path, allow_symmetric);
  return t;
}

void writeTargetYaml(const std::string& path, const ChessboardTarget& target) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::WRITE);
  } catch (const cv::Exception&) {
  }
  if (!fs.isOpened()) throw InputError(path, "cannot be written");
  fs << "type" << "chessboard";
  fs << "inner_corners_cols" << target.cols << "inner_corners_rows" << target.rows;
  fs << "square_size" << target.square_size;
}

}  // namespace slamcmp
