#pragma once
// Baarda's data snooping ("A testing procedure for use in geodetic networks", 1968) for a Kalman
// update from blocks of whitened rows [H | r] (noise covariance I), one block per observation
// (a tracked feature's rows in the MSCKF): each block tested against all the others and the prior.
#include <vector>

#include <Eigen/Core>

namespace slamcmp {

// The blocks stacked into one matrix, in order.
Eigen::MatrixXd stackRows(const std::vector<Eigen::MatrixXd>& blocks);

// The update's residual e = r - H K r equals S^-1 r, with covariance S^-1 (S = H P H^T + I), so
// block i's e_i^T ((S^-1)_ii)^-1 e_i is chi-squared with its rows' dof when the observation is
// what the model says: it is the block's innovation against the update by all the others. The
// worst beyond its quantile at `probability` is removed from `blocks` and the test repeated until
// none fails (one block left: its test is the caller's own gate). A block whose statistic is not
// finite counts as failing. S^-1 = I - H G H^T with G = P (I + H^T H P)^-1 (the push-through
// identity: a c x c inverse, so each pass is linear in the rows). Returns the blocks removed.
int snoopBlocks(const Eigen::MatrixXd& P, double probability, std::vector<Eigen::MatrixXd>* blocks);

}  // namespace slamcmp
