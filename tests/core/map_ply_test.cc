// map.ply: what writeMapPly writes is read back exactly; point clouds as Open3D and CloudCompare
// write them (ascii and binary, extra properties, other elements) are read; malformed files are
// InputErrors naming the file and line.
#include "core/map_ply.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::readLines;

std::vector<MapPoint> threePoints() {
  std::vector<MapPoint> points(3);
  for (int i = 0; i < 3; ++i) {
    points[i].id = 10 + i;
    points[i].p_world = Vec3(0.5 * i, -1.25, 2.0 + i);
    points[i].observations = 4 * i;
    points[i].sigma = i == 0 ? -1.0 : 0.01 * i;
  }
  return points;
}

// The message of the InputError `f` throws ("" if none).
template <class F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MapPly, HeaderAndVertices) {
  test::TempDir dir;
  const std::string path = dir.file("map.ply");
  writeMapPly(path, threePoints());
  const auto lines = readLines(path);
  ASSERT_GE(lines.size(), 4u);
  EXPECT_EQ(lines[0], "ply");
  EXPECT_EQ(lines[1], "format ascii 1.0");
  const auto end = std::find(lines.begin(), lines.end(), "end_header");
  ASSERT_NE(end, lines.end());
  EXPECT_NE(std::find(lines.begin(), end, "element vertex 3"), end);
  for (const char* p : {"property float x", "property float y", "property float z"})
    EXPECT_NE(std::find(lines.begin(), end, p), end) << p;
  ASSERT_EQ(lines.end() - end - 1, 3);
  std::istringstream row(*(end + 3));
  double x, y, z, sigma;
  int id, observations;
  row >> x >> y >> z >> id >> observations >> sigma;
  EXPECT_EQ(x, 1.0);
  EXPECT_EQ(y, -1.25);
  EXPECT_EQ(z, 4.0);
  EXPECT_EQ(id, 12);
  EXPECT_EQ(observations, 8);
  EXPECT_NEAR(sigma, 0.02, 1e-6);
}

TEST(MapPly, ReadsBackWhatItWrites) {
  test::TempDir dir;
  std::vector<MapPoint> points = threePoints();
  points[1].p_world = Vec3(0.1234567, -2.5e-3, 3.75);  // 6 decimals are written: 0.5 um rounding
  writeMapPly(dir.file("map.ply"), points);
  const auto read = readMapPly(dir.file("map.ply"));
  ASSERT_EQ(read.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_LT((read[i].p_world - points[i].p_world).cwiseAbs().maxCoeff(), 5.1e-7) << i;
    EXPECT_EQ(read[i].id, points[i].id);
    EXPECT_EQ(read[i].observations, points[i].observations);
    EXPECT_NEAR(read[i].sigma, points[i].sigma, 5.1e-7);
  }
  writeMapPly(dir.file("empty.ply"), {});
  EXPECT_TRUE(readMapPly(dir.file("empty.ply")).empty());
}

// A diverged point far away prints hundreds of digits: its line is written whole, not cut.
TEST(MapPly, FarPointIsWrittenWhole) {
  test::TempDir dir;
  std::vector<MapPoint> points = threePoints();
  points[0].p_world = Vec3(1e300, -1e300, 2.0);
  writeMapPly(dir.file("map.ply"), points);
  const auto read = readMapPly(dir.file("map.ply"));
  ASSERT_EQ(read.size(), points.size());
  EXPECT_EQ(read[0].p_world.x(), 1e300);
  EXPECT_EQ(read[0].p_world.y(), -1e300);
  EXPECT_EQ(read[0].id, points[0].id);
  EXPECT_EQ(read[1].id, points[1].id);
}

TEST(MapPly, UnwritableOutputIsAnInputError) {
  test::TempDir dir;
  EXPECT_THROW(writeMapPly(dir.file("missing/map.ply"), {}), InputError);
}

// Open3D's ascii point cloud (double coordinates, normals, colours), here with Windows line ends.
TEST(MapPly, ReadsOpen3dAsciiWithCrLf) {
  test::TempDir dir;
  test::writeText(dir.file("o3d.ply"),
                  "ply\r\nformat ascii 1.0\r\ncomment Created by Open3D\r\nelement vertex 2\r\n"
                  "property double x\r\nproperty double y\r\nproperty double z\r\nproperty double nx\r\n"
                  "property double ny\r\nproperty double nz\r\nproperty uchar red\r\nproperty uchar green\r\n"
                  "property uchar blue\r\nend_header\r\n"
                  "0.25 -0.5 1e-3 0 0 1 255 0 0\r\n-1 2 3.5 0 1 0 0 255 0\r\n");
  const auto points = readMapPly(dir.file("o3d.ply"));
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].p_world, Vec3(0.25, -0.5, 1e-3));
  EXPECT_EQ(points[1].p_world, Vec3(-1, 2, 3.5));
  EXPECT_EQ(points[1].id, 1);  // no id property: the vertex index
  EXPECT_EQ(points[1].observations, 0);
  EXPECT_EQ(points[1].sigma, -1.0);
}

// An element before the vertices and a face list after them, in ascii.
TEST(MapPly, SkipsOtherElementsInAscii) {
  test::TempDir dir;
  test::writeText(dir.file("mesh.ply"),
                  "ply\nformat ascii 1.0\nelement camera 1\nproperty float view_px\nproperty list uchar int ids\n"
                  "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                  "1.5 2 7 8\n0 0 0\n\n1 0 0\n0 1 0\n3 0 1 2\n");
  const auto points = readMapPly(dir.file("mesh.ply"));
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[2].p_world, Vec3(0, 1, 0));
}

template <class T>
void put(std::string* bytes, T v, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  bytes->append(b, sizeof(T));
}

// CloudCompare's binary point cloud: obj_info line, float coordinates, colours and a scalar
// field, then a face element with a list.
TEST(MapPly, ReadsCloudCompareBinaryLittleEndian) {
  test::TempDir dir;
  std::string ply =
      "ply\nformat binary_little_endian 1.0\ncomment Author: CloudCompare (TELECOM PARISTECH/EDF R&D)\n"
      "obj_info Generated by CloudCompare!\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property float scalar_Scalar_field\nproperty int id\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const float xyz[2][3] = {{0.5f, -0.25f, 2.0f}, {1.0f, 0.125f, -3.0f}};
  for (int i = 0; i < 2; ++i) {
    for (float c : xyz[i]) put(&ply, c, false);
    for (int c = 0; c < 3; ++c) put(&ply, static_cast<uint8_t>(200), false);
    put(&ply, 0.75f, false);
    put(&ply, static_cast<int32_t>(40 + i), false);
  }
  put(&ply, static_cast<uint8_t>(3), false);
  for (int32_t k : {0, 1, 0}) put(&ply, k, false);
  test::writeText(dir.file("cc.ply"), ply);
  const auto points = readMapPly(dir.file("cc.ply"));
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].p_world, Vec3(0.5, -0.25, 2.0));
  EXPECT_EQ(points[1].p_world, Vec3(1.0, 0.125, -3.0));
  EXPECT_EQ(points[1].id, 41);

  // Cut inside the second vertex: an error naming it.
  test::writeText(dir.file("cut.ply"), ply.substr(0, ply.find("end_header\n") + 11 + 30));
  const std::string e = errorOf([&] { readMapPly(dir.file("cut.ply")); });
  EXPECT_NE(e.find(dir.file("cut.ply") + ": the file ends before vertex 1 of 2"), std::string::npos) << e;
}

TEST(MapPly, ReadsBinaryBigEndianDoubles) {
  test::TempDir dir;
  std::string ply =
      "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
      "property double z\nproperty short observations\nend_header\n";
  for (double c : {0.1, -0.2, 0.3}) put(&ply, c, true);
  put(&ply, static_cast<int16_t>(-7), true);
  test::writeText(dir.file("be.ply"), ply);
  const auto points = readMapPly(dir.file("be.ply"));
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].p_world, Vec3(0.1, -0.2, 0.3));
  EXPECT_EQ(points[0].observations, -7);
}

struct BadPly {
  const char* name;
  std::string text;
  std::string where;  // after the file name
  std::string what;
};

class MapPlyBad : public ::testing::TestWithParam<BadPly> {};

TEST_P(MapPlyBad, IsAnInputErrorNamingFileAndLine) {
  test::TempDir dir;
  const std::string path = dir.file("map.ply");
  test::writeText(path, GetParam().text);
  const std::string e = errorOf([&] { readMapPly(path); });
  EXPECT_NE(e.find(path + GetParam().where), std::string::npos) << e;
  EXPECT_NE(e.find(GetParam().what), std::string::npos) << e;
}

const std::string kHead = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n";

INSTANTIATE_TEST_SUITE_P(
    Corpus, MapPlyBad,
    ::testing::Values(
        BadPly{"Empty", "", ": ", "no end_header"},
        BadPly{"NotPly", "x y z\n1 2 3\n", ":1: ", "not a PLY file"},
        BadPly{"NoEndHeader", "ply\nformat ascii 1.0\nelement vertex 0\n", ": ", "no end_header"},
        BadPly{"NoFormat", "ply\nelement vertex 0\nproperty float x\nend_header\n", ": ", "no format line"},
        BadPly{"UnknownFormat", "ply\nformat utf8 1.0\nend_header\n", ":2: ", "unknown format 'utf8'"},
        BadPly{"BadVersion", "ply\nformat ascii 2.0\nend_header\n", ":2: ", "version"},
        BadPly{"BadCount", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", ":3: ", "not a count"},
        BadPly{"PropertyFirst", "ply\nformat ascii 1.0\nproperty float x\nend_header\n", ":3: ",
               "before any element"},
        BadPly{"UnknownType", "ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\nend_header\n", ":4: ",
               "unknown type 'real'"},
        BadPly{"UnknownKeyword", "ply\nformat ascii 1.0\nvertices 3\nend_header\n", ":3: ", "unknown header"},
        BadPly{"ElementWithoutProperties",  // used to spin over 2^64 empty instances
               "ply\nformat binary_little_endian 1.0\nelement face 18446744073709551615\nelement vertex 1\n"
               "property float x\nproperty float y\nproperty float z\nend_header\n",
               ": ", "no properties"},
        BadPly{"NoVertex", "ply\nformat ascii 1.0\nelement face 0\nend_header\n", ": ", "no 'element vertex'"},
        BadPly{"NoZ",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
               ": ", "no x, y and z"},
        BadPly{"TooFewValues", kHead + "1 2 3\n1 2\n", ":9: ", "too few values"},
        BadPly{"TooManyValues", kHead + "1 2 3 4\n", ":8: ", "expected 3 values"},
        BadPly{"NotANumber", kHead + "1 2 3\n1 two 3\n", ":9: ", "'two' is not a number"},
        BadPly{"NaN", kHead + "1 2 nan\n", ":8: ", "not finite"},
        BadPly{"Infinite", kHead + "1 2 3\n1e999 2 3\n", ":9: ", "not finite"},
        BadPly{"TooFewVertices", kHead + "1 2 3\n", ": ", "ends before vertex 1 of 2"},
        BadPly{"HugeCount", "ply\nformat binary_little_endian 1.0\nelement vertex 99999999999999\n"
                            "property float x\nproperty float y\nproperty float z\nend_header\n",
               ": ", "ends before vertex 0"},
        // Found by the reliability probe: both read garbage or ignored data, silently.
        BadPly{"MoreVerticesThanDeclared", kHead + "1 2 3\n4 5 6\n7 8 9\n", ":10: ", "data beyond the 2 vertices"},
        BadPly{"BinaryHeaderOverText",
               "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n1.5 2 3\n4 5 6.25\n",
               ": ", "the header says binary_little_endian but the data is text"},
        BadPly{"BinaryMoreThanDeclared",
               "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty uchar x\nproperty uchar y\n"
               "property uchar z\nend_header\n\x01\x02\x03\x04\x05\x06",
               ": ", "data beyond the 1 vertices"},
        BadPly{"IdOutOfRange",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
               "property double id\nend_header\n0 0 0 1e12\n",
               ":9: ", "id is not an integer"}),
    [](const ::testing::TestParamInfo<BadPly>& info) { return info.param.name; });

}  // namespace
}  // namespace slamcmp
