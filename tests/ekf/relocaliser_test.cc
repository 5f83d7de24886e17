#include "ekf/relocaliser.h"

#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace slamcmp {
namespace {

// A wall like the presets' (shapes of random grey on grey, plane z = kPlaneZ, 2.4 m square), seen
// through a pinhole camera: the image is the wall's texture under the plane's homography.
constexpr double kPlaneZ = 1.5;
constexpr double kTexturePxPerM = 500;
constexpr int kTextureSide = 1200;

cv::Mat wallTexture(unsigned seed = 3) {
  cv::Mat texture(kTextureSide, kTextureSide, CV_8U, cv::Scalar(128));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> at(0, kTextureSide - 1), size(3, 25), grey(0, 255), round(0, 1);
  for (int i = 0; i < 6000; ++i) {
    const cv::Point c(at(rng), at(rng));
    const int s = size(rng);
    const cv::Scalar g(grey(rng));
    if (round(rng))
      cv::circle(texture, c, s / 2, g, -1, cv::LINE_AA);
    else
      cv::rectangle(texture, cv::Rect(c.x, c.y, s, s), g, -1, cv::LINE_AA);
  }
  return texture;
}

CameraModel pinhole() {
  return CameraModel::fromOpenCV((cv::Mat_<double>(3, 3) << 520, 0, 319.5, 0, 520, 239.5, 0, 0, 1),
                                 cv::Mat::zeros(1, 5, CV_64F), cv::Size(640, 480));
}

cv::Mat renderWall(const cv::Mat& texture, const CameraModel& camera, const SE3& T_world_camera) {
  // Texture pixel (u, v) is the wall point ((u - side/2) / px_per_m, (v - side/2) / px_per_m, z).
  const SE3 T_camera_world = T_world_camera.inverse();
  const Mat3& R = T_camera_world.R();
  Mat3 A;
  A.col(0) = R.col(0) / kTexturePxPerM;
  A.col(1) = R.col(1) / kTexturePxPerM;
  A.col(2) = R.col(2) * kPlaneZ + T_camera_world.t() - (R.col(0) + R.col(1)) * (kTextureSide / 2.0) / kTexturePxPerM;
  Mat3 K;
  K << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1;
  const Mat3 H = K * A;
  cv::Mat H_cv(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) H_cv.at<double>(i, j) = H(i, j);
  cv::Mat image;
  cv::warpPerspective(texture, image, H_cv, cv::Size(camera.width, camera.height), cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(0));
  return image;
}

// A map as a filter would hold it: corners of the first view on the wall, each with the
// descriptor of that view.
struct WallMap {
  std::vector<Vec3> p_world;
  std::vector<Mat3> p_world_covariance;  // exact unless a test says otherwise
  cv::Mat descriptors;
};

WallMap mapFromFirstView(const Relocaliser& relocaliser, const CameraModel& camera, const cv::Mat& grey) {
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(grey, corners, 150, 0.01, 12);
  WallMap map;
  for (const cv::Point2f& c : corners) {
    const cv::Mat d = relocaliser.describe(grey, Vec2(c.x, c.y));
    if (d.empty()) continue;
    const Vec2 xy = camera.undistortPixel(Vec2(c.x, c.y));
    map.p_world.push_back(Vec3(xy.x(), xy.y(), 1.0) * kPlaneZ);  // the first camera is the world
    map.p_world_covariance.push_back(Mat3::Zero());
    map.descriptors.push_back(d);
  }
  return map;
}

// A corner's descriptor, computed over its neighbourhood, is the one ORB gives over the whole image,
// near the border too; within ORB's border neither gives one.
TEST(Relocaliser, DescribesACornerAsOverTheWholeImage) {
  const CameraModel camera = pinhole();
  const cv::Mat grey = renderWall(wallTexture(), camera, SE3::fromRotvec(Vec3(0.05, -0.1, 0.3), Vec3(0.02, 0, 0)));
  const Relocaliser relocaliser{RelocalisationOptions{}};
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(grey, corners, 100, 0.01, 12);
  std::vector<Vec2> uvs;
  for (const cv::Point2f& c : corners) uvs.emplace_back(c.x, c.y);
  for (double x : {31.6, 32.0, 32.5, 40.3, 606.0, 606.6, 607.2})
    for (double y : {31.6, 32.0, 47.2, 240.5, 446.0, 446.6, 447.4}) uvs.emplace_back(x, y);
  // Between floats and at halves: the keypoint is the float nearest (as a cv::KeyPoint holds it).
  for (const Vec2& uv : {Vec2(301.49999, 240.2), Vec2(301.4999999, 121.5), Vec2(607.99998, 200.3),
                         Vec2(32.4999999, 100.5), Vec2(31.9999999, 447.5000001)})
    uvs.push_back(uv);
  int described = 0;
  for (const Vec2& uv : uvs) {
    std::vector<cv::Point2f> one = {cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()))};
    const cv::Mat whole = relocaliser.describeAll(grey, &one);
    const cv::Mat around = relocaliser.describe(grey, uv);
    ASSERT_EQ(around.empty(), one.empty()) << uv.transpose();
    if (around.empty()) continue;
    EXPECT_EQ(cv::norm(around, whole, cv::NORM_HAMMING), 0) << uv.transpose();
    ++described;
  }
  EXPECT_GE(described, 80);
  EXPECT_TRUE(relocaliser.describe(grey, Vec2(-100, 50)).empty());
  EXPECT_TRUE(relocaliser.describe(grey, Vec2(NAN, 50)).empty());
  EXPECT_TRUE(relocaliser.describe(grey, Vec2(1e300, 50)).empty());  // no integer overflow on the way
}

// A camera that moved 8 cm and turned (a 25-degree roll among it) since the map was made is found
// again from the map alone, to the millimetres its pixel-grid corners allow.
TEST(Relocaliser, FindsTheCameraAgainFromTheMap) {
  const CameraModel camera = pinhole();
  const cv::Mat texture = wallTexture();
  const Relocaliser relocaliser{RelocalisationOptions{}};
  const WallMap map = mapFromFirstView(relocaliser, camera, renderWall(texture, camera, SE3()));
  ASSERT_GE(map.p_world.size(), 100u) << "corners away from the border get a descriptor";

  for (const SE3& T_world_camera : {SE3::fromRotvec(Vec3(0, 0, 0.1), Vec3(0.02, 0, 0)),
                                    SE3::fromRotvec(Vec3(0.05, -0.08, 0.44), Vec3(0.05, -0.04, 0.05))}) {
    int inliers = 0;
    const std::optional<SE3> found = relocaliser.relocalise(renderWall(texture, camera, T_world_camera), camera,
                                                            map.p_world, map.p_world_covariance, map.descriptors, &inliers);
    ASSERT_TRUE(found);
    EXPECT_GE(inliers, 50);
    EXPECT_LT((found->t() - T_world_camera.t()).norm(), 0.006);
    EXPECT_LT(rotvecFromRotation(found->R().transpose() * T_world_camera.R()).norm(), 0.3 * M_PI / 180);
  }
}

// Where the map is not in view (another wall of the same kind; a blank frame) there is no pose.
TEST(Relocaliser, NoPoseWhereTheMapIsNotInView) {
  const CameraModel camera = pinhole();
  const cv::Mat texture = wallTexture();
  const Relocaliser relocaliser{RelocalisationOptions{}};
  const WallMap map = mapFromFirstView(relocaliser, camera, renderWall(texture, camera, SE3()));
  int inliers = -1;
  EXPECT_FALSE(relocaliser.relocalise(renderWall(wallTexture(4), camera, SE3()), camera, map.p_world,
                                      map.p_world_covariance, map.descriptors, &inliers));
  EXPECT_EQ(inliers, 0);
  EXPECT_FALSE(relocaliser.relocalise(cv::Mat(480, 640, CV_8U, cv::Scalar(128)), camera, map.p_world,
                                      map.p_world_covariance, map.descriptors, &inliers));
}

// Points mirrored through the camera centre (p -> -p) project to the same pixels from behind it.
// Spread in depth along their rays (any depth fits the view they were seen in), no pose with them
// in front fits them: the best, upside down, fits the 6 of 119 near the image's middle row, too
// few of the matches (min_inlier_ratio). (A pose that puts its points behind the camera, which
// OpenCV's refinement can reach, is refused too: tum_fr1_rpy, RealTumFr1RpyBoardFree.)
TEST(Relocaliser, RefusesMirroredPoints) {
  const CameraModel camera = pinhole();
  const Relocaliser relocaliser{RelocalisationOptions{}};
  const cv::Mat view = renderWall(wallTexture(), camera, SE3());
  WallMap map = mapFromFirstView(relocaliser, camera, view);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> depth(0.5, 2.0);
  for (Vec3& p : map.p_world) p *= depth(rng);
  int inliers = 0;
  const std::optional<SE3> found = relocaliser.relocalise(view, camera, map.p_world, map.p_world_covariance, map.descriptors, &inliers);
  ASSERT_TRUE(found);
  EXPECT_LT(found->t().norm(), 1e-3);
  for (Vec3& p : map.p_world) p = -p;
  EXPECT_FALSE(relocaliser.relocalise(view, camera, map.p_world, map.p_world_covariance, map.descriptors, &inliers));
  EXPECT_EQ(inliers, 0);
}

// A map whose depths are uncertain (a filter's inverse-depth features, here 0.5 m along each ray at
// 1.5 m) confirms a pose only where that uncertainty projects within the inlier test (3 px). From a
// camera 2 cm beside the first, turned 6 degrees, it projects within 2.4 px: found. From one 8 cm
// away it projects 3.6-9.6 px: PnP would take the points as exact and fit them anywhere along those
// pixels, so no pose, whatever the other points do, as long as fewer than min_inliers are known
// better; with 20 of them known to 1 cm the pose is found, those 20 the most its count can hold.
TEST(Relocaliser, CountsOnlyInliersWhosePointsAreKnownToWithinTheInlierTest) {
  const CameraModel camera = pinhole();
  const cv::Mat texture = wallTexture();
  const Relocaliser relocaliser{RelocalisationOptions{}};
  WallMap map = mapFromFirstView(relocaliser, camera, renderWall(texture, camera, SE3()));
  const auto alongRays = [&](double sigma, size_t known) {  // the first `known` points to 1 cm
    for (size_t k = 0; k < map.p_world.size(); ++k) {
      const Vec3 ray = map.p_world[k].normalized();  // from the first camera, at the origin
      const double s = k < known ? 0.01 : sigma;
      map.p_world_covariance[k] = s * s * ray * ray.transpose();
    }
  };
  const SE3 beside = SE3::fromRotvec(Vec3(0.06, -0.08, 0.1), Vec3(0.02, 0, 0));
  const SE3 away = SE3::fromRotvec(Vec3(0.05, -0.08, 0.44), Vec3(0.05, -0.04, 0.05));
  const cv::Mat view_away = renderWall(texture, camera, away);
  int inliers = 0;
  alongRays(0.5, 0);
  EXPECT_TRUE(relocaliser.relocalise(renderWall(texture, camera, beside), camera, map.p_world,
                                     map.p_world_covariance, map.descriptors, &inliers));
  EXPECT_FALSE(relocaliser.relocalise(view_away, camera, map.p_world, map.p_world_covariance, map.descriptors,
                                      &inliers));
  EXPECT_EQ(inliers, 0);
  const int min_inliers = RelocalisationOptions{}.min_inliers;
  alongRays(0.5, static_cast<size_t>(min_inliers - 1));
  EXPECT_FALSE(relocaliser.relocalise(view_away, camera, map.p_world, map.p_world_covariance, map.descriptors,
                                      &inliers));
  alongRays(0.5, 20);
  const std::optional<SE3> found =
      relocaliser.relocalise(view_away, camera, map.p_world, map.p_world_covariance, map.descriptors, &inliers);
  ASSERT_TRUE(found);
  EXPECT_GE(inliers, min_inliers);
  EXPECT_LE(inliers, 20) << "only the points known to within the test count";
  EXPECT_LT((found->t() - away.t()).norm(), 0.006);
}

// A wall of repeated tiles (one every 0.24 m, about 80 px in the image): every corner has a
// look-alike a tile away, and Lowe's ratio test among all the frame's corners refuses the matches.
// Guided by a pose 1 cm and 1 degree off the camera's (a lost filter's own), each point is matched
// among the corners within 40 px of where that pose projects it, out of its look-alikes' reach,
// and the camera is found; with no guess it is not.
TEST(Relocaliser, AGuessFindsTheCameraWhereLookAlikesDefeatTheRatioTest) {
  const CameraModel camera = pinhole();
  constexpr int kTile = 120;  // texture pixels: 0.24 m
  const cv::Mat tile = wallTexture()(cv::Rect(0, 0, kTile, kTile)).clone();
  cv::Mat texture;
  cv::repeat(tile, kTextureSide / kTile, kTextureSide / kTile, texture);
  const Relocaliser relocaliser{RelocalisationOptions{}};
  const WallMap map = mapFromFirstView(relocaliser, camera, renderWall(texture, camera, SE3()));
  const SE3 T_world_camera = SE3::fromRotvec(Vec3(0.03, -0.02, 0.05), Vec3(0.03, 0.01, 0));
  const cv::Mat view = renderWall(texture, camera, T_world_camera);
  int inliers = 0;
  EXPECT_FALSE(relocaliser.relocalise(view, camera, map.p_world, map.p_world_covariance, map.descriptors, &inliers));
  const SE3 guess = T_world_camera * SE3::fromRotvec(Vec3(0, M_PI / 180, 0), Vec3(0.01, 0, 0));
  const std::optional<SE3> found =
      relocaliser.relocalise(view, camera, map.p_world, map.p_world_covariance, map.descriptors, &inliers, &guess);
  ASSERT_TRUE(found);
  EXPECT_GE(inliers, 20);
  EXPECT_LT((found->t() - T_world_camera.t()).norm(), 0.006);
  EXPECT_LT(rotvecFromRotation(found->R().transpose() * T_world_camera.R()).norm(), 0.3 * M_PI / 180);
}

}  // namespace
}  // namespace slamcmp
