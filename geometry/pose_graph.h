#pragma once
// Pose-graph optimisation: poses corrected so that the relative motions between them stay as
// measured (each with its own uncertainty) while some poses are held at known values. With a
// chain of keyframes held at both ends (the board seen before and after a gap), the drift the chain
// accumulated is spread along it. Levenberg-Marquardt on sparse normal equations.
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

struct PoseGraphEdge {
  int from = 0, to = 0;
  SE3 T_from_to;                    // measured: pose `to` in the frame of pose `from`
  double sigma_rotation = 1e-3;     // radians, per axis
  double sigma_translation = 1e-3;  // metres, per axis
};

// Poses as T_world_node; fixed[i] holds pose i. Returns the optimised poses (the fixed ones
// unchanged). The residual of an edge is the rotation vector and translation of
// T_from_to^-1 T_from^-1 T_to.
std::vector<SE3> optimisePoseGraph(std::vector<SE3> T_world_node, const std::vector<char>& fixed,
                                   const std::vector<PoseGraphEdge>& edges, int max_iterations = 10);

}  // namespace slamcmp
