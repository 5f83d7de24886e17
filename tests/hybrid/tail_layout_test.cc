// hybrid's record of the EKF state's tail (clones and points interleaved): offsets stay right while
// the map's features come and go before the tail and blocks leave it in any order.
#include "hybrid/tail_layout.h"

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

using Kind = TailLayout::Kind;

// A block of `dim` values all equal to `value`, uncorrelated with the rest.
int appendTail(EkfState& state, TailLayout& tail, Kind kind, int id, int dim, double value) {
  const int offset = state.appendToTail(Eigen::VectorXd::Constant(dim, value), Eigen::MatrixXd::Identity(dim, dim),
                                        Eigen::MatrixXd::Zero(dim, state.size()));
  tail.push(kind, id, dim);
  return offset;
}

TEST(TailLayout, OffsetsFollowTheMapAndTheTailsRemovals) {
  EkfState state;
  state.reset(SE3(), Eigen::Matrix<double, 13, 13>::Identity());
  TailLayout tail;
  EXPECT_TRUE(tail.matches(state));
  EXPECT_EQ(appendTail(state, tail, Kind::kClone, 0, 7, 1), 13);
  EXPECT_EQ(appendTail(state, tail, Kind::kPoint, 0, 6, 2), 20);  // a point with the clone's id
  EXPECT_EQ(appendTail(state, tail, Kind::kClone, 1, 7, 3), 26);
  EXPECT_TRUE(tail.matches(state));
  EXPECT_EQ(tail.offset(state, Kind::kPoint, 0), 20);
  EXPECT_EQ(tail.offset(state, Kind::kPoint, 1), -1);

  // A map feature before the tail moves every tail block by its size.
  state.append(Vec3(9, 9, 9), Mat3::Identity(), Eigen::MatrixXd::Zero(3, state.size()));
  EXPECT_EQ(tail.offset(state, Kind::kClone, 0), 16);
  EXPECT_EQ(tail.offset(state, Kind::kPoint, 0), 23);
  EXPECT_EQ(tail.offset(state, Kind::kClone, 1), 29);

  // The first clone leaves: the blocks after it move up, with their values.
  tail.remove(state, Kind::kClone, 0);
  EXPECT_EQ(state.tailSize(), 13);
  EXPECT_EQ(tail.offset(state, Kind::kPoint, 0), 16);
  EXPECT_EQ(state.x().segment(16, 6), Eigen::VectorXd::Constant(6, 2));
  EXPECT_EQ(tail.offset(state, Kind::kClone, 1), 22);
  EXPECT_EQ(state.x().segment(22, 7), Eigen::VectorXd::Constant(7, 3));
  tail.remove(state, Kind::kClone, 0);  // no longer there: nothing happens
  EXPECT_EQ(state.size(), 29);

  // The filter restarted: the state's tail is not the one recorded.
  EkfState restarted;
  restarted.reset(SE3(), Eigen::Matrix<double, 13, 13>::Identity());
  EXPECT_FALSE(tail.matches(restarted));
  tail.clear(state);
  EXPECT_EQ(state.size(), 16);
  EXPECT_EQ(state.tailSize(), 0);
  EXPECT_TRUE(tail.matches(state));
}

}  // namespace
}  // namespace slamcmp
