// Options structs: loaded from a YAML section (unknown keys and wrong types refused naming the
// field), checked, written to JSON and described.
#include "core/options.h"

#include <gtest/gtest.h>

#include <string>

#include "tests/test_util.h"

namespace slamcmp {
namespace {

struct SearchOptions {
  double sigma_gate = 3.0;  // standard deviations
  int patch_size = 11;      // pixels, odd
  template <class V>
  void visit(V& v) {
    v("sigma_gate", sigma_gate, "search ellipse, in standard deviations");
    v("patch_size", patch_size, "pixels, odd");
  }
  void check() const {
    if (patch_size % 2 == 0) throw InputError("search.patch_size", "must be odd");
  }
};

struct ExampleOptions {
  int max_features = 100;
  double min_ncc = 0.8;
  bool verbose = false;
  std::string name = "ekf";
  SearchOptions search;
  template <class V>
  void visit(V& v) {
    v("max_features", max_features, "features kept at most");
    v("min_ncc", min_ncc, "accept a match at or above this correlation");
    v("verbose", verbose, "print per-frame diagnostics");
    v("name", name, "label in reports");
    v("search", search, "active search");
  }
  void check() const {
    if (max_features < 1) throw InputError("max_features", "must be at least 1");
    search.check();
  }
};

// Loads the `example` section of a YAML text (written to a file, opened with FileStorage).
ExampleOptions loadFromYaml(const std::string& body) {
  test::TempDir dir;
  const std::string path = dir.file("config.yaml");
  test::writeText(path, "%YAML:1.0\n---\n" + body);
  cv::FileStorage fs(path, cv::FileStorage::READ);
  EXPECT_TRUE(fs.isOpened());
  ExampleOptions options;
  loadOptions(fs["example"], "config.yaml: example", options);
  return options;
}

std::string errorOf(const std::string& body) {
  try {
    loadFromYaml(body);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(Options, LoadSetsPresentFieldsAndKeepsDefaults) {
  const ExampleOptions o = loadFromYaml(
      "example:\n  max_features: 42\n  verbose: true\n  name: cslam\n  search:\n    patch_size: "
      "7\n");
  EXPECT_EQ(o.max_features, 42);
  EXPECT_TRUE(o.verbose);
  EXPECT_EQ(o.name, "cslam");
  EXPECT_EQ(o.search.patch_size, 7);
  EXPECT_EQ(o.min_ncc, 0.8);            // default kept
  EXPECT_EQ(o.search.sigma_gate, 3.0);  // default kept
  // An absent section leaves every default.
  const ExampleOptions d = loadFromYaml("other: 1\n");
  EXPECT_EQ(d.max_features, 100);
  EXPECT_EQ(d.name, "ekf");
  // An integer is a valid double.
  EXPECT_EQ(loadFromYaml("example:\n  min_ncc: 1\n").min_ncc, 1.0);
}

TEST(Options, UnknownKeysAreRefusedNamingTheField) {
  EXPECT_NE(errorOf("example:\n  max_feature: 42\n")
                .find("config.yaml: example.max_feature: unknown option"),
            std::string::npos);
  EXPECT_NE(
      errorOf("example:\n  search:\n    sigma: 2\n").find("config.yaml: example.search.sigma"),
      std::string::npos);
}

TEST(Options, WrongTypesAreRefusedNamingTheField) {
  EXPECT_NE(
      errorOf("example:\n  max_features: many\n").find("example.max_features: must be an integer"),
      std::string::npos);
  EXPECT_NE(errorOf("example:\n  max_features: 4.5\n").find("example.max_features"),
            std::string::npos);
  EXPECT_NE(errorOf("example:\n  min_ncc: high\n").find("example.min_ncc: must be a number"),
            std::string::npos);
  EXPECT_NE(errorOf("example:\n  verbose: maybe\n").find("example.verbose: must be true or false"),
            std::string::npos);
  EXPECT_NE(errorOf("example:\n  name: 3\n").find("example.name: must be a string"),
            std::string::npos);
  EXPECT_NE(errorOf("example:\n  search: 3\n").find("example.search: must be a map"),
            std::string::npos);
  EXPECT_NE(errorOf("example: 5\n").find("config.yaml: example: must be a map"), std::string::npos);
}

TEST(Options, CheckRunsAfterLoading) {
  EXPECT_NE(errorOf("example:\n  max_features: 0\n").find("max_features"), std::string::npos);
  EXPECT_NE(
      errorOf("example:\n  search:\n    patch_size: 10\n").find("search.patch_size: must be odd"),
      std::string::npos);
}

// Block YAML from a JSON object (OpenCV's parser keeps the quotes of JSON's keys).
std::string yamlFromJson(const nlohmann::json& j, const std::string& indent) {
  std::string out;
  for (const auto& [key, value] : j.items()) {
    if (value.is_object())
      out += indent + key + ":\n" + yamlFromJson(value, indent + "  ");
    else
      out += indent + key + ": " + value.dump() + "\n";
  }
  return out;
}

TEST(Options, JsonRoundTripThroughYaml) {
  ExampleOptions o;
  o.max_features = 7;
  o.min_ncc = 0.65;
  o.verbose = true;
  o.name = "run 3";
  o.search.sigma_gate = 2.5;
  const nlohmann::json j = optionsToJson(o);
  EXPECT_EQ(j["max_features"], 7);
  EXPECT_EQ(j["min_ncc"], 0.65);
  EXPECT_EQ(j["verbose"], true);
  EXPECT_EQ(j["name"], "run 3");
  EXPECT_EQ(j["search"]["sigma_gate"], 2.5);
  EXPECT_EQ(j["search"]["patch_size"], 11);
  // The recorded settings, written back as YAML, load into the same options.
  const ExampleOptions back = loadFromYaml("example:\n" + yamlFromJson(j, "  "));
  EXPECT_EQ(optionsToJson(back), j);
  // describeOptions lists every field with its doc.
  const std::string text = describeOptions(o);
  EXPECT_NE(text.find("max_features: 7  # features kept at most"), std::string::npos) << text;
  EXPECT_NE(text.find("  patch_size: 11  # pixels, odd"), std::string::npos) << text;
}

// A struct bounded by the image size, nested two levels down: checkOptionsAgainstImage finds it
// and names its full path and the size; a struct without checkImage is skipped.
struct WindowOptions {
  int window_px = 21;
  template <class V>
  void visit(V& v) {
    v("window_px", window_px, "pixels");
  }
  void check() const {}
  void checkImage(cv::Size image) const { requireWithinImage("window_px", window_px, image.height, image); }
};
struct TrackerOptions {
  WindowOptions lk;
  SearchOptions search;
  template <class V>
  void visit(V& v) {
    v("lk", lk, "optical flow");
    v("search", search, "active search");
  }
  void check() const {}
};

TEST(Options, ImageBoundsAreCheckedWhereverNested) {
  TrackerOptions o;
  EXPECT_NO_THROW(checkOptionsAgainstImage(o, cv::Size(160, 120), "run.yaml: cslam"));
  o.lk.window_px = 121;
  try {
    checkOptionsAgainstImage(o, cv::Size(160, 120), "run.yaml: cslam");
    FAIL() << "a window taller than the image was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "run.yaml: cslam.lk.window_px: must be at most 120 px for 160x120 images, got 121");
  }
  EXPECT_NO_THROW(checkOptionsAgainstImage(o, cv::Size(640, 480), "cslam"));
}

}  // namespace
}  // namespace slamcmp
