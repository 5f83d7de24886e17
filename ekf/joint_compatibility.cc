#include "ekf/joint_compatibility.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>

namespace slamcmp {

double chiSquaredQuantile(int dof, double probability) {
  // Standard normal quantile by Acklam's rational approximation (central region and tails).
  const double p = probability;
  const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                      1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                      6.680131188771972e+01, -1.328068155288572e+01};
  const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                      -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                      3.754408661907416e+00};
  double z;
  if (p < 0.02425) {
    const double q = std::sqrt(-2 * std::log(p));
    z = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p > 1 - 0.02425) {
    const double q = std::sqrt(-2 * std::log(1 - p));
    z = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else {
    const double q = p - 0.5, r = q * q;
    z = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  }
  const double k = dof, h = 2.0 / (9.0 * k);
  return k * std::pow(1 - h + z * std::sqrt(h), 3);
}

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
