#pragma once
// The essential matrix from normalised correspondences (thesis eqs. 3.27 to 3.37): normalised
// 8-point algorithm, singular values forced to (1, 1, 0), the four (R, t) candidates and the
// cheirality test. Convention: x_b^T E x_a = 0 with E = [t]x R, where (R, t) = T_b_a maps points
// of camera a into camera b (p_b = R p_a + t) and x are undistorted normalised coordinates.
// Pose direction (geometry/'s convention, camera from world, camera a being the world): T_b_a.
#include <array>
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

// Least-squares E from n >= 8 correspondences (Hartley-normalised, thesis eqs. 3.32 to 3.34),
// projected onto the essential manifold (singular values 1, 1, 0).
Mat3 essentialEightPoint(const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b);

// The four (R, t) of E (eqs. 3.35 to 3.37): R = U W V^T or U W^T V^T, t = +-u3 (unit length).
std::array<SE3, 4> decomposeEssential(const Mat3& E);

// Points in front of both cameras for T_b_a (triangulated by closest points of the rays).
int countInFront(const SE3& T_b_a, const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b);

// The candidate with the most points in front of both cameras; *in_front receives the count.
SE3 selectByCheirality(const Mat3& E, const std::vector<Vec2>& xy_a, const std::vector<Vec2>& xy_b,
                       int* in_front = nullptr);

// Sampson distance of a correspondence to x_b^T E x_a = 0 (Hartley and Zisserman eq. 11.9), signed
// (the sign of x_b^T E x_a: a least-squares residual), in normalised units; NaN where it is not
// defined (x_a and x_b both at their epipoles, a coordinate not finite).
double signedSampsonDistance(const Mat3& E, const Vec2& xy_a, const Vec2& xy_b);
// Its square, +inf where it is not defined: such a correspondence fits no model.
double sampsonErrorSquared(const Mat3& E, const Vec2& xy_a, const Vec2& xy_b);

}  // namespace slamcmp
