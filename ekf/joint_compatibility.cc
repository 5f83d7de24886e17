#include "ekf/joint_compatibility.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>

#include "core/statistics.h"

namespace slamcmp {

namespace {

struct Search {
  const std::vector<Vec2>& predicted;
  const Eigen::MatrixXd& S;
  const std::vector<std::vector<Vec2>>& candidates;
  std::vector<double> threshold;  // chi2 quantile by number of pairs
  std::vector<int> order;         // features in the order they are decided
  std::vector<int> assignment, best;
  int best_pairs = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  int nodes = 0, max_nodes = 0;

  // Mahalanobis distance of the stacked innovation of the current pairs; -1 if S is not invertible.
  double jointDistance() const {
    std::vector<int> paired;
    for (int f : order)
      if (assignment[f] >= 0) paired.push_back(f);
    const int k = static_cast<int>(paired.size());
    Eigen::VectorXd nu(2 * k);
    Eigen::MatrixXd S_sub(2 * k, 2 * k);
    for (int a = 0; a < k; ++a) {
      nu.segment<2>(2 * a) = candidates[paired[a]][assignment[paired[a]]] - predicted[paired[a]];
      for (int b = 0; b < k; ++b) S_sub.block<2, 2>(2 * a, 2 * b) = S.block<2, 2>(2 * paired[a], 2 * paired[b]);
    }
    const Eigen::LLT<Eigen::MatrixXd> llt(S_sub);
    if (llt.info() != Eigen::Success) return -1;
    return nu.dot(llt.solve(nu));
  }

  void visit(int depth, int pairs, double d2) {
    if (++nodes > max_nodes) return;
    const int m = static_cast<int>(order.size());
    if (depth == m) {
      if (pairs > best_pairs || (pairs == best_pairs && d2 < best_d2)) {
        best_pairs = pairs;
        best_d2 = d2;
        best = assignment;
      }
      return;
    }
    if (pairs + (m - depth) < best_pairs) return;  // cannot pair as many as the best
    const int f = order[depth];
    const Mat2 S_ff = S.block<2, 2>(2 * f, 2 * f);
    for (int c = 0; c < static_cast<int>(candidates[f].size()); ++c) {
      const Vec2 nu = candidates[f][c] - predicted[f];
      if (!(nu.dot(S_ff.ldlt().solve(nu)) <= threshold[1])) continue;  // individually incompatible
      assignment[f] = c;
      const double d2_new = jointDistance();
      if (d2_new >= 0 && d2_new <= threshold[pairs + 1]) visit(depth + 1, pairs + 1, d2_new);
    }
    assignment[f] = -1;
    visit(depth + 1, pairs, d2);
  }
};

}  // namespace

std::vector<int> jointCompatibleAssociation(const std::vector<Vec2>& predicted, const Eigen::MatrixXd& S,
                                            const std::vector<std::vector<Vec2>>& candidates,
                                            double probability, int max_nodes) {
  const int m = static_cast<int>(predicted.size());
  Search s{predicted, S, candidates, {}, {}, std::vector<int>(m, -1), std::vector<int>(m, -1), 0,
           std::numeric_limits<double>::infinity(), 0, max_nodes};
  s.threshold.push_back(0.0);
  for (int k = 1; k <= m; ++k) s.threshold.push_back(chiSquaredQuantile(2 * k, probability));
  // Features with fewer candidates first: unambiguous matches constrain the rest early.
  for (int i = 0; i < m; ++i)
    if (!candidates[i].empty()) s.order.push_back(i);
  std::stable_sort(s.order.begin(), s.order.end(),
                   [&](int a, int b) { return candidates[a].size() < candidates[b].size(); });
  s.visit(0, 0, 0.0);
  return s.best;
}

}  // namespace slamcmp
