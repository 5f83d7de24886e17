#pragma once
// Umeyama's least-squares similarity between two registered point sets (Umeyama, PAMI 1991,
// eqs. 34 to 43), computed as evo's geometry.umeyama_alignment does so that aligned errors agree.
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

// p_to = scale * R * p_from + t.
struct Similarity3 {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  double scale = 1.0;
  Vec3 operator*(const Vec3& p_from) const { return scale * (R * p_from) + t; }
};

// The similarity (scale fixed to 1 unless with_scale) minimising sum |p_to - (s R p_from + t)|^2.
// Throws InputError for fewer than 3 pairs, or points whose covariance has rank below 2 (all on one
// line: the rotation about it is undetermined; evo's test, singular values above machine epsilon).
Similarity3 alignUmeyama(const std::vector<Vec3>& p_from, const std::vector<Vec3>& p_to,
                         bool with_scale);

// The positions' RMS spread about their centroid along the principal axes, ascending (the square
// roots of their covariance's eigenvalues): how far an alignment's rotation is pinned down.
Vec3 principalSpread(const std::vector<Vec3>& positions);

}  // namespace slamcmp
