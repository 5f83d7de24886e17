#include "eval/app/job_runner.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/progress.h"
#include "eval/app/compare_plan.h"
#include "eval/app/run_sequence.h"

namespace slamcmp {

namespace {

// Starts the run with its log as stdout and stderr. Everything the child needs is made before fork:
// between fork and exec only async-signal-safe calls.
pid_t startRun(const PlannedRun& run, const std::string& dir) {
  const std::string log = (std::filesystem::path(dir) / run.log).string();
  const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(log, "cannot be written");
  std::vector<char*> argv;
  for (const std::string& a : run.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // What the log says if the program cannot be started (collect quotes a log's last line).
  const std::string cannot_start = "slamcmp: cannot execute " + run.argv.front() + "\n";
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    execv(argv[0], argv.data());
    if (write(STDERR_FILENO, cannot_start.data(), cannot_start.size()) < 0) _exit(127);
    _exit(127);
  }
  close(fd);
  if (pid < 0) throw std::runtime_error("cannot start a run (fork failed)");
  return pid;
}

// A run ended by a signal says so in its log, whose last line collect reads: stopped by compare
// itself, or a crash ("slamcmp: ...", a failed run's form).
void noteSignal(const PlannedRun& run, const std::string& dir, int signal, bool stopping) {
  std::ofstream log(std::filesystem::path(dir) / run.log, std::ios::app);
  const std::string name = strsignal(signal) ? strsignal(signal) : "unknown";
  if (stopping)
    log << "\n" << kStoppedByCompare << " this run (signal " << signal << ", " << name
        << ") before it wrote its outputs\n";
  else
    log << "\n" << kEndedOnSignal << signal << " (" << name << ")\n";
}

}  // namespace

bool runPlannedJobs(const Plan& plan, const std::string& dir, int jobs) {
  struct Running {
    pid_t pid;
    size_t run;
  };
  std::vector<Running> running;
  size_t next = 0, done = 0;
  bool stopping = false;
  Progress progress("compare", static_cast<int>(plan.runs.size()));
  while (true) {
    try {
      while (!interrupted() && next < plan.runs.size() && static_cast<int>(running.size()) < std::max(1, jobs))
        running.push_back({startRun(plan.runs[next], dir), next}), ++next;
    } catch (...) {
      // A run that cannot start stops the compare: the runs started stop too, before it reports.
      for (const Running& r : running) kill(r.pid, SIGTERM);
      for (const Running& r : running) waitpid(r.pid, nullptr, 0);
      throw;
    }
    if (running.empty()) break;
    if (interrupted() && !stopping) {
      // A terminal's Ctrl-C reaches the runs too; a SIGTERM or SIGHUP sent to compare alone does not.
      for (const Running& r : running) kill(r.pid, SIGTERM);
      stopping = true;
    }
    for (size_t k = 0; k < running.size();) {
      int status = 0;
      if (waitpid(running[k].pid, &status, WNOHANG) == running[k].pid) {
        if (WIFSIGNALED(status)) noteSignal(plan.runs[running[k].run], dir, WTERMSIG(status), stopping);
        running.erase(running.begin() + static_cast<long>(k));
        ++done;
      } else {
        ++k;
      }
    }
    progress.update(static_cast<int>(done), std::to_string(running.size()) + " running");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  progress.finish();
  return !interrupted();
}

}  // namespace slamcmp
