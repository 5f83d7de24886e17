#include "ekf/ekf_state.h"

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

// A state with the camera and two points whose covariance entries are all distinct.
EkfState stateWithTwoPoints() {
  EkfState s;
  s.reset(SE3::fromRotvec(Vec3(0.1, 0.2, 0.3), Vec3(1, 2, 3)), Eigen::Matrix<double, 13, 13>::Identity());
  s.append(Vec3(1, 1, 1), Mat3::Identity() * 2, Eigen::MatrixXd::Constant(3, 13, 0.1));
  s.append(Vec3(2, 2, 2), Mat3::Identity() * 3, Eigen::MatrixXd::Constant(3, 16, 0.2));
  return s;
}

TEST(EkfState, AppendPlacesBlocksAndCrossCovariances) {
  const EkfState s = stateWithTwoPoints();
  ASSERT_EQ(s.size(), 19);
  EXPECT_EQ(s.x().segment<3>(16), Vec3(2, 2, 2));
  EXPECT_DOUBLE_EQ(s.P()(14, 14), 2.0);
  EXPECT_DOUBLE_EQ(s.P()(17, 17), 3.0);
  EXPECT_DOUBLE_EQ(s.P()(17, 14), 0.2);
  EXPECT_DOUBLE_EQ(s.P()(14, 17), 0.2);
  EXPECT_DOUBLE_EQ(s.P()(0, 13), 0.1);
  EXPECT_TRUE(s.P().isApprox(s.P().transpose()));
}

TEST(EkfState, RemoveDropsRowsAndColumnsOfOneBlock) {
  EkfState s = stateWithTwoPoints();
  const Eigen::MatrixXd P_before = s.P();
  s.remove(13, 3);
  ASSERT_EQ(s.size(), 16);
  EXPECT_EQ(s.x().segment<3>(13), Vec3(2, 2, 2));
  EXPECT_TRUE(s.P().topLeftCorner(13, 13).isApprox(P_before.topLeftCorner(13, 13)));
  EXPECT_TRUE(s.P().block(13, 13, 3, 3).isApprox(P_before.block(16, 16, 3, 3)));
  EXPECT_TRUE(s.P().block(13, 0, 3, 13).isApprox(P_before.block(16, 0, 3, 13)));
}

TEST(EkfState, RenormalisationMakesQUnitAndTransformsCovariance) {
  EkfState s = stateWithTwoPoints();
  s.x().segment<4>(EkfState::kQ) *= 1.2;
  const Vec4 q = s.q();
  s.renormaliseQuaternion();
  EXPECT_NEAR(s.q().norm(), 1.0, 1e-15);
  // Covariance of q / |q| = J P_qq J^T, J = (I - n n^T)/|q|: no variance along q itself.
  const Vec4 n = q.normalized();
  EXPECT_NEAR(n.dot(s.P().block<4, 4>(EkfState::kQ, EkfState::kQ) * n), 0.0, 1e-14);
  // P_qq was I: J J^T = (I - n n^T) / |q|^2.
  EXPECT_NEAR(s.P()(EkfState::kQ + 1, EkfState::kQ + 1), (1 - n(1) * n(1)) / q.squaredNorm(), 1e-12);
}


TEST(EkfState, BlocksAppendedWithATailGoBeforeIt) {
  // The same three blocks, appended in order (point, clone, point) without a tail, and with the
  // clone in the tail: the second state is the first with its last two blocks swapped.
  EkfState plain;
  plain.reset(SE3::fromRotvec(Vec3(0.1, 0.2, 0.3), Vec3(1, 2, 3)), Eigen::Matrix<double, 13, 13>::Identity());
  EkfState tailed = plain;
  const Eigen::MatrixXd cross_1 = Eigen::MatrixXd::Constant(3, 13, 0.1);
  const Eigen::MatrixXd clone_cross = Eigen::MatrixXd::Constant(7, 16, 0.3);
  Eigen::MatrixXd cross_2 = Eigen::MatrixXd::Constant(3, 23, 0.2);
  cross_2.rightCols(7).setConstant(0.4);  // with the clone
  for (EkfState* s : {&plain, &tailed}) s->append(Vec3(1, 1, 1), Mat3::Identity() * 2, cross_1);
  plain.append(Eigen::VectorXd::Constant(7, 5), Eigen::MatrixXd::Identity(7, 7) * 5, clone_cross);
  EXPECT_EQ(tailed.appendToTail(Eigen::VectorXd::Constant(7, 5), Eigen::MatrixXd::Identity(7, 7) * 5, clone_cross), 16);
  plain.append(Vec3(2, 2, 2), Mat3::Identity() * 3, cross_2);
  EXPECT_EQ(tailed.append(Vec3(2, 2, 2), Mat3::Identity() * 3, cross_2), 16);
  ASSERT_EQ(tailed.size(), 26);
  EXPECT_EQ(tailed.tailSize(), 7);
  Eigen::VectorXi order(26);  // tailed index -> plain index
  for (int i = 0; i < 16; ++i) order[i] = i;
  for (int i = 0; i < 3; ++i) order[16 + i] = 23 + i;
  for (int i = 0; i < 7; ++i) order[19 + i] = 16 + i;
  for (int i = 0; i < 26; ++i) {
    EXPECT_EQ(tailed.x()[i], plain.x()[order[i]]);
    for (int j = 0; j < 26; ++j) EXPECT_EQ(tailed.P()(i, j), plain.P()(order[i], order[j])) << i << "," << j;
  }
  // A map block removed before the tail leaves the tail whole; a tail block removed shrinks it.
  tailed.remove(13, 3);
  EXPECT_EQ(tailed.tailSize(), 7);
  EXPECT_EQ(tailed.x().tail(7), Eigen::VectorXd::Constant(7, 5));
  tailed.remove(16, 7);
  EXPECT_EQ(tailed.tailSize(), 0);
  EXPECT_EQ(tailed.x().tail<3>(), Vec3(2, 2, 2));
}

}  // namespace
}  // namespace slamcmp
