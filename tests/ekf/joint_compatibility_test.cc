#include "ekf/joint_compatibility.h"

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

// Four board corners predicted with a large, strongly correlated uncertainty (the camera pose is
// the uncertain part): each sees its true corner and neighbours one square (50 px) away. The
// true corners are 3 px from the predictions, all shifted the same way.
TEST(JointCompatibility, PicksTheConsistentAssignmentAmongRepeatedCorners) {
  const std::vector<Vec2> predicted = {{200, 150}, {400, 150}, {400, 300}, {200, 300}};
  const int m = 4;
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(2 * m, 2 * m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) S.block<2, 2>(2 * i, 2 * j) = Mat2::Identity() * (i == j ? 1700.0 : 1600.0);
  const Vec2 shift(3, -2);
  std::vector<std::vector<Vec2>> candidates(m);
  // A neighbour listed first, the true corner second, another neighbour third.
  for (int i = 0; i < m; ++i)
    candidates[i] = {predicted[i] + shift + Vec2(50, 0) * (i % 2 ? -1 : 1), predicted[i] + shift,
                     predicted[i] + shift + Vec2(0, 50)};
  // Corner 2 also has its neighbour nearest: shifted by a square, inconsistent with the others.
  candidates[2].insert(candidates[2].begin(), predicted[2] + Vec2(-20, 0));
  const std::vector<int> choice = jointCompatibleAssociation(predicted, S, candidates, 0.99);
  EXPECT_EQ(choice, (std::vector<int>{1, 1, 2, 1}));
}

TEST(JointCompatibility, LeavesAnOutlierUnpaired) {
  const std::vector<Vec2> predicted = {{100, 100}, {300, 100}, {200, 250}};
  Eigen::MatrixXd S = Eigen::MatrixXd::Identity(6, 6) * 4.0;  // 2 px, independent
  const std::vector<std::vector<Vec2>> candidates = {{{101, 100}}, {{300, 99}}, {{205, 255}}};
  const std::vector<int> choice = jointCompatibleAssociation(predicted, S, candidates, 0.99);
  EXPECT_EQ(choice, (std::vector<int>{0, 0, -1}));
}

TEST(JointCompatibility, FeaturesWithoutCandidatesStayUnpaired) {
  const std::vector<int> choice =
      jointCompatibleAssociation({{10, 10}, {20, 20}}, Eigen::MatrixXd::Identity(4, 4), {{}, {{20.5, 20}}}, 0.99);
  EXPECT_EQ(choice, (std::vector<int>{-1, 0}));
}

}  // namespace
}  // namespace slamcmp
