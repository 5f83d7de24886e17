#pragma once
// The planar chessboard that defines the world frame (SPEC section 2).
#include <string>
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

struct ChessboardTarget {
  int cols = 0;              // inner corners along X
  int rows = 0;              // inner corners along Y
  double square_size = 0.0;  // metres

  int numCorners() const { return cols * rows; }
  // Inner corner (i, j) is at (i*s, j*s, 0); index = j * cols + i (OpenCV's row-major order).
  Vec3 cornerWorld(int i, int j) const { return Vec3(i * square_size, j * square_size, 0.0); }
  std::vector<Vec3> cornersWorld() const;
  // The four outermost inner corners: (0,0), (cols-1,0), (cols-1,rows-1), (0,rows-1).
  std::vector<Vec3> outerCornersWorld() const;
  // Both counts odd or both even: a 180 degree turn maps the board onto itself, so its frame
  // (SPEC section 2) is ambiguous: `run` picks one origin and keeps it (chooseSymmetricOrder).
  bool symmetric() const { return cols % 2 == rows % 2; }
  // Refuses sizes under 2, non-positive squares, and symmetric boards unless allow_symmetric.
  void check(const std::string& where, bool allow_symmetric = false) const;
};

// target.yaml: type: chessboard, inner_corners_cols, inner_corners_rows, square_size.
// allow_symmetric: for calibration, where the board's orientation does not matter, and for `run`,
// which warns and keeps the origin by continuity.
ChessboardTarget readTargetYaml(const std::string& path, bool allow_symmetric = false);
void writeTargetYaml(const std::string& path, const ChessboardTarget& target);

}  // namespace slamcmp
