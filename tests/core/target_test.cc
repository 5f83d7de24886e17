// target.yaml: boards whose orientation is ambiguous (both counts even or both odd) and impossible
// square sizes are refused naming the file; valid ones are read exactly.
#include "core/target.h"

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

std::string targetYaml(const std::string& cols, const std::string& rows, const std::string& square,
                       const std::string& type = "chessboard") {
  return "%YAML:1.0\n---\ntype: " + type + "\ninner_corners_cols: " + cols +
         "\ninner_corners_rows: " + rows + "\nsquare_size: " + square + "\n";
}

TEST(Target, ReadsVamrTarget) {
  SLAMCMP_REQUIRE_SHARED(data);
  const ChessboardTarget t = readTargetYaml(data + "/vamr_checkerboard/target.yaml");
  EXPECT_EQ(t.cols, 9);
  EXPECT_EQ(t.rows, 6);
  EXPECT_DOUBLE_EQ(t.square_size, 0.04);
  EXPECT_EQ(t.numCorners(), 54);
}

TEST(Target, ReadWriteRoundTripAndCornerLayout) {
  test::TempDir dir;
  const std::string path = dir.file("target.yaml");
  test::writeText(path, targetYaml("7", "4", "0.025"));
  const ChessboardTarget t = readTargetYaml(path);
  EXPECT_EQ(t.cols, 7);
  EXPECT_EQ(t.rows, 4);
  EXPECT_EQ(t.square_size, 0.025);
  // Inner corner (i, j) at (i s, j s, 0), index j * cols + i.
  const auto corners = t.cornersWorld();
  ASSERT_EQ(corners.size(), 28u);
  EXPECT_EQ(corners[1], Vec3(0.025, 0, 0));
  EXPECT_EQ(corners[7], Vec3(0, 0.025, 0));
  EXPECT_EQ(corners[27], Vec3(6 * 0.025, 3 * 0.025, 0));
  const auto outer = t.outerCornersWorld();
  ASSERT_EQ(outer.size(), 4u);
  EXPECT_EQ(outer[2], corners[27]);
  EXPECT_EQ(outer[3], corners[21]);

  const std::string copy = dir.file("copy.yaml");
  writeTargetYaml(copy, t);
  const ChessboardTarget back = readTargetYaml(copy);
  EXPECT_EQ(back.cols, t.cols);
  EXPECT_EQ(back.rows, t.rows);
  EXPECT_EQ(back.square_size, t.square_size);
}

struct BadTarget {
  std::string name;
  std::string content;
  std::string says;  // a word the message must hold besides the file name
};

// gtest prints the parameter by its name.
void PrintTo(const BadTarget& c, std::ostream* os) { *os << c.name; }

class BadTargetYaml : public ::testing::TestWithParam<BadTarget> {};

TEST_P(BadTargetYaml, RefusedNamingTheFile) {
  test::TempDir dir;
  const std::string path = dir.file("target.yaml");
  test::writeText(path, GetParam().content);
  try {
    readTargetYaml(path);
    FAIL() << "accepted " << GetParam().name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(GetParam().says), std::string::npos) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadTargetYaml,
    ::testing::Values(
        BadTarget{"even_even", targetYaml("8", "6", "0.03"), "even"},
        BadTarget{"odd_odd", targetYaml("9", "7", "0.03"), "odd"},
        BadTarget{"zero_square", targetYaml("9", "6", "0"), "square_size"},
        BadTarget{"negative_square", targetYaml("9", "6", "-0.04"), "square_size"},
        BadTarget{"too_few_corners", targetYaml("1", "6", "0.04"), "3x3"},
        BadTarget{"not_a_chessboard", targetYaml("9", "6", "0.04", "aprilgrid"), "type"},
        BadTarget{"missing_rows", "%YAML:1.0\n---\ninner_corners_cols: 9\nsquare_size: 0.04\n",
                  "inner_corners_rows"}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace slamcmp

namespace slamcmp {
namespace {

// A symmetric board is refused unless the caller allows it: calibration (its corner order only needs
// the right handedness) and `run` (which warns and keeps the origin by continuity).
TEST(Target, SymmetricBoardOnlyForCalibration) {
  test::TempDir tmp;
  test::writeText(tmp.file("t.yaml"), "%YAML:1.0\n---\ntype: chessboard\ninner_corners_cols: 8\n"
                                      "inner_corners_rows: 6\nsquare_size: 0.03\n");
  EXPECT_THROW(readTargetYaml(tmp.file("t.yaml")), InputError);
  const ChessboardTarget t = readTargetYaml(tmp.file("t.yaml"), /*allow_symmetric=*/true);
  EXPECT_TRUE(t.symmetric());
  EXPECT_EQ(t.numCorners(), 48);
}

}  // namespace
}  // namespace slamcmp
