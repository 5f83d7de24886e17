// slurm.sbatch run as Slurm runs an array task: bash with the array's variables set. Every line
// of jobs.txt runs once whatever the array's size, and a task fails when one of its lines does.
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "eval/app/compare_plan.h"
#include "tests/test_util.h"

namespace fs = std::filesystem;

namespace slamcmp {
namespace {

using test::TempDir;

// A plan of `n` runs, run k appending k to ran.txt; the runs in `failing` exit 3.
Plan markerPlan(const std::string& dir, int n, const std::vector<int>& failing = {}) {
  Plan plan;
  for (int k = 1; k <= n; ++k) {
    PlannedRun run;
    run.dir = "runs/" + std::to_string(k);
    run.log = "logs/" + std::to_string(k) + ".log";
    const bool fails = std::find(failing.begin(), failing.end(), k) != failing.end();
    run.argv = {"/bin/sh", "-c",
                "echo " + std::to_string(k) + " >> '" + dir + "/ran.txt'" + (fails ? "; exit 3" : "")};
    plan.runs.push_back(run);
  }
  fs::create_directories(fs::path(dir) / "logs");
  writePlanFiles(plan, dir);
  return plan;
}

// Runs task `id` of an array with the given variables; returns its exit status.
int runTask(const std::string& dir, int id, int count, int min = 1, int step = 1) {
  const std::string command = "SLURM_ARRAY_TASK_ID=" + std::to_string(id) + " SLURM_ARRAY_TASK_COUNT=" +
                              std::to_string(count) + " SLURM_ARRAY_TASK_MIN=" + std::to_string(min) +
                              " SLURM_ARRAY_TASK_STEP=" + std::to_string(step) + " bash '" + dir +
                              "/slurm.sbatch' > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// How many times each run appended itself.
std::map<int, int> timesRun(const std::string& dir) {
  std::map<int, int> times;
  for (const std::string& line : test::readLines(dir + "/ran.txt")) ++times[std::stoi(line)];
  return times;
}

std::string arrayDirective(const std::string& dir) {
  std::ifstream in(dir + "/slurm.sbatch");
  std::stringstream text;
  text << in.rdbuf();
  const std::string sbatch = text.str();
  const size_t at = sbatch.find("#SBATCH --array=");
  return at == std::string::npos ? "" : sbatch.substr(at, sbatch.find('\n', at) - at);
}

TEST(SlurmScript, ArrayAsLargeAsThePlanUpToSlurmsDefaultMaxArraySize) {
  TempDir tmp;
  markerPlan(tmp.file("small"), 7);
  EXPECT_EQ(arrayDirective(tmp.file("small")), "#SBATCH --array=1-7");
  markerPlan(tmp.file("large"), 1001);
  EXPECT_EQ(arrayDirective(tmp.file("large")), "#SBATCH --array=1-1000");
}

TEST(SlurmScript, EveryLineRunsOnceWhateverTheArraysSize) {
  for (const int tasks : {1, 3, 7, 10}) {
    TempDir tmp;
    const std::string dir = tmp.file("plan");
    markerPlan(dir, 7);
    for (int id = 1; id <= tasks; ++id) EXPECT_EQ(runTask(dir, id, tasks), 0) << id << " of " << tasks;
    std::map<int, int> expected;
    for (int k = 1; k <= 7; ++k) expected[k] = 1;
    EXPECT_EQ(timesRun(dir), expected) << tasks << " tasks";
  }
}

TEST(SlurmScript, AnArrayNotStartingAtOneOrWithAStepCoversThePlan) {
  TempDir tmp;
  const std::string dir = tmp.file("plan");
  markerPlan(dir, 5);
  for (const int id : {10, 12, 14}) EXPECT_EQ(runTask(dir, id, 3, 10, 2), 0);  // --array=10-14:2
  EXPECT_EQ(timesRun(dir), (std::map<int, int>{{1, 1}, {2, 1}, {3, 1}, {4, 1}, {5, 1}}));
}

TEST(SlurmScript, ATaskFailsWhenOneOfItsRunsFailsAndStillRunsTheOthers) {
  TempDir tmp;
  const std::string dir = tmp.file("plan");
  markerPlan(dir, 6, {3});
  EXPECT_NE(runTask(dir, 1, 2), 0);  // lines 1, 3, 5
  EXPECT_EQ(runTask(dir, 2, 2), 0);  // lines 2, 4, 6
  EXPECT_EQ(timesRun(dir).size(), 6u);
}

}  // namespace
}  // namespace slamcmp
