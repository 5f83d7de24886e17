// What `run` and `compare` leave and say when a run is not quite right (cases found by the
// reliability probe).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_util.h"

namespace fs = std::filesystem;

namespace slamcmp {
namespace {

using test::TempDir;
using test::writeText;

int lineCount(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// tv1's first `frames` frames rendered into tmp/`name`.
std::string renderTv1(const TempDir& tmp, int frames, const std::string& name = "tv1") {
  const auto r = test::runSlamcmp("synth --preset tv1 --frames " + std::to_string(frames) +
                                  " --supersample 1 --out " + tmp.file(name));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return tmp.file(name);
}

// A run that fails midway (an image of another size at frame 5) into the folder of a finished run:
// the earlier run's summary.json, map.ply and keyframes.txt must not stay beside the new run's
// partial files.
TEST(RunOutputs, AFailedRerunLeavesNoEarlierSummaryBehind) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 10);
  const std::string out = tmp.file("out");
  const auto first = test::runSlamcmp("run --backend cslam --sequence " + seq + " --out " + out);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  ASSERT_TRUE(fs::exists(out + "/summary.json"));
  ASSERT_TRUE(fs::exists(out + "/map.ply"));
  ASSERT_TRUE(fs::exists(out + "/keyframes.txt"));
  writeText(out + "/notes.txt", "the user's own file\n");

  ASSERT_TRUE(cv::imwrite(seq + "/rgb/000005.png", cv::Mat(60, 80, CV_8UC1, cv::Scalar(128))));
  const auto rerun = test::runSlamcmp("run --backend cslam --sequence " + seq + " --out " + out);
  EXPECT_EQ(rerun.exit_code, 2) << rerun.err;
  EXPECT_NE(rerun.err.find("000005.png: image is 80x60"), std::string::npos) << rerun.err;
  EXPECT_FALSE(fs::exists(out + "/summary.json"));
  EXPECT_FALSE(fs::exists(out + "/map.ply"));
  EXPECT_FALSE(fs::exists(out + "/keyframes.txt"));
  EXPECT_EQ(test::readLines(out + "/frames.csv").size(), 6u);  // the header and frames 0 to 4
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));                  // only the run's own outputs go
}

// One undecodable image in a sequence does not end the run: its frame is lost, and the file is
// named once on stderr however often the list plays it.
TEST(RunOutputs, AnUndecodableImageMidSequenceIsWarnedOnce) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 10);
  writeText(seq + "/rgb/000004.png", "not a PNG");
  std::ofstream(seq + "/rgb.txt", std::ios::app) << "100.0 rgb/000004.png\n";  // played again, last
  const std::string out = tmp.file("out");
  const auto r = test::runSlamcmp("run --backend cslam --sequence " + seq + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind(seq + "/rgb/000004.png: warning: cannot be decoded as an image", 0), 0u) << r.err;
  const auto rows = test::readLines(out + "/frames.csv");
  ASSERT_EQ(rows.size(), 12u);
  EXPECT_EQ(rows[5].rfind("4,", 0), 0u);
  EXPECT_NE(rows[5].find(",lost,"), std::string::npos) << rows[5];
  EXPECT_NE(rows[11].find(",lost,"), std::string::npos) << rows[11];
}

// Ground truth the run cannot be scored against (its clock 1000 s off): the run is fine (exit 0),
// and one line names groundtruth.txt and why, as summary.json's metrics_error does.
TEST(RunOutputs, GroundTruthThatCannotScoreTheRunIsWarnedAbout) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 10);
  std::string shifted;
  for (const std::string& line : test::readLines(seq + "/groundtruth.txt")) {
    if (line.empty() || line[0] == '#') continue;
    const auto space = line.find(' ');
    shifted += std::to_string(std::stod(line.substr(0, space)) + 1000.0) + line.substr(space) + "\n";
  }
  writeText(seq + "/groundtruth.txt", shifted);
  const std::string out = tmp.file("out");
  const auto r = test::runSlamcmp("run --backend cslam --sequence " + seq + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind(seq + "/groundtruth.txt: warning: the run cannot be scored against it: no time overlap", 0),
            0u)
      << r.err;
  const nlohmann::json summary = nlohmann::json::parse(readFile(out + "/summary.json"));
  EXPECT_NE(summary.value("metrics_error", "").find("no time overlap"), std::string::npos) << summary.dump();
}

// A run with one posed frame has no ATE or RPE (each needs two poses): said, not left out unsaid.
TEST(RunOutputs, ARunTooShortToScoreIsWarnedAbout) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 3);
  const std::string out = tmp.file("out");
  const auto r = test::runSlamcmp("run --backend cslam --max-frames 1 --sequence " + seq + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind(seq + "/groundtruth.txt: warning: the run cannot be scored against it: 1 posed frame(s)", 0), 0u)
      << r.err;
  const nlohmann::json summary = nlohmann::json::parse(readFile(out + "/summary.json"));
  EXPECT_FALSE(summary.contains("ate"));
  EXPECT_EQ(summary.value("metrics_error", ""), "1 posed frame(s): the ATE and RPE need 2 or more");
  const auto two = test::runSlamcmp("run --backend cslam --max-frames 2 --sequence " + seq + " --out " + out);
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_EQ(two.err, "");
  EXPECT_TRUE(nlohmann::json::parse(readFile(out + "/summary.json")).contains("ate"));
}

// A board described wrong (its inner corner counts swapped; its square size doubled) poses every
// frame in a world turned or scaled against the ground truth's: said, with the fit that shows it.
TEST(RunOutputs, ABoardDescribedWrongIsHintedAt) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 12);
  const std::string target = readFile(seq + "/target.yaml");
  const auto hint = [&](const std::string& changed_target) {
    writeText(seq + "/target.yaml", changed_target);
    const auto r = test::runSlamcmp("run --backend cslam --sequence " + seq + " --out " + tmp.file("out"));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_LE(lineCount(r.err), 1) << r.err;
    const nlohmann::json summary = nlohmann::json::parse(readFile(tmp.file("out/summary.json")));
    return std::make_pair(r.err, summary.value("metrics_warning", ""));
  };
  const std::string swapped = hint(std::regex_replace(std::regex_replace(target, std::regex("inner_corners_cols: 9"), "inner_corners_cols: 6"),
                                    std::regex("inner_corners_rows: 6"), "inner_corners_rows: 9")).second;
  EXPECT_NE(swapped.find("degree turn"), std::string::npos) << swapped;
  EXPECT_NE(swapped.find("is target.yaml's square_size or are its inner corner counts right?"), std::string::npos);
  const std::string doubled =
      hint(std::regex_replace(target, std::regex("square_size: [^\n]*"), "square_size: 0.08")).second;
  EXPECT_NE(doubled.find("a scale of 0.50"), std::string::npos) << doubled;
  EXPECT_EQ(hint(target).second, "");
}

// A compare of cslam on tv1's first 10 frames into tmp/c; the run's folder.
std::string compareTv1(const TempDir& tmp) {
  const std::string seq = renderTv1(tmp, 10, "good");
  const auto r = test::runSlamcmp("compare --jobs 1 --sequence " + seq + " --backends cslam --out " + tmp.file("c"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return tmp.file("c/runs/good-cslam");
}

// The error results.csv gives the run of `dir` after compare --collect of it.
std::string collectedError(const std::string& dir) {
  test::runSlamcmp("compare --collect " + dir);
  const std::string results = readFile(dir + "/results.csv");
  const auto at = results.find("runs/good-cslam,");
  return at == std::string::npos ? "" : results.substr(at, results.find('\n', at) - at);
}

// --collect does not take the files of two runs (an earlier run's summary.json beside a rerun's
// frames.csv cut short) for one.
TEST(RunOutputs, CollectRefusesARunWhoseFilesDisagree) {
  TempDir tmp;
  const std::string run = compareTv1(tmp);
  const std::vector<std::string> rows = test::readLines(run + "/frames.csv");
  std::string fewer;
  for (size_t i = 0; i + 3 < rows.size(); ++i) fewer += rows[i] + "\n";
  writeText(run + "/frames.csv", fewer);
  std::string error = collectedError(tmp.file("c"));
  EXPECT_NE(error.find(run + "/frames.csv: has 7 rows but summary.json says 10 frames"), std::string::npos) << error;

  // summary.json's nees is nees.csv's mean: one without the other (a filter's run whose nees.csv
  // was lost would leave the trials' NEES test without it, unsaid).
  const std::string other = compareTv1(tmp);
  nlohmann::json summary = nlohmann::json::parse(readFile(other + "/summary.json"));
  summary["nees"] = {{"mean", 6.0}, {"dof", 6}, {"lower", 5.0}, {"upper", 7.0}};
  writeText(other + "/summary.json", summary.dump());
  error = collectedError(tmp.file("c"));
  EXPECT_NE(error.find(other + "/summary.json: has nees but nees.csv is missing"), std::string::npos) << error;
  summary.erase("nees");
  writeText(other + "/summary.json", summary.dump());
  writeText(other + "/nees.csv", "timestamp,nees,position,orientation\n0.1,6,3,3\n");
  error = collectedError(tmp.file("c"));
  EXPECT_NE(error.find(other + "/nees.csv: is there but summary.json has no nees"), std::string::npos) << error;
}

// --collect checks what it reads of summary.json: a negative count or a word for a number is
// refused naming the file and the field, not drawn or left as an empty cell.
TEST(RunOutputs, CollectRefusesAMalformedSummary) {
  TempDir tmp;
  const std::string run = compareTv1(tmp);
  nlohmann::json summary = nlohmann::json::parse(readFile(run + "/summary.json"));
  summary["tracked"] = -5;
  writeText(run + "/summary.json", summary.dump());
  std::string error = collectedError(tmp.file("c"));
  EXPECT_NE(error.find(run + "/summary.json: tracked: must be a whole number from 0 to 10, got -5"), std::string::npos)
      << error;
  summary["tracked"] = 10;
  summary["ms_per_frame"]["median"] = "fast";
  writeText(run + "/summary.json", summary.dump());
  error = collectedError(tmp.file("c"));
  EXPECT_NE(error.find(run + "/summary.json: ms_per_frame.median: must be a number of milliseconds, got \"\"fast\"\""),
            std::string::npos)
      << error;
}

// --collect of a run one of whose files is a folder says so, naming the file (a folder was read as
// an empty file: frames.csv and nees.csv "had the wrong header", map.ply "no end_header line",
// summary.json "Is a directory" naming no file), as for any run that cannot be read: one line for
// the run, one for the report, exit 2.
TEST(RunOutputs, CollectSaysWhichRunFileIsAFolder) {
  TempDir tmp;
  const std::string run = compareTv1(tmp);
  ASSERT_TRUE(fs::exists(run + "/map.ply"));  // read as tv1 has a scene.yaml
  ASSERT_FALSE(fs::exists(run + "/nees.csv"));  // cslam writes none; read when it is there
  for (const char* name : {"summary.json", "frames.csv", "trajectory.txt", "nees.csv", "map.ply"}) {
    SCOPED_TRACE(name);
    const std::string file = run + "/" + name, aside = tmp.file("aside");
    const bool existed = fs::exists(file);
    if (existed) fs::rename(file, aside);
    fs::create_directory(file);
    const auto collected = test::runSlamcmp("compare --collect " + tmp.file("c"));
    EXPECT_EQ(collected.exit_code, 2) << collected.err;
    EXPECT_EQ(lineCount(collected.err), 2) << collected.err;
    EXPECT_EQ(collected.err.rfind("slamcmp: " + run + ": failed: " + file + ": is a folder, not a text file\n", 0), 0u)
        << collected.err;
    fs::remove(file);
    if (existed) fs::rename(aside, file);
  }
  const auto restored = test::runSlamcmp("compare --collect " + tmp.file("c"));
  EXPECT_EQ(restored.exit_code, 0) << restored.err;
}

// --collect of a planned run whose log is a folder (and no summary.json): the run failed, and its
// error names the log as a folder (it was "nothing in its log (killed?)").
TEST(RunOutputs, CollectSaysARunLogIsAFolder) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 3, "good");
  const std::string plan = tmp.file("p");
  const auto planned = test::runSlamcmp("compare --sequence " + seq + " --backends cslam --plan " + plan);
  ASSERT_EQ(planned.exit_code, 0) << planned.err;
  const std::string log = plan + "/logs/good-cslam.log";
  fs::create_directories(log);
  const auto collected = test::runSlamcmp("compare --collect " + plan);
  EXPECT_EQ(collected.exit_code, 2) << collected.err;
  EXPECT_EQ(lineCount(collected.err), 2) << collected.err;
  EXPECT_EQ(collected.err.rfind("slamcmp: " + plan + "/runs/good-cslam: failed: " + log +
                                    ": is a folder, not a text file\n",
                                0),
            0u)
      << collected.err;
}

// --collect of a run whose log ends on its success line but whose summary.json is gone: the
// error says summary.json is missing (it quoted the success line alone, as if that were the failure).
TEST(RunOutputs, CollectSaysASummaryIsMissing) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 3, "good");
  const std::string dir = tmp.file("c");
  ASSERT_EQ(test::runSlamcmp("compare --jobs 1 --sequence " + seq + " --backends cslam --out " + dir).exit_code, 0);
  fs::remove(dir + "/runs/good-cslam/summary.json");
  const auto collected = test::runSlamcmp("compare --collect " + dir);
  EXPECT_EQ(collected.exit_code, 2) << collected.err;
  EXPECT_EQ(collected.err.rfind("slamcmp: " + dir + "/runs/good-cslam: failed: no summary.json; its log ends: cslam: 3/3",
                                0),
            0u)
      << collected.err;
}

// A compare where a run failed says so, a line for each, and exits 2, as --collect of it does.
TEST(RunOutputs, CompareAndCollectSayWhichRunsFailed) {
  TempDir tmp;
  const std::string good = renderTv1(tmp, 10, "good");
  const std::string bad = renderTv1(tmp, 10, "bad");
  ASSERT_TRUE(cv::imwrite(bad + "/rgb/000003.png", cv::Mat(60, 80, CV_8UC1, cv::Scalar(128))));
  const std::string dir = tmp.file("c");
  const auto r = test::runSlamcmp("compare --jobs 1 --sequence " + good + " --sequence " + bad +
                                  " --backends cslam --out " + dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.out.find("report: "), std::string::npos) << r.out;
  ASSERT_EQ(lineCount(r.err), 2) << r.err;
  EXPECT_EQ(r.err.rfind("slamcmp: " + dir + "/runs/bad-cslam: failed: " + bad + "/rgb/000003.png: image is 80x60", 0),
            0u)
      << r.err;
  EXPECT_NE(r.err.find("1 run(s) failed"), std::string::npos) << r.err;

  const auto collected = test::runSlamcmp("compare --collect " + dir);
  EXPECT_EQ(collected.exit_code, 2) << collected.err;
  EXPECT_EQ(collected.err, r.err);
}

// A sequence gone since its runs (deleted, or not copied back from a cluster's scratch) fails its
// own runs, a line for each, and exit 2; the other sequence's runs are collected and reported, the
// gone one's length unknown (it stopped the whole collect with "does not exist").
TEST(RunOutputs, CollectWithASequenceGoneReportsTheOthers) {
  TempDir tmp;
  const std::string kept = renderTv1(tmp, 4, "kept");
  const std::string gone = renderTv1(tmp, 4, "gone");
  const std::string dir = tmp.file("c");
  ASSERT_EQ(test::runSlamcmp("compare --jobs 1 --sequence " + kept + " --sequence " + gone +
                             " --backends cslam,monoslam --out " + dir)
                .exit_code,
            0);
  fs::remove_all(gone);
  const auto collected = test::runSlamcmp("compare --collect " + dir);
  EXPECT_EQ(collected.exit_code, 2) << collected.err;
  EXPECT_EQ(lineCount(collected.err), 3) << collected.err;
  for (const std::string run : {"gone-cslam", "gone-monoslam"})
    EXPECT_NE(collected.err.find("slamcmp: " + dir + "/runs/" + run + ": failed: its sequence cannot be read: " + gone +
                                 ": does not exist\n"),
              std::string::npos)
        << collected.err;
  EXPECT_NE(collected.err.find("2 run(s) failed"), std::string::npos) << collected.err;
  const std::vector<std::string> report = test::readLines(dir + "/report.md");
  const auto has = [&](const std::string& line) { return std::find(report.begin(), report.end(), line) != report.end(); };
  EXPECT_TRUE(has("| kept | 4 | - |  |"));
  EXPECT_TRUE(has("| gone | - | - |  |"));
  for (const std::string backend : {"cslam", "monoslam"}) {
    EXPECT_TRUE(std::any_of(report.begin(), report.end(), [&](const std::string& line) {
      return line.rfind("| kept | " + backend + " | 4/4 |", 0) == 0;
    })) << backend;
    EXPECT_TRUE(has("- `runs/gone-" + backend + "`: failed: its sequence cannot be read: " + gone + ": does not exist"))
        << backend;
  }
}

}  // namespace
}  // namespace slamcmp
