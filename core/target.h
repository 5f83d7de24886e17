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
  // Refuses sizes under 2, non-positive squares, and boards with both counts odd or both even
  // (their orientation is ambiguous).
  void check(const std::string& where) const;
};

// target.yaml: type: chessboard, inner_corners_cols, inner_corners_rows, square_size.
ChessboardTarget readTargetYaml(const std::string& path);
void writeTargetYaml(const std::string& path, const ChessboardTarget& target);

}  // namespace slamcmp
