// Baarda's data snooping (ekf/data_snooping.h) against the test it stands for, computed here by
// brute force: each block's innovation against the Kalman update by the prior and all the other
// blocks, nu^T (H_i P_others H_i^T + I)^-1 nu, over its chi-squared quantile.
#include "ekf/data_snooping.h"

#include <cmath>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <gtest/gtest.h>

namespace slamcmp {
namespace {

// Block i of the whitened rows [H | r] (noise I, prior on the state N(0, P)) tested against the
// update by the prior and every other block: the information form, then the innovation.
double bruteForceStatistic(const Eigen::Matrix2d& P, const std::vector<Eigen::MatrixXd>& blocks, size_t i) {
  Eigen::Matrix2d information = P.inverse();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (size_t j = 0; j < blocks.size(); ++j) {
    if (j == i) continue;
    const Eigen::MatrixXd H = blocks[j].leftCols(2);
    information += H.transpose() * H;
    b += H.transpose() * blocks[j].col(2);
  }
  const Eigen::Matrix2d P_others = information.inverse();
  const Eigen::MatrixXd H_i = blocks[i].leftCols(2);
  const Eigen::VectorXd nu = blocks[i].col(2) - H_i * (P_others * b);
  const Eigen::MatrixXd S = H_i * P_others * H_i.transpose() + Eigen::MatrixXd::Identity(H_i.rows(), H_i.rows());
  return nu.dot(S.ldlt().solve(nu));
}

// A 2-value state with a loose prior, one precise observation (H about 10: its (S^-1)_ii, the
// covariance of its residual, has a diagonal of 0.03-0.04, far from I) and two loose ones (H about
// 1), each of 2 rows; the precise one is 18 (whitened units) off. Brute force: its statistic is
// 10.5, over the 95 % quantile of 2 dof (-2 ln 0.05 = 5.99), the loose ones' 1.2 and 3.6, and
// without it both loose ones pass: it alone is removed and the loose ones are kept in order. Its
// e^T e (the residual not scaled by its covariance) is 30 times smaller, 0.35, and would keep it
// (and every other block: theirs are 1.2 and 3.5).
TEST(DataSnooping, APreciseBlockOffByMoreThanItsResidualCovarianceIsRemoved) {
  Eigen::Matrix2d P;
  P << 1.0, 0.3, 0.3, 0.8;
  const Eigen::Vector2d x(0.1, -0.2);  // the state's error the observations see
  Eigen::Matrix2d H0, H1, H2;
  H0 << 10, 1, -2, 9;
  H1 << 1, 0.2, 0.1, 1;
  H2 << 0.9, -0.3, 0.2, 1.1;
  const auto block = [](const Eigen::Matrix2d& H, const Eigen::Vector2d& r) {
    Eigen::MatrixXd b(2, 3);
    b << H, r;
    return b;
  };
  const std::vector<Eigen::MatrixXd> all{block(H0, H0 * x + Eigen::Vector2d(14, -11)),
                                         block(H1, H1 * x + Eigen::Vector2d(0.3, -0.2)),
                                         block(H2, H2 * x + Eigen::Vector2d(-0.1, 0.25))};
  const double probability = 0.95, quantile = -2 * std::log(1 - probability);  // chi-squared, 2 dof
  EXPECT_GT(bruteForceStatistic(P, all, 0), quantile);
  EXPECT_LT(bruteForceStatistic(P, all, 1), quantile);
  EXPECT_LT(bruteForceStatistic(P, all, 2), quantile);
  const std::vector<Eigen::MatrixXd> loose{all[1], all[2]};
  EXPECT_LT(bruteForceStatistic(P, loose, 0), quantile);
  EXPECT_LT(bruteForceStatistic(P, loose, 1), quantile);

  std::vector<Eigen::MatrixXd> blocks = all;
  EXPECT_EQ(snoopBlocks(P, probability, &blocks), 1);
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[0], all[1]);
  EXPECT_EQ(blocks[1], all[2]);
}

}  // namespace
}  // namespace slamcmp
