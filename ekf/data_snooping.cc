#include "ekf/data_snooping.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "core/statistics.h"

namespace slamcmp {

Eigen::MatrixXd stackRows(const std::vector<Eigen::MatrixXd>& blocks) {
  Eigen::Index rows = 0;
  for (const Eigen::MatrixXd& b : blocks) rows += b.rows();
  Eigen::MatrixXd stacked(rows, blocks.empty() ? 0 : blocks.front().cols());
  rows = 0;
  for (const Eigen::MatrixXd& b : blocks) {
    stacked.middleRows(rows, b.rows()) = b;
    rows += b.rows();
  }
  return stacked;
}

int snoopBlocks(const Eigen::MatrixXd& P, double probability, std::vector<Eigen::MatrixXd>* blocks) {
  const Eigen::Index c = P.rows();
  int removed = 0;
  while (blocks->size() > 1) {
    const Eigen::MatrixXd stacked = stackRows(*blocks);
    const Eigen::MatrixXd H = stacked.leftCols(c);
    const Eigen::MatrixXd X = Eigen::MatrixXd::Identity(c, c) + H.transpose() * H * P;
    const Eigen::MatrixXd G = P * X.partialPivLu().inverse();
    const Eigen::VectorXd e = stacked.col(c) - H * (G * (H.transpose() * stacked.col(c)));
    double worst = 1.0;  // the statistic over its quantile
    size_t worst_block = 0;
    Eigen::Index start = 0;
    for (size_t i = 0; i < blocks->size(); ++i) {
      const Eigen::Index m = (*blocks)[i].rows();
      const Eigen::MatrixXd H_i = H.middleRows(start, m);
      const Eigen::MatrixXd covariance = Eigen::MatrixXd::Identity(m, m) - H_i * G * H_i.transpose();
      const Eigen::VectorXd e_i = e.segment(start, m);
      double ratio = e_i.dot(covariance.ldlt().solve(e_i)) / chiSquaredQuantile(static_cast<int>(m), probability);
      if (!std::isfinite(ratio)) ratio = std::numeric_limits<double>::infinity();
      if (ratio > worst) {
        worst = ratio;
        worst_block = i;
      }
      start += m;
    }
    if (worst <= 1.0) break;
    blocks->erase(blocks->begin() + static_cast<long>(worst_block));
    ++removed;
  }
  return removed;
}

}  // namespace slamcmp
