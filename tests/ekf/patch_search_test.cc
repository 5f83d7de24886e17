#include "ekf/patch_search.h"

#include <gtest/gtest.h>

#include "ekf/patch_warp.h"
#include "tests/ekf/plane_render.h"

namespace slamcmp {
namespace {

cv::Mat texturedImage() {
  const CameraModel camera = test::testCamera();
  return test::renderPlane(camera, SE3::fromRotvec(Vec3::Zero(), Vec3(0, 0, -1.0)), 0.0);
}

// The 11x11 template centred on uv (sub-pixel), as the EKF cuts one where it first sees a feature.
bool templateAt(const cv::Mat& image, const Vec2& uv, cv::Mat* templ) {
  PatchSource source;
  return makePatchSource(image, uv, 15, SE3(), &source) && sourceTemplate(source, 11, templ);
}

// Parabola interpolation of a correlation peak is biased towards whole pixels ("pixel locking") and
// by the peak's asymmetry: within 0.15 px at a whole pixel, 0.4 px between them (the 1 px
// measurement noise covers it).
TEST(PatchSearch, FindsATemplateToSubPixelAccuracy) {
  const cv::Mat image = texturedImage();
  const SearchEllipse e{Vec2(262, 170), Mat2::Identity() * 100};  // 10 px sigma, 30 px gate
  for (const auto& [truth, tolerance] : {std::pair{Vec2(250, 181), 0.15}, std::pair{Vec2(250.3, 180.6), 0.4}}) {
    cv::Mat templ;
    ASSERT_TRUE(templateAt(image, truth, &templ));
    const std::vector<PatchMatch> matches = searchEllipses(image, templ, {e}, 3.0, 0.8);
    ASSERT_FALSE(matches.empty());
    EXPECT_LT((matches.front().uv - truth).norm(), tolerance) << matches.front().uv.transpose();
    EXPECT_GT(matches.front().ncc, 0.98);
  }
}

TEST(PatchSearch, LooksOnlyInsideTheEllipse) {
  const cv::Mat image = texturedImage();
  cv::Mat templ;
  ASSERT_TRUE(templateAt(image, Vec2(250, 180), &templ));
  // The true position is 40 px away along x; the ellipse is narrow along x.
  Mat2 S;
  S << 25, 0, 0, 2500;
  for (const PatchMatch& m : searchEllipses(image, templ, {{Vec2(290, 180), S}}, 3.0, 0.8))
    EXPECT_GT((m.uv - Vec2(250, 180)).norm(), 5.0);
}

TEST(PatchSearch, FlatImageGivesNoMatch) {
  const cv::Mat flat(480, 640, CV_8U, cv::Scalar(90));
  cv::Mat templ;
  ASSERT_TRUE(templateAt(texturedImage(), Vec2(250, 180), &templ));
  EXPECT_TRUE(searchEllipses(flat, templ, {{Vec2(250, 180), Mat2::Identity() * 100}}, 3.0, 0.8).empty());
}

TEST(PatchSearch, EllipseBoundingBox) {
  const cv::Rect box = ellipsesBoundingBox({{Vec2(100, 50), Mat2::Identity() * 4}, {Vec2(120, 60), Mat2::Identity()}}, 3.0);
  EXPECT_EQ(box, cv::Rect(94, 44, 30, 20));  // x 94..123, y 44..63
}

}  // namespace
}  // namespace slamcmp
