#include "geometry/pose_graph.h"

#include <algorithm>
#include <cassert>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

namespace slamcmp {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// Right perturbation: T exp(delta), delta = (rotation vector, translation in T's frame).
SE3 perturb(const SE3& T, const Vec6& delta) {
  return T * SE3(rotationFromRotvec(delta.head<3>()), delta.tail<3>());
}

Vec6 edgeResidual(const PoseGraphEdge& e, const SE3& T_from, const SE3& T_to) {
  const SE3 E = e.T_from_to.inverse() * (T_from.inverse() * T_to);
  Vec6 r;
  r << rotvecFromRotation(E.R()) / e.sigma_rotation, E.t() / e.sigma_translation;
  return r;
}

double totalCost(const std::vector<SE3>& T, const std::vector<PoseGraphEdge>& edges) {
  double c = 0;
  for (const PoseGraphEdge& e : edges) c += edgeResidual(e, T[e.from], T[e.to]).squaredNorm();
  return c;
}

}  // namespace

std::vector<SE3> optimisePoseGraph(std::vector<SE3> T, const std::vector<char>& fixed,
                                   const std::vector<PoseGraphEdge>& edges, int max_iterations) {
  assert(fixed.size() == T.size());
  std::vector<int> block(T.size(), -1);
  int n = 0;
  for (size_t i = 0; i < T.size(); ++i)
    if (!fixed[i]) block[i] = n++;
  if (n == 0) return T;
  assert(std::all_of(edges.begin(), edges.end(), [&](const PoseGraphEdge& e) {
    return e.from >= 0 && e.to >= 0 && e.from < static_cast<int>(T.size()) && e.to < static_cast<int>(T.size());
  }));
  double cost = totalCost(T, edges);
  double lambda = 1e-6;
  constexpr double kStep = 1e-7;
  for (int it = 0; it < max_iterations; ++it) {
    // Normal equations with numeric Jacobians (6 x 12 per edge; the graphs here are small).
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(6 * n);
    for (const PoseGraphEdge& e : edges) {
      const int b[2] = {block[e.from], block[e.to]};
      if (b[0] < 0 && b[1] < 0) continue;
      const Vec6 r = edgeResidual(e, T[e.from], T[e.to]);
      Eigen::Matrix<double, 6, 6> J[2];
      for (int side = 0; side < 2; ++side) {
        if (b[side] < 0) continue;
        for (int k = 0; k < 6; ++k) {
          Vec6 d = Vec6::Zero();
          d(k) = kStep;
          const SE3 from = side == 0 ? perturb(T[e.from], d) : T[e.from];
          const SE3 to = side == 1 ? perturb(T[e.to], d) : T[e.to];
          J[side].col(k) = (edgeResidual(e, from, to) - r) / kStep;
        }
      }
      for (int s = 0; s < 2; ++s) {
        if (b[s] < 0) continue;
        g.segment<6>(6 * b[s]) += J[s].transpose() * r;
        for (int u = 0; u < 2; ++u) {
          if (b[u] < 0) continue;
          const Mat6 H = J[s].transpose() * J[u];
          for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j) triplets.emplace_back(6 * b[s] + i, 6 * b[u] + j, H(i, j));
        }
      }
    }
    Eigen::SparseMatrix<double> H(6 * n, 6 * n);
    H.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::VectorXd diagonal = H.diagonal();
    bool accepted = false;
    for (int attempt = 0; attempt < 8 && !accepted; ++attempt) {
      Eigen::SparseMatrix<double> A = H;
      for (int i = 0; i < 6 * n; ++i) A.coeffRef(i, i) += lambda * std::max(diagonal(i), 1e-9);
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
      const Eigen::VectorXd delta = solver.solve(-g);
      if (solver.info() != Eigen::Success || !delta.allFinite()) {
        lambda *= 10;
        continue;
      }
      std::vector<SE3> candidate = T;
      for (size_t i = 0; i < T.size(); ++i)
        if (block[i] >= 0) candidate[i] = perturb(T[i], delta.segment<6>(6 * block[i]));
      const double c = totalCost(candidate, edges);
      if (c < cost) {
        const double decrease = cost - c;
        T.swap(candidate);
        cost = c;
        lambda = std::max(lambda * 0.1, 1e-12);
        accepted = true;
        if (decrease < 1e-10 * (1 + cost)) it = max_iterations;
      } else {
        lambda *= 10;
      }
    }
    if (!accepted) break;
  }
  for (SE3& pose : T) pose = SE3(nearestRotation(pose.R()), pose.t());
  return T;
}

}  // namespace slamcmp
