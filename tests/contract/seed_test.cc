// `run --seed N` (compare's trials on real sequences): every registered back-end has a random seed
// (an option called "seed"), and --seed sets each of them, as summary.json's options record.
#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "eval/app/backends.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

// Every value of a key called "seed" in the options' JSON.
void collectSeeds(const nlohmann::json& j, std::vector<int>* seeds) {
  if (!j.is_object()) return;
  for (const auto& [key, value] : j.items()) {
    if (key == "seed" && value.is_number_integer()) seeds->push_back(value.get<int>());
    collectSeeds(value, seeds);
  }
}

TEST(Seed, EveryBackendHasOneAndSetSeedsSetsThemAll) {
  for (const BackendRegistration& b : backends()) {
    const auto options = b.default_options();
    const int set = options->setSeeds(7);
    EXPECT_GE(set, 1) << b.name << " has no random seed: compare's trials on real data would all be alike";
    std::vector<int> seeds;
    collectSeeds(options->toJson(), &seeds);
    EXPECT_EQ(static_cast<int>(seeds.size()), set) << b.name;
    for (int s : seeds) EXPECT_EQ(s, 7) << b.name;
    // A seed does not hide a bad --set.
    EXPECT_THROW(loadBackendOptions(b, "", {b.name + ".no_such_option=1"}, 3), InputError);
  }
}

TEST(Seed, RunRecordsTheSeedInSummary) {
  test::TempDir tmp;
  ASSERT_EQ(test::runSlamcmp("synth --preset tv1 --frames 8 --supersample 1 --out " + tmp.file("tv1")).exit_code, 0);
  const auto r = test::runSlamcmp("run --backend monoslam --seed 3 --sequence " + tmp.file("tv1") + " --out " +
                                  tmp.file("run"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(tmp.file("run/summary.json"));
  const nlohmann::json summary = nlohmann::json::parse(in);
  std::vector<int> seeds;
  collectSeeds(summary["options"], &seeds);
  ASSERT_FALSE(seeds.empty()) << summary["options"].dump();
  for (int s : seeds) EXPECT_EQ(s, 3);
  const auto bad = test::runSlamcmp("run --backend monoslam --seed -1 --sequence " + tmp.file("tv1"));
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
}

}  // namespace
}  // namespace slamcmp
