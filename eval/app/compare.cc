#include "eval/app/compare.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <thread>

#include <opencv2/core/utility.hpp>

#include "core/error.h"
#include "core/progress.h"
#include "eval/app/backends.h"
#include "eval/app/run_sequence.h"

namespace fs = std::filesystem;

namespace slamcmp {

Method methodOf(const std::string& backend_name, const std::string& mode, const std::string& where) {
  const BackendRegistration& backend = findBackend(backend_name, where);
  const BackendMode& m = findMode(backend, mode, where);
  Method method;
  method.backend = backend.name;
  method.mode = &m == &backend.modes.front() ? "" : m.name;  // the default mode keeps the short label
  method.colour = m.colour;
  method.thesis_method = m.thesis_method;
  return method;
}

std::vector<Method> allMethods() {
  std::vector<Method> methods;
  for (const BackendRegistration& b : backends())
    for (const BackendMode& m : b.modes) methods.push_back(methodOf(b.name, m.name, b.name));
  return methods;
}

std::vector<Method> parseMethods(const std::string& list) {
  std::vector<Method> methods;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    const auto colon = item.find(':');
    const std::string mode = colon == std::string::npos ? "" : item.substr(colon + 1);
    if (colon != std::string::npos && mode.empty()) throw InputError("--backends " + item, "names no mode");
    Method m = methodOf(item.substr(0, colon), mode, "--backends " + item);
    for (const Method& other : methods)
      if (other.label() == m.label())  // both runs would write into one folder
        throw InputError("--backends", "'" + item + "' is listed twice (as " + m.label() + ")");
    methods.push_back(m);
  }
  if (methods.empty()) throw InputError("--backends", "names no back-end");
  return methods;
}

namespace {

void runAll(const CompareOptions& options, const std::vector<SequenceInfo>& seqs,
            std::vector<std::vector<RunResult>>* results) {
  struct Job {
    size_t seq, method;
  };
  std::vector<Job> jobs;
  long total_frames = 0;
  for (size_t s = 0; s < seqs.size(); ++s)
    for (size_t m = 0; m < options.methods.size(); ++m) {
      jobs.push_back({s, m});
      total_frames += options.max_frames >= 0 ? std::min(options.max_frames, seqs[s].frames) : seqs[s].frames;
    }
  results->assign(seqs.size(), std::vector<RunResult>(options.methods.size()));

  // Each run on one core: runs at once take the cores, and ms per frame mean one core.
  cv::setNumThreads(1);
  std::atomic<size_t> next{0};
  std::atomic<long> frames_done{0};
  std::atomic<int> workers_left{std::max(1, std::min<int>(options.jobs, static_cast<int>(jobs.size())))};
  std::mutex mutex;
  auto worker = [&] {
    for (size_t j; (j = next++) < jobs.size();) {
      const SequenceInfo& seq = seqs[jobs[j].seq];
      const Method& method = options.methods[jobs[j].method];
      RunRequest req;
      req.backend = method.backend;
      req.mode = method.mode;
      req.sequence_path = seq.path;
      req.out_dir = options.out_dir + "/runs/" + seq.name + "-" + method.slug();
      req.max_frames = options.max_frames;
      req.progress = false;
      req.on_frame = [&] { ++frames_done; };
      RunResult r;
      try {
        runSequence(req);
        r = loadRun(method, req.out_dir, seq);
      } catch (const std::exception& e) {
        r.method = method;
        r.dir = req.out_dir;
        r.error = e.what();
      }
      std::lock_guard<std::mutex> lock(mutex);
      (*results)[jobs[j].seq][jobs[j].method] = std::move(r);
    }
    --workers_left;
  };
  std::vector<std::thread> threads;
  const int n_workers = workers_left;
  for (int i = 0; i < n_workers; ++i) threads.emplace_back(worker);
  Progress progress("compare", static_cast<int>(total_frames));
  while (workers_left > 0 && !interrupted()) {
    progress.update(static_cast<int>(frames_done), std::to_string(std::min(next.load(), jobs.size())) + "/" +
                                                        std::to_string(jobs.size()) + " runs");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (auto& t : threads) t.join();
  progress.finish();
  cv::setNumThreads(-1);
}

}  // namespace

std::string runCompare(const CompareOptions& options) {
  if (options.sequences.empty()) throw InputError("--sequence", "give at least one sequence");
  if (options.max_frames == 0) throw InputError("--max-frames 0", "nothing to run");
  std::vector<SequenceInfo> seqs;
  for (const auto& path : options.sequences) {
    SequenceInfo info = readSequenceInfo(path);
    for (const auto& other : seqs)
      if (other.name == info.name) throw InputError(path, "two sequences are named '" + info.name + "'");
    seqs.push_back(std::move(info));
  }
  std::error_code ec;
  fs::create_directories(options.out_dir + "/figures", ec);
  if (ec) throw InputError(options.out_dir, "output folder cannot be created: " + ec.message());

  std::vector<std::vector<RunResult>> results;
  runAll(options, seqs, &results);

  std::ostringstream preamble;
  preamble << "Methods: ";
  for (size_t m = 0; m < options.methods.size(); ++m)
    preamble << (m ? ", " : "") << "`" << options.methods[m].label() << "`";
  preamble << ". Each run on one core (" << std::max(1, options.jobs) << " runs at once on "
           << std::thread::hardware_concurrency() << " cores); ms per frame exclude image decoding.";
  return writeCompareReport(seqs, options.methods, results, options.max_frames, preamble.str(), options.out_dir);
}

}  // namespace slamcmp
