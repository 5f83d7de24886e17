// compare as an experiment: trials and sweeps (results.csv one row a run, the report's mean ± std
// recomputed from it), a plan run elsewhere and collected (byte-identical tables), GNU parallel
// over jobs.txt, and an interrupted compare (exit 130, unfinished runs marked).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/target.h"
#include "datasets/synth_sequence.h"
#include "eval/app/compare.h"
#include "eval/app/compare_plan.h"
#include "tests/test_util.h"

namespace fs = std::filesystem;

namespace slamcmp {
namespace {

using test::TempDir;

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// One CSV line's fields ("..." quoting as results.csv writes it).
std::vector<std::string> csvFields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      out.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}

// results.csv as rows of column name -> text.
std::vector<std::map<std::string, std::string>> readResults(const std::string& path) {
  const std::vector<std::string> lines = test::readLines(path);
  std::vector<std::map<std::string, std::string>> rows;
  if (lines.empty()) return rows;
  const std::vector<std::string> header = csvFields(lines[0]);
  for (size_t k = 1; k < lines.size(); ++k) {
    const std::vector<std::string> f = csvFields(lines[k]);
    EXPECT_EQ(f.size(), header.size()) << lines[k];
    std::map<std::string, std::string> row;
    for (size_t c = 0; c < header.size() && c < f.size(); ++c) row[header[c]] = f[c];
    rows.push_back(row);
  }
  return rows;
}

// tv1's first `frames`, rendered fast (one sample a pixel).
SynthOptions shortTv1(int frames) {
  SynthOptions synth;
  synth.preset = "tv1";
  synth.frames = frames;
  synth.supersample = 1;
  return synth;
}

std::string renderTv1(const TempDir& tmp, int frames) {
  writeSyntheticSequence(shortTv1(frames), tmp.file("tv1"));
  return tmp.file("tv1");
}

CompareOptions shortCompare(const std::string& sequence, const std::string& methods, const std::string& out) {
  CompareOptions options;
  options.sequences = {sequence};
  options.methods = parseMethods(methods);
  options.out_dir = out;
  const char* bin = std::getenv("SLAMCMP_BIN");
  if (bin) options.slamcmp = bin;  // the runs are `slamcmp run` processes
  return options;
}

// Three trials of cslam swept over two feature counts and of monoslam: a row per run with its
// trial, seed and swept value; each report cell is the mean ± population std of results.csv's
// numbers, recomputed here; monoslam's NEES over the trials is recomputed from its runs' nees.csv;
// the sweep's, the trials' and the NEES figures are drawn.
TEST(CompareExperiment, TrialStatisticsAreRecomputableFromResultsCsv) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  CompareOptions options = shortCompare(renderTv1(tmp, 15), "cslam,monoslam", tmp.file("out"));
  options.trials = 3;
  options.sets = {"cslam.features.max_features=100,200"};
  const std::string report = readFile(runCompare(options));

  const auto rows = readResults(tmp.file("out/results.csv"));
  ASSERT_EQ(rows.size(), 3u * 3u);  // (cslam x 2 settings + monoslam) x 3 trials
  std::map<std::string, std::vector<double>> ate_mm, cpu;
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("status"), "ok") << row.at("run") << ": " << row.at("error");
    EXPECT_EQ(row.at("seed_kind"), "render");  // a synthetic sequence: each trial rendered with its seed
    EXPECT_EQ(row.at("seed"), row.at("trial"));
    const std::string swept = row.at("cslam.features.max_features");
    EXPECT_EQ(swept.empty(), row.at("method") == "monoslam");
    const std::string label = row.at("method") + (swept.empty() ? "" : " features.max_features=" + swept);
    ate_mm[label].push_back(1e3 * std::stod(row.at("ate_trans_rmse_m")));
    cpu[label].push_back(std::stod(row.at("cpu_ms_median")));
  }
  // Trial k's render differs from trial 1's (the seed changes the room's textures and the jitter).
  EXPECT_NE(ate_mm["monoslam"][0], ate_mm["monoslam"][1]);
  auto meanStd = [](const std::vector<double>& v) {
    double mean = 0, var = 0;
    for (double x : v) mean += x / v.size();
    for (double x : v) var += (x - mean) * (x - mean) / v.size();
    char text[64];
    std::snprintf(text, sizeof text, "%.2f ± %.2f", mean, std::sqrt(var));
    return std::string(text);
  };
  ASSERT_EQ(ate_mm.size(), 3u);
  for (const auto& [label, values] : ate_mm) {
    ASSERT_EQ(values.size(), 3u) << label;
    // The accuracy row: | tv1 | label | posed | first lost | ATE ... | ... | CPU ms | ms |
    const std::string row_start = "| tv1 | " + label + " | ";
    const size_t at = report.find(row_start);
    ASSERT_NE(at, std::string::npos) << label << "\n" << report;
    const std::string row = report.substr(at, report.find('\n', at) - at);
    EXPECT_NE(row.find("| " + meanStd(values) + " |"), std::string::npos) << row << " vs " << meanStd(values);
    EXPECT_NE(row.find("| " + meanStd(cpu[label]) + " |"), std::string::npos) << row << " vs " << meanStd(cpu[label]);
  }
  EXPECT_NE(report.find("## Sweep: accuracy against CPU time"), std::string::npos);
  EXPECT_NE(report.find("The thesis's MonoSLAM lost every feature on tv1"), std::string::npos) << report;
  // monoslam's NEES over the trials, frame by frame (its runs' nees.csv): the mean of the frames'
  // trial averages, recomputed here, and the share of frames inside their interval in [0, 100].
  std::map<double, std::vector<double>> per_frame;
  for (const auto& row : rows) {
    if (row.at("method") != "monoslam") continue;
    const std::vector<std::string> lines = test::readLines(tmp.file("out/" + row.at("run") + "/nees.csv"));
    ASSERT_GT(lines.size(), 10u) << row.at("run");
    EXPECT_EQ(lines[0], "timestamp,nees,position,orientation");
    double sum = 0, position = 0, orientation = 0;
    for (size_t k = 1; k < lines.size(); ++k) {
      const std::vector<std::string> f = csvFields(lines[k]);
      per_frame[std::stod(f[0])].push_back(std::stod(f[1]));
      sum += std::stod(f[1]);
      position += std::stod(f[2]);
      orientation += std::stod(f[3]);
    }
    const double n = lines.size() - 1;
    EXPECT_NEAR(std::stod(row.at("nees_mean")), sum / n, 1e-9 * sum);  // summary.json's
    EXPECT_NEAR(std::stod(row.at("nees_position_mean")), position / n, 1e-9 * position);
    EXPECT_NEAR(std::stod(row.at("nees_orientation_mean")), orientation / n, 1e-9 * orientation);
  }
  double anees_sum = 0;
  int frames = 0;
  size_t fewest = 3, most = 0;
  for (const auto& [t, v] : per_frame) {
    if (v.size() < 2) continue;
    fewest = std::min(fewest, v.size());
    most = std::max(most, v.size());
    double mean = 0;
    for (double x : v) mean += x / v.size();
    anees_sum += mean;
    ++frames;
  }
  ASSERT_GT(frames, 10);
  char anees_text[32];
  std::snprintf(anees_text, sizeof anees_text, "%.2f", anees_sum / frames);
  const size_t nees_table = report.find("## Consistency over the trials (Monte Carlo NEES)");
  ASSERT_NE(nees_table, std::string::npos) << report;
  const std::string trials_text = std::to_string(fewest) + (fewest == most ? "" : "-" + std::to_string(most));
  const std::string nees_row_start =
      "| tv1 | monoslam | " + trials_text + " | " + std::to_string(frames) + " | " + anees_text + " | ";
  EXPECT_NE(report.find(nees_row_start, nees_table), std::string::npos) << nees_row_start << "\n" << report;
  for (const char* figure : {"ate_boxplot", "sweep_ate_cpu", "tv1_stages", "tv1_anees"}) {
    EXPECT_TRUE(fs::exists(tmp.file(std::string("out/figures/") + figure + ".png"))) << figure;
    EXPECT_NE(report.find(std::string("(figures/") + figure + ".png)"), std::string::npos) << figure;
  }
  // Trials 2 and 3 were rendered; trial 1 is the given sequence (rendered with seed 1).
  EXPECT_TRUE(fs::exists(tmp.file("out/sequences/seed2/tv1/rgb.txt")));
  EXPECT_FALSE(fs::exists(tmp.file("out/sequences/seed1")));
}

// A real sequence (no info.yaml) is rerun with `run --seed k`; a sweep value a back-end refuses,
// or a swept back-end not compared, stops the compare before anything runs.
TEST(CompareExperiment, RealSequencesTakeTheBackEndSeedAndBadSweepsAreRefused) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 12);
  fs::remove(seq + "/info.yaml");
  CompareOptions options = shortCompare(seq, "monoslam", tmp.file("plan"));
  options.trials = 2;
  planCompare(options);
  const std::string jobs = readFile(tmp.file("plan/jobs.txt"));
  EXPECT_NE(jobs.find("--seed 1 "), std::string::npos) << jobs;
  EXPECT_NE(jobs.find("--seed 2 "), std::string::npos) << jobs;
  options.sets = {"cslam.features.max_features=50"};
  EXPECT_THROW(planCompare(options), InputError);  // cslam is not compared
  options.methods = parseMethods("cslam");
  options.sets = {"cslam.features.max_features=50,many"};
  try {
    planCompare(options);
    FAIL() << "a value the option cannot take";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cslam.features.max_features"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("many"), std::string::npos) << e.what();
  }
  // A render copied and changed (here another square size) keeps its info.yaml; its trials are
  // its back-ends' seeds, not new renders of another board.
  {
    const std::string changed = tmp.file("changed");
    const std::string rendered = renderTv1(tmp, 12);
    fs::copy(rendered, changed, fs::copy_options::recursive);
    ChessboardTarget target = readTargetYaml(changed + "/target.yaml", true);
    target.square_size *= 2;
    writeTargetYaml(changed + "/target.yaml", target);
    CompareOptions copied = shortCompare(changed, "cslam", tmp.file("copied"));
    copied.trials = 2;
    planCompare(copied);
    const std::string copied_jobs = readFile(tmp.file("copied/jobs.txt"));
    EXPECT_NE(copied_jobs.find("--sequence " + changed + " --out " + tmp.file("copied/runs/changed-cslam-t2") + " --seed 2"),
              std::string::npos)
        << copied_jobs;
    EXPECT_FALSE(fs::exists(tmp.file("copied/sequences")));
  }
  // Values written apart but read alike would run the same runs twice.
  for (const auto& [sweep, said] : std::vector<std::pair<std::string, std::string>>{
           {"cslam.features.max_features=200,150,0200", "lists '200' and '0200', the same value"},
           {"cslam.fusion.min_pixel_sigma=0.02,2e-2", "lists '0.02' and '2e-2', the same value"},
           {"cslam.fusion.enabled=true,1", "lists 'true' and '1', the same value"}}) {
    options.sets = {sweep};
    try {
      planCompare(options);
      ADD_FAILURE() << "accepted " << sweep;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--set " + sweep + ": " + said), std::string::npos) << e.what();
    }
  }
  options.sets = {"cslam.fusion.min_pixel_sigma=0.02,0.021"};
  EXPECT_EQ(planCompare(options), 4u);
}

// A sequence without ground truth (a real video) over trials and a sweep: no ATE to plot, and the
// report is written without those figures (gnuplot was handed empty panels: exit 1, no report).
// Compared again into the same folder with fewer runs, the earlier experiment's run folders,
// trial renders and figures are gone.
TEST(CompareExperiment, NoGroundTruthTrialsAndARerunIntoTheSameFolder) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 12);
  for (const char* file : {"groundtruth.txt", "scene.yaml", "info.yaml"}) fs::remove(seq + "/" + file);
  CompareOptions options = shortCompare(seq, "cslam", tmp.file("c"));
  options.trials = 2;  // without info.yaml, each trial its back-end's seed
  options.sets = {"cslam.features.max_features=100,200"};
  const std::string report = runCompare(options);
  EXPECT_TRUE(fs::exists(report));
  EXPECT_EQ(readFile(report).find("The thesis's MonoSLAM"), std::string::npos);  // no monoslam here
  EXPECT_FALSE(fs::exists(tmp.file("c/figures/ate_boxplot.png")));
  EXPECT_FALSE(fs::exists(tmp.file("c/figures/sweep_ate_cpu.png")));
  EXPECT_EQ(readResults(tmp.file("c/results.csv")).size(), 4u);
  const std::vector<std::string> first_figures = linkedFigures(tmp.file("c"));
  ASSERT_FALSE(first_figures.empty());
  for (const std::string& figure : first_figures) EXPECT_TRUE(fs::exists(tmp.file("c/" + figure))) << figure;
  // The user's own files in compare's folders: a figure for a paper, a standalone run's default
  // folder (runs/SEQ-BACKEND), notes. Every later compare or plan into the folder leaves them.
  const std::vector<std::string> users = {"c/figures/paper_fig1.pdf", "c/runs/tv1-monoslam/summary.json",
                                          "c/runs/notes.txt", "c/logs/mine.txt"};
  for (const std::string& file : users) {
    fs::create_directories(fs::path(tmp.file(file)).parent_path());
    test::writeText(tmp.file(file), "the user's\n");
  }
  test::writeText(tmp.file("c/logs/slurm-12_3.out"), "a Slurm task's log of the earlier compare\n");
  runCompare(options);  // the same experiment again, and its collect
  for (const std::string& file : users) EXPECT_TRUE(fs::exists(tmp.file(file))) << file;
  EXPECT_FALSE(fs::exists(tmp.file("c/logs/slurm-12_3.out")));
  // A standalone run in the folder compare's own run would take is refused, not replaced.
  {
    TempDir other;
    fs::create_directories(other.file("o/runs/tv1-cslam"));
    test::writeText(other.file("o/runs/tv1-cslam/summary.json"), "the user's\n");
    CompareOptions into = shortCompare(seq, "cslam", other.file("o"));
    EXPECT_THROW(planCompare(into), InputError);
    EXPECT_TRUE(fs::exists(other.file("o/runs/tv1-cslam/summary.json")));
  }
  // A report.md or plan.json edited to point outside compare's folders removes nothing there.
  test::writeText(tmp.file("c/outside.txt"), "the user's\n");
  {
    std::ofstream report(tmp.file("c/report.md"), std::ios::app);
    report << "![x](figures/../outside.txt)\n![y](figures/..)\n";
  }
  const std::string valid_plan = readFile(tmp.file("c/plan.json"));
  std::string plan_text = valid_plan;
  const size_t log = plan_text.find("\"log\": \"") + 8;
  ASSERT_NE(log, std::string::npos + 8);
  plan_text.replace(log, plan_text.find('"', log) - log, "logs/../outside.txt");
  test::writeText(tmp.file("c/plan.json"), plan_text);
  runCompare(options);
  EXPECT_TRUE(fs::exists(tmp.file("c/outside.txt")));
  for (const std::string& file : users) EXPECT_TRUE(fs::exists(tmp.file(file))) << file;
  test::writeText(tmp.file("c/plan.json"), "{\"not\": \"a plan\"}\n");
  EXPECT_THROW(runCompare(options), InputError);  // not an earlier compare's: nothing removed
  EXPECT_TRUE(fs::exists(tmp.file("c/results.csv")));
  test::writeText(tmp.file("c/plan.json"), valid_plan);

  // A plan into the folder: the earlier experiment's report and tables go with its runs.
  CompareOptions plan_only = shortCompare(seq, "cslam", tmp.file("c"));
  planCompare(plan_only);
  for (const char* file : {"report.md", "results.csv", "table_3_1.csv", "table_3_2.csv"})
    EXPECT_FALSE(fs::exists(tmp.file(std::string("c/") + file))) << file;
  EXPECT_TRUE(fs::exists(tmp.file("c/jobs.txt")));

  const std::string with_truth = renderTv1(tmp, 12);  // the same folder, ground truth back
  ASSERT_EQ(with_truth, seq);
  CompareOptions again = shortCompare(seq, "cslam", tmp.file("c"));
  runCompare(again);
  EXPECT_EQ(readResults(tmp.file("c/results.csv")).size(), 1u);
  EXPECT_FALSE(fs::exists(tmp.file("c/runs/tv1-cslam-features.max_features=100-t1")));
  EXPECT_FALSE(fs::exists(tmp.file("c/sequences")));
  size_t runs = 0;
  for (const auto& entry : fs::directory_iterator(tmp.file("c/runs"))) runs += entry.is_directory();
  EXPECT_EQ(runs, 2u);  // this compare's and the user's
  for (const std::string& file : users) EXPECT_TRUE(fs::exists(tmp.file(file))) << file;
  // The first report's figures that this one does not draw are gone.
  const std::vector<std::string> figures = linkedFigures(tmp.file("c"));
  for (const std::string& figure : first_figures)
    EXPECT_EQ(fs::exists(tmp.file("c/" + figure)), std::count(figures.begin(), figures.end(), figure) == 1) << figure;

  // A sequence given from the folder's sequences/ (as reproduce renders tv1..tv4 there) stays for
  // the next compare into it; the earlier trials' renders beside it go.
  const SynthOptions synth = shortTv1(4);
  writeSyntheticSequence(synth, tmp.file("r/sequences/tv1"));
  CompareOptions inside = shortCompare(tmp.file("r/sequences/tv1"), "cslam", tmp.file("r"));
  inside.trials = 2;
  runCompare(inside);
  EXPECT_TRUE(fs::exists(tmp.file("r/sequences/seed2/tv1/rgb.txt")));
  inside.trials = 1;
  runCompare(inside);
  EXPECT_EQ(readResults(tmp.file("r/results.csv")).size(), 1u);
  EXPECT_TRUE(fs::exists(tmp.file("r/sequences/tv1/rgb.txt")));
  EXPECT_FALSE(fs::exists(tmp.file("r/sequences/seed2")));

  // Nor one given that is a trial render's folder itself, nor a user's folder behind a link of
  // that name.
  writeSyntheticSequence(synth, tmp.file("r/sequences/seed3"));
  fs::create_directories(tmp.file("mine"));
  test::writeText(tmp.file("mine/notes.txt"), "the user's\n");
  fs::create_directory_symlink(tmp.file("mine"), tmp.file("r/sequences/seed5"));
  CompareOptions seed3 = shortCompare(tmp.file("r/sequences/seed3"), "cslam", tmp.file("r"));
  runCompare(seed3);
  runCompare(seed3);
  EXPECT_EQ(readResults(tmp.file("r/results.csv")).size(), 1u);
  EXPECT_TRUE(fs::exists(tmp.file("r/sequences/seed3/rgb.txt")));
  EXPECT_TRUE(fs::exists(tmp.file("mine/notes.txt")));
  EXPECT_TRUE(fs::is_symlink(tmp.file("r/sequences/seed5")));
}

// A run that `run` could not score (two posed frames under Sim(3): the alignment needs three) is
// whole, as `run` exits 0 for it: compare lists it ok with empty score cells and says why, where it
// called it failed and exited 2.
TEST(CompareExperiment, ARunTooShortToScoreIsWholeNotFailed) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 12);
  CompareOptions options = shortCompare(seq, "monoslam@none", tmp.file("c"));
  options.max_frames = 2;
  std::vector<UnfinishedRun> unfinished;
  runCompare(options, &unfinished);
  EXPECT_TRUE(unfinished.empty());
  const auto rows = readResults(tmp.file("c/results.csv"));
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("status"), "ok");
  EXPECT_TRUE(rows[0].at("ate_trans_rmse_m").empty()) << rows[0].at("ate_trans_rmse_m");
  EXPECT_NE(rows[0].at("error").find("not scored"), std::string::npos) << rows[0].at("error");
  EXPECT_NE(rows[0].at("error").find("3"), std::string::npos) << rows[0].at("error");
}

// Collected while its runs are still going (a cluster's array mid-way), a run with a log but no
// summary.json is not finished, not failed: collect exits 0 with its warning (it called every
// running run failed and exited 2). A run that ended on a signal compare did not send (a crash)
// failed, and says which signal.
TEST(CompareExperiment, RunningRunsAreUnfinishedAndACrashSaysItsSignal) {
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 4);
  CompareOptions options = shortCompare(seq, "cslam", tmp.file("p"));
  options.slamcmp = "/bin/true";  // never run: the runs' logs are made here
  planCompare(options);
  test::writeText(tmp.file("p/logs/tv1-cslam.log"), "tv1: warning: a line a running run printed\n");
  std::vector<UnfinishedRun> unfinished;
  collectCompare(tmp.file("p"), &unfinished);  // throws InputError if a run failed
  ASSERT_EQ(unfinished.size(), 1u);
  EXPECT_EQ(unfinished[0].status, "unfinished");
  EXPECT_NE(unfinished[0].error.find("still running"), std::string::npos) << unfinished[0].error;

  // A run program that dies on SIGKILL.
  const std::string crash = tmp.file("crash.sh");
  test::writeText(crash, "#!/bin/sh\nkill -KILL $$\n");
  fs::permissions(crash, fs::perms::owner_all);
  CompareOptions crashing = shortCompare(seq, "cslam", tmp.file("c"));
  crashing.slamcmp = crash;
  runCompare(crashing, &unfinished);
  ASSERT_EQ(unfinished.size(), 1u);
  EXPECT_EQ(unfinished[0].status, "failed");
  EXPECT_NE(unfinished[0].error.find("ended on signal 9"), std::string::npos) << unfinished[0].error;

  // The same through jobs.txt, as GNU parallel and slurm.sbatch run its lines: the line notes it.
  CompareOptions planned = shortCompare(seq, "cslam", tmp.file("j"));
  planned.slamcmp = crash;
  planCompare(planned);
  const std::vector<std::string> jobs = test::readLines(tmp.file("j/jobs.txt"));
  ASSERT_EQ(jobs.size(), 1u);
  EXPECT_NE(std::system(("/bin/sh -c " + shellQuoted(jobs[0])).c_str()), 0);
  collectCompare(tmp.file("j"), &unfinished);
  ASSERT_EQ(unfinished.size(), 1u);
  EXPECT_EQ(unfinished[0].status, "failed");
  EXPECT_NE(unfinished[0].error.find("ended on signal 9"), std::string::npos) << unfinished[0].error;
}

// Two renders of one preset that differ in their seed alone share every trial (trial k is seed k):
// compare says so. A third with other options (noise) is not said to.
TEST(CompareExperiment, RendersDifferingInTheirSeedAloneAreSaidToShareTheirTrials) {
  TempDir tmp;
  SynthOptions synth = shortTv1(4);
  writeSyntheticSequence(synth, tmp.file("s1"));
  synth.seed = 2;
  writeSyntheticSequence(synth, tmp.file("s2"));
  synth.noise = 1.0;
  writeSyntheticSequence(synth, tmp.file("noisy"));
  CompareOptions options = shortCompare(tmp.file("s1"), "cslam", tmp.file("p"));
  options.sequences = {tmp.file("s1"), tmp.file("s2"), tmp.file("noisy")};
  options.trials = 2;
  testing::internal::CaptureStderr();
  planCompare(options);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find(tmp.file("s2") + ": warning: the same render as " + tmp.file("s1")), std::string::npos) << err;
  EXPECT_EQ(err.find(tmp.file("noisy") + ": warning"), std::string::npos) << err;
  options.trials = 1;  // each its own render
  testing::internal::CaptureStderr();
  planCompare(options);
  EXPECT_EQ(testing::internal::GetCapturedStderr().find("warning"), std::string::npos);
}

// A compare's folder moved (or copied back from a cluster's scratch) is collected where it is now:
// its trial renders are found inside it (collect looked for them at the old path: "does not exist").
// A collect reads the runs, the ground truth and the scene, not the images: a cluster's user who
// deleted the renders' images to free the disk gets the same report (collect refused: "image ...
// does not exist"). A plan still checks them, as its runs need them.
TEST(CompareExperiment, AMovedFolderIsCollectedWhereItIsWithoutItsImages) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 8);
  CompareOptions options = shortCompare(seq, "cslam", tmp.file("a"));
  options.trials = 2;  // trial 2 rendered into a/sequences/seed2
  runCompare(options);
  const std::string before = readFile(tmp.file("a/results.csv"));
  ASSERT_TRUE(fs::exists(tmp.file("a/sequences/seed2/tv1")));
  fs::rename(tmp.file("a"), tmp.file("b"));
  for (const std::string& render : {seq, tmp.file("b/sequences/seed2/tv1")}) {
    ASSERT_TRUE(fs::exists(render + "/rgb")) << render;
    fs::remove_all(render + "/rgb");
  }
  collectCompare(tmp.file("b"));
  const auto rows = readResults(tmp.file("b/results.csv"));
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) EXPECT_EQ(row.at("status"), "ok") << row.at("error");
  EXPECT_EQ(readFile(tmp.file("b/results.csv")), before);
  EXPECT_FALSE(fs::exists(tmp.file("a")));
  try {
    planCompare(shortCompare(seq, "cslam", tmp.file("c")));
    FAIL() << "a plan over a sequence without its images was written";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

// A method whose every run failed: its accuracy row has as many cells as the header (it had one
// more), and a run's map is scored as run wrote it, so results.csv and summary.json agree exactly.
TEST(CompareExperiment, AFailedMethodsRowFitsItsTableAndMapFiguresAgree) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 12);
  CompareOptions options = shortCompare(seq, "monoslam", tmp.file("c"));
  options.sets = {"monoslam.search.source_size=41,1001"};  // 1001: the run fails on the image size
  std::vector<UnfinishedRun> unfinished;
  const std::string report = runCompare(options, &unfinished);
  ASSERT_EQ(unfinished.size(), 1u);
  const std::vector<std::string> lines = test::readLines(report);
  const auto cells = [](const std::string& row) { return std::count(row.begin(), row.end(), '|'); };
  const auto header = std::find_if(lines.begin(), lines.end(),
                                   [](const std::string& l) { return l.rfind("| video | method | posed |", 0) == 0; });
  ASSERT_NE(header, lines.end());
  const auto failed = std::find_if(header, lines.end(), [](const std::string& l) { return l.find("failed") != std::string::npos; });
  ASSERT_NE(failed, lines.end());
  EXPECT_EQ(cells(*failed), cells(*header)) << *failed;

  for (const auto& row : readResults(tmp.file("c/results.csv"))) {
    if (row.at("status") != "ok") continue;
    const nlohmann::json summary = nlohmann::json::parse(readFile(tmp.file("c/" + row.at("run") + "/summary.json")));
    ASSERT_TRUE(summary.contains("map")) << row.at("run");
    EXPECT_EQ(std::stod(row.at("map_median_m")), summary["map"]["median"].get<double>()) << row.at("run");
  }
}

// Option files (--config) are settings of the back-ends they have a section for: hybrid runs with
// its defaults (`defaults`) and with the file, labelled by its name, each run with exactly its
// options (summary.json), a sweep applies to each; cslam, which the file does not name, runs once.
// A file that cannot serve, or a value it sets that the back-end refuses, stops the compare before
// anything runs, naming the file and the field.
TEST(CompareExperiment, OptionFilesAreSettingsOfTheirBackEnds) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 12);
  const std::string file = tmp.file("precise.yaml");
  test::writeText(file, "%YAML:1.0\n---\nhybrid:\n  corners:\n    pixel_sigma: 0.02\n");
  CompareOptions options = shortCompare(seq, "cslam,hybrid", tmp.file("out"));
  options.configs = {"defaults", file};
  runCompare(options);
  const auto rows = readResults(tmp.file("out/results.csv"));
  ASSERT_EQ(rows.size(), 3u);
  std::map<std::string, std::string> config_of;  // run folder -> config column
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("status"), "ok") << row.at("run") << ": " << row.at("error");
    config_of[row.at("run")] = row.at("config");
  }
  ASSERT_EQ(config_of.count("runs/tv1-cslam"), 1u);
  ASSERT_EQ(config_of.count("runs/tv1-hybrid"), 1u);
  ASSERT_EQ(config_of.count("runs/tv1-hybrid-config=precise"), 1u);
  EXPECT_EQ(config_of["runs/tv1-cslam"], "");
  EXPECT_EQ(config_of["runs/tv1-hybrid"], "");
  EXPECT_EQ(config_of["runs/tv1-hybrid-config=precise"], fs::canonical(file).string());
  const auto pixel_sigma = [&](const std::string& run) {
    const nlohmann::json summary = nlohmann::json::parse(readFile(tmp.file("out/" + run + "/summary.json")));
    return summary.at("options").at("corners").at("pixel_sigma").get<double>();
  };
  EXPECT_EQ(pixel_sigma("runs/tv1-hybrid-config=precise"), 0.02);
  EXPECT_EQ(pixel_sigma("runs/tv1-hybrid"), 0.05);
  const std::string report = readFile(tmp.file("out/report.md"));
  EXPECT_NE(report.find("`hybrid config=precise`"), std::string::npos) << report;
  EXPECT_NE(report.find("Option files (`run --config`): `" + fs::canonical(file).string() + "`"),
            std::string::npos);

  // Without `defaults` the file replaces them; a sweep applies on top of it.
  CompareOptions swept = shortCompare(seq, "cslam,hybrid", tmp.file("plan"));
  swept.configs = {file};
  swept.sets = {"hybrid.corners.gate=0.999,0.9999"};
  ASSERT_EQ(planCompare(swept), 3u);
  const std::vector<std::string> jobs = test::readLines(tmp.file("plan/jobs.txt"));
  ASSERT_EQ(jobs.size(), 3u);
  EXPECT_EQ(jobs[0].find("--config"), std::string::npos) << jobs[0];
  for (int k : {1, 2}) {
    EXPECT_NE(jobs[k].find("--config " + fs::canonical(file).string() + " --set hybrid.corners.gate=0.999"),
              std::string::npos) << jobs[k];
    EXPECT_NE(jobs[k].find("runs/tv1-hybrid-config=precise-corners.gate=0.999"), std::string::npos) << jobs[k];
  }
  // The plan names the file apart from the swept values: a sweep's line is one back-end and file.
  const nlohmann::json plan = nlohmann::json::parse(readFile(tmp.file("plan/plan.json")));
  ASSERT_EQ(plan.at("methods").size(), 3u);
  EXPECT_EQ(plan["methods"][0].value("config", "?"), "");
  for (int k : {1, 2}) {
    EXPECT_EQ(plan["methods"][k].value("config", ""), "precise");
    EXPECT_EQ(plan["methods"][k].value("setting", "").rfind("corners.gate=0.999", 0), 0u) << plan["methods"][k];
  }

  const auto refused = [&](const std::vector<std::string>& configs, const std::string& methods,
                           const std::vector<std::string>& expected, const std::vector<std::string>& sets = {}) {
    CompareOptions bad = shortCompare(seq, methods, tmp.file("refused"));
    bad.configs = configs;
    bad.sets = sets;
    try {
      planCompare(bad);
      ADD_FAILURE() << "accepted " << configs.back();
    } catch (const InputError& e) {
      for (const std::string& text : expected) EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(tmp.file("refused")));  // refused before any folder is made
  };
  refused({file}, "cslam", {"--config " + file, "no section for a back-end among --backends"});
  refused({file, file}, "hybrid", {"--config " + file, "given twice"});
  refused({tmp.file("missing.yaml")}, "hybrid", {tmp.file("missing.yaml")});
  const std::string negative = tmp.file("negative.yaml");
  test::writeText(negative, "%YAML:1.0\n---\nhybrid:\n  corners:\n    pixel_sigma: -1\n");
  refused({negative}, "hybrid", {negative, "hybrid.corners.pixel_sigma"});
  // The same file through a link; two names that make the same folder name.
  fs::create_symlink(file, tmp.file("link.yaml"));
  refused({file, tmp.file("link.yaml")}, "hybrid", {"--config " + tmp.file("link.yaml"), "given twice"});
  test::writeText(tmp.file("a b.yaml"), "%YAML:1.0\n---\nhybrid:\n  corners:\n    gate: 0.999\n");
  test::writeText(tmp.file("a_b.yaml"), "%YAML:1.0\n---\nhybrid:\n  corners:\n    gate: 0.99\n");
  refused({tmp.file("a b.yaml"), tmp.file("a_b.yaml")}, "hybrid", {"would write the same run folders"});
  // A sweep is checked on top of each file it applies to: min_track_length may reach the file's
  // window (6), beyond the defaults' (4); a value the file's options refuse names the file.
  const std::string window = tmp.file("window.yaml");
  test::writeText(window, "%YAML:1.0\n---\nhybrid:\n  tracked_motion:\n    window: 6\n");
  CompareOptions long_tracks = shortCompare(seq, "hybrid", tmp.file("long"));
  long_tracks.configs = {window};
  long_tracks.sets = {"hybrid.tracked_motion.min_track_length=5,6"};
  EXPECT_EQ(planCompare(long_tracks), 2u);
  refused({"defaults", window}, "hybrid", {"--set hybrid.tracked_motion.min_track_length=5,6: value 5: "},
          {"hybrid.tracked_motion.min_track_length=5,6"});
  refused({window}, "hybrid", {"value 7 with --config " + fs::canonical(window).string()},
          {"hybrid.tracked_motion.min_track_length=5,7"});
  const std::string misspelt = tmp.file("misspelt.yaml");
  test::writeText(misspelt, "%YAML:1.0\n---\nhybird:\n  corners:\n    pixel_sigma: 0.1\n");
  refused({misspelt}, "hybrid", {misspelt, "hybird"});
}

// Bad usage of the plan options: one line naming what is wrong, exit 2, nothing written.
TEST(CompareExperiment, PlanAndCollectUsageErrors) {
  TempDir tmp;
  const auto no_plan = test::runSlamcmp("compare --collect " + tmp.path());
  EXPECT_EQ(no_plan.exit_code, 2);
  EXPECT_EQ(std::count(no_plan.err.begin(), no_plan.err.end(), '\n'), 1) << no_plan.err;
  EXPECT_NE(no_plan.err.find(tmp.file("plan.json")), std::string::npos) << no_plan.err;
  test::writeText(tmp.file("plan.json"), "{\"slamcmp_plan\": 1, \"sequences\": 3}");
  const auto bad_plan = test::runSlamcmp("compare --collect " + tmp.path());
  EXPECT_EQ(bad_plan.exit_code, 2) << bad_plan.err;
  EXPECT_NE(bad_plan.err.find("plan.json: malformed plan"), std::string::npos) << bad_plan.err;
  const auto both = test::runSlamcmp("compare --sequence " + tmp.path() + " --plan " + tmp.file("p") + " --out " +
                                     tmp.file("o"));
  EXPECT_EQ(both.exit_code, 2) << both.err;
  EXPECT_FALSE(fs::exists(tmp.file("p")));
  for (const char* option : {"--trials 5", "--backends cslam", "--max-frames 10", "--jobs 2",
                             "--set cslam.features.max_features=100,200", "--config defaults"}) {
    const auto ignored = test::runSlamcmp("compare --collect " + tmp.path() + " " + option);
    EXPECT_EQ(ignored.exit_code, 2) << option << ": " << ignored.err;
    EXPECT_EQ(std::count(ignored.err.begin(), ignored.err.end(), '\n'), 1) << ignored.err;
    const std::string name = std::string(option).substr(0, std::string(option).find(' '));
    EXPECT_NE(ignored.err.find("takes no " + name), std::string::npos) << ignored.err;
  }
  const auto trials = test::runSlamcmp("compare --sequence " + tmp.path() + " --trials 0 --out " + tmp.file("o"));
  EXPECT_EQ(trials.exit_code, 2) << trials.err;
  EXPECT_NE(trials.err.find("--trials"), std::string::npos) << trials.err;
}

// --plan writes a self-contained command a line and a Slurm array over them; the runs made from
// jobs.txt by a shell (or anything else) and collected give the tables a direct compare gives on
// the same run outputs, byte for byte; and a collect of a direct compare's folder rewrites its
// tables identically.
TEST(CompareExperiment, PlanThenCollectIsByteIdenticalToACompare) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string seq = renderTv1(tmp, 12);
  const CompareOptions direct = shortCompare(seq, "cslam,monoslam", tmp.file("direct"));
  runCompare(direct);
  const char* tables[] = {"report.md", "results.csv", "table_3_1.csv", "table_3_2.csv"};
  std::map<std::string, std::string> direct_tables;
  for (const char* t : tables) direct_tables[t] = readFile(tmp.file(std::string("direct/") + t));

  CompareOptions planned = direct;
  planned.out_dir = tmp.file("planned");
  EXPECT_EQ(planCompare(planned), 2u);
  const std::vector<std::string> jobs = test::readLines(tmp.file("planned/jobs.txt"));
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].rfind('/', 0), 0u) << jobs[0];  // absolute paths
  EXPECT_NE(jobs[0].find(" run --backend cslam --sequence " + fs::absolute(seq).string()), std::string::npos) << jobs[0];
  EXPECT_NE(jobs[0].find("--out " + fs::absolute(tmp.file("planned/runs/tv1-cslam")).string()), std::string::npos);
  const std::string sbatch = readFile(tmp.file("planned/slurm.sbatch"));
  EXPECT_NE(sbatch.find("#SBATCH --array=1-2\n"), std::string::npos) << sbatch;
  EXPECT_NE(sbatch.find("SLURM_ARRAY_TASK_ID"), std::string::npos) << sbatch;
  EXPECT_FALSE(fs::exists(tmp.file("planned/report.md")));  // nothing ran

  // Collected before any run finished: every run marked, nothing invented.
  const auto early = test::runSlamcmp("compare --collect " + tmp.file("planned"));
  EXPECT_EQ(early.exit_code, 0) << early.err;
  EXPECT_NE(early.err.find("warning: " + fs::absolute(tmp.file("planned/report.md")).lexically_normal().string() +
                           ": 2 run(s) not finished"),
            std::string::npos)
      << early.err;
  EXPECT_NE(readFile(tmp.file("planned/report.md")).find("`runs/tv1-monoslam`: not run"), std::string::npos);

  // The same run outputs (copied) give the same tables, byte for byte.
  fs::copy(tmp.file("direct/runs"), tmp.file("planned/runs"),
           fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  fs::copy(tmp.file("direct/logs"), tmp.file("planned/logs"),
           fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const auto collected = test::runSlamcmp("compare --collect " + tmp.file("planned"));
  ASSERT_EQ(collected.exit_code, 0) << collected.err;
  for (const char* t : tables) EXPECT_EQ(readFile(tmp.file(std::string("planned/") + t)), direct_tables[t]) << t;
  ASSERT_EQ(test::runSlamcmp("compare --collect " + tmp.file("direct")).exit_code, 0);
  for (const char* t : tables) EXPECT_EQ(readFile(tmp.file(std::string("direct/") + t)), direct_tables[t]) << t;

  // jobs.txt run by a shell, line by line: the runs' tracking is the same as compare's (only the
  // times differ), so the accuracy columns agree exactly.
  for (const std::string& line : jobs) ASSERT_EQ(std::system(line.c_str()), 0) << line;  // sh -c line
  ASSERT_EQ(test::runSlamcmp("compare --collect " + tmp.file("planned")).exit_code, 0);
  const auto a = readResults(tmp.file("direct/results.csv")), b = readResults(tmp.file("planned/results.csv"));
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k)
    for (const char* column : {"status", "tracked", "ate_trans_rmse_m", "rpe_trans_rmse_m", "drift_trans_percent"})
      EXPECT_EQ(a[k].at(column), b[k].at(column)) << column << " of " << a[k].at("run");
}

// GNU parallel, the documented way on one machine: `parallel < jobs.txt`, then --collect.
TEST(CompareExperiment, GnuParallelRunsThePlan) {
  if (std::system("parallel --version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "GNU parallel is not installed (apt-get install parallel): skipped";
  TempDir tmp;
  CompareOptions options = shortCompare(renderTv1(tmp, 12), "cslam,cslam:calibration,monoslam", tmp.file("plan"));
  options.trials = 2;
  ASSERT_EQ(planCompare(options), 6u);
  ASSERT_EQ(std::system(("parallel --will-cite -j 2 < " + tmp.file("plan/jobs.txt")).c_str()), 0);
  const auto collected = test::runSlamcmp("compare --collect " + tmp.file("plan"));
  ASSERT_EQ(collected.exit_code, 0) << collected.err;
  const auto rows = readResults(tmp.file("plan/results.csv"));
  ASSERT_EQ(rows.size(), 6u);
  for (const auto& row : rows) EXPECT_EQ(row.at("status"), "ok") << row.at("run") << ": " << row.at("error");
  EXPECT_EQ(readFile(tmp.file("plan/report.md")).find("## Runs not finished"), std::string::npos);
}

// SIGTERM to compare alone (a scheduler's signal, which the runs do not hear): the runs are stopped
// and whole, the report marks them, and compare exits 130.
TEST(CompareExperiment, InterruptedCompareMarksItsRunsAndFails) {
  const char* bin = std::getenv("SLAMCMP_BIN");
  ASSERT_NE(bin, nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  renderTv1(tmp, 40);
  // 2000 frames played from the 40 rendered: still running when the signal comes.
  const std::string seq = tmp.file("long");
  test::writeLoopedSequence(seq, "tv1", 40, 2000);
  // Its ground truth and scene, so that a finished run would have drift and map tables.
  fs::copy_file(tmp.file("tv1/scene.yaml"), seq + "/scene.yaml");
  const std::vector<std::string> truth = test::readLines(tmp.file("tv1/groundtruth.txt"));
  std::ostringstream looped_truth;
  for (int i = 0; i < 2000; ++i) {
    const std::string& line = truth.at(1 + i % 40);  // after the header
    looped_truth << 0.1 * i << line.substr(line.find(' ')) << "\n";
  }
  test::writeText(seq + "/groundtruth.txt", looped_truth.str());

  const std::string out = tmp.file("out");
  const pid_t pid = fork();
  if (pid == 0) {
    freopen(tmp.file("stderr").c_str(), "w", stderr);
    freopen(tmp.file("stdout").c_str(), "w", stdout);
    for (const int s : {SIGINT, SIGTERM, SIGHUP}) signal(s, SIG_DFL);
    execl(bin, bin, "compare", "--sequence", seq.c_str(), "--backends", "cslam,monoslam,hybrid", "--jobs", "2",
          "--out", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  ASSERT_GT(pid, 0);
  // Once both running runs have recorded frames.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  auto rows = [&](const std::string& run) { return test::readLines(out + "/runs/" + run + "/frames.csv").size(); };
  while ((rows("long-cslam") < 5 || rows("long-monoslam") < 5) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const std::string err = readFile(tmp.file("stderr"));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("interrupted"), std::string::npos) << err;
  const std::string report = readFile(out + "/report.md");
  EXPECT_NE(report.find("## Runs not finished"), std::string::npos) << report;
  EXPECT_NE(report.find("`runs/long-cslam`: interrupted: stopped after"), std::string::npos) << report;
  EXPECT_NE(report.find("`runs/long-hybrid`: not run"), std::string::npos) << report;
  for (const auto& row : readResults(out + "/results.csv")) EXPECT_NE(row.at("status"), "ok") << row.at("run");
  // No finished run: no drift or map table (they had their headers and no row).
  EXPECT_EQ(report.find("## Drift over path segments"), std::string::npos) << report;
  EXPECT_EQ(report.find("## Map accuracy"), std::string::npos) << report;
}

// A run whose program cannot be started fails with that said in its log, which the report quotes
// (its log was empty: "nothing in its log").
TEST(CompareExperiment, AProgramThatCannotStartIsSaid) {
  TempDir tmp;
  CompareOptions options = shortCompare(renderTv1(tmp, 4), "cslam", tmp.file("c"));
  options.slamcmp = tmp.file("no-such-slamcmp");
  runCompare(options);
  const auto rows = readResults(tmp.file("c/results.csv"));
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("status"), "failed");
  EXPECT_NE(rows[0].at("error").find("cannot execute " + tmp.file("no-such-slamcmp")), std::string::npos)
      << rows[0].at("error");
}

// A board-free run on tv1's first frames moves nearly along a line: its ATE rotation error after
// Sim(3) is not determined. results.csv says so and the report marks the cell; the board-started
// run, scored unaligned, has no mark.
TEST(CompareExperiment, AnUndeterminedRotationErrorIsMarked) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string report = readFile(runCompare(shortCompare(renderTv1(tmp, 12), "cslam,monoslam@none", tmp.file("c"))));
  std::map<std::string, std::string> undetermined;
  for (const auto& row : readResults(tmp.file("c/results.csv"))) undetermined[row.at("method")] = row.at("ate_rot_undetermined");
  EXPECT_EQ(undetermined["cslam"], "0");
  EXPECT_EQ(undetermined["monoslam@none"], "1");
  const auto row = [&](const std::string& method) {
    const size_t at = report.find("| tv1 | " + method + " | ");
    return at == std::string::npos ? std::string() : report.substr(at, report.find('\n', at) - at);
  };
  EXPECT_NE(row("monoslam@none").find(" † |"), std::string::npos) << report;
  EXPECT_EQ(row("cslam").find("†"), std::string::npos) << report;
  EXPECT_NE(report.find("† In a trial or more the matched positions lie nearly on one line"), std::string::npos);
}

}  // namespace
}  // namespace slamcmp
