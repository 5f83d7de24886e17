#pragma once
// Data association for one frame's matches: Joint Compatibility Branch and Bound (Neira and Tardos
// 2001). Each measured feature may have several candidate matches (a chessboard corner looks like
// its neighbours); the chosen set pairs as many features as possible whose stacked innovation
// passes a chi-squared test under the joint innovation covariance, the smallest Mahalanobis
// distance breaking ties. A feature left unpaired counts as a failed match.
#include <vector>

#include <Eigen/Core>

#include "core/geometry.h"

namespace slamcmp {

// predicted[i]: feature i's predicted pixel; S: the joint innovation covariance of all features
// (2m x 2m, feature i at rows 2i, 2i+1); candidates[i]: its candidate pixels (each must also pass
// the test alone, chi2 of 2 dof). Returns, for each
// feature, the index of the chosen candidate or -1. Gives up refining after max_nodes search nodes
// (keeping the best found so far).
std::vector<int> jointCompatibleAssociation(const std::vector<Vec2>& predicted, const Eigen::MatrixXd& S,
                                            const std::vector<std::vector<Vec2>>& candidates,
                                            double probability, int max_nodes = 20000);

}  // namespace slamcmp
