// slurm.sbatch run as Slurm runs an array task: bash with SLURM_ARRAY_TASK_ID set. Every line of
// jobs.txt runs once over the array's tasks, a task reruns its own lines alone, and a task fails
// when one of its lines does.
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
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
Plan markerPlan(const std::string& dir, int n, int array_tasks = 1000, const std::vector<int>& failing = {}) {
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
  writePlanFiles(plan, dir, array_tasks);
  return plan;
}

// Runs array task `id` as Slurm does (bash, SLURM_ARRAY_TASK_ID set; none: a run by hand); its
// exit status.
int runTask(const std::string& dir, std::optional<int> id) {
  const std::string command = (id ? "SLURM_ARRAY_TASK_ID=" + std::to_string(*id) + " " : std::string("")) + "bash '" +
                              dir + "/slurm.sbatch' > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// How many times each run appended itself.
std::map<int, int> timesRun(const std::string& dir) {
  std::map<int, int> times;
  if (!fs::exists(dir + "/ran.txt")) return times;
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
  markerPlan(tmp.file("capped"), 7, 3);
  EXPECT_EQ(arrayDirective(tmp.file("capped")), "#SBATCH --array=1-3");
}

TEST(SlurmScript, EveryLineRunsOnceOverTheArraysTasks) {
  for (const int array_tasks : {1, 3, 7, 10}) {
    TempDir tmp;
    const std::string dir = tmp.file("plan");
    markerPlan(dir, 7, array_tasks);
    for (int id = 1; id <= std::min(array_tasks, 7); ++id) EXPECT_EQ(runTask(dir, id), 0) << id;
    std::map<int, int> expected;
    for (int k = 1; k <= 7; ++k) expected[k] = 1;
    EXPECT_EQ(timesRun(dir), expected) << array_tasks << " tasks";
  }
}

// A task's id names the same lines however it is submitted: `sbatch --array=2` reruns task 2's
// runs alone; by hand (no Slurm) the script runs task 1's.
TEST(SlurmScript, ATaskRerunRunsItsOwnLinesOnly) {
  TempDir tmp;
  const std::string dir = tmp.file("plan");
  markerPlan(dir, 7, 3);
  EXPECT_EQ(runTask(dir, 2), 0);
  EXPECT_EQ(timesRun(dir), (std::map<int, int>{{2, 1}, {5, 1}}));
  EXPECT_EQ(runTask(dir, std::nullopt), 0);
  EXPECT_EQ(timesRun(dir), (std::map<int, int>{{1, 1}, {2, 1}, {4, 1}, {5, 1}, {7, 1}}));
}

TEST(SlurmScript, ATaskFailsWhenOneOfItsRunsFailsAndStillRunsTheOthers) {
  TempDir tmp;
  const std::string dir = tmp.file("plan");
  markerPlan(dir, 6, 2, {3});
  EXPECT_NE(runTask(dir, 1), 0);  // lines 1, 3, 5
  EXPECT_EQ(runTask(dir, 2), 0);  // lines 2, 4, 6
  EXPECT_EQ(timesRun(dir).size(), 6u);
}

}  // namespace
}  // namespace slamcmp
