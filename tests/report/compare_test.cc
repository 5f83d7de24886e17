#include "eval/compare.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/thesis_tables.h"
#include "eval/tracker_factory.h"

namespace slamcmp {
namespace {

TEST(Compare, ParsesMethodsWithModes) {
  const std::string first = trackerNames().at(0);
  const auto methods = parseMethods(first + "," + first + ":calibration");
  ASSERT_EQ(methods.size(), 2u);
  EXPECT_EQ(methods[0].label(), first);
  EXPECT_EQ(methods[1].mode, "calibration");
  EXPECT_EQ(methods[1].slug(), first + "-calibration");
}

TEST(Compare, RefusesUnknownAndEmptyMethodLists) {
  EXPECT_THROW(parseMethods("nosuchslam"), InputError);
  EXPECT_THROW(parseMethods(","), InputError);
}

TEST(Compare, ThesisTablesHoldTheFourVideos) {
  int frames = 0;
  for (const char* v : {"tv1", "tv2", "tv3", "tv4"}) frames += thesisVideo(v).value().frames;
  EXPECT_EQ(frames, 337 + 335 + 318 + 402);
  EXPECT_DOUBLE_EQ(thesisVideo("tv4")->ms_monoslam, 653.23);
  EXPECT_FALSE(thesisVideo("tv5"));
}

}  // namespace
}  // namespace slamcmp
