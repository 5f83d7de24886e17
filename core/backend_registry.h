#pragma once
// How a back-end describes itself (SPEC section 1): its name, its modes (with their display names
// and figure colours), its options type and a factory given options already parsed. Each back-end
// folder defines one function returning its BackendRegistration; the application's list
// (eval/app/backends.cc) is the one line that names them, and the command line, compare,
// reproduce, the benchmarks and the figures enumerate it.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/options.h"
#include "core/tracker.h"

namespace slamcmp {

struct BackendMode {
  std::string name;     // the --mode value
  std::string display;  // in tables and figure keys
  std::string colour;   // figure colour, "#rrggbb"
  std::string thesis_method = "";  // the thesis's Table 3.2 column it stands beside ("" = none)
};

// A back-end's options behind one type-erased face, so the application can read, override,
// check and print them without knowing their type.
class BackendOptions {
 public:
  virtual ~BackendOptions() = default;
  virtual std::unique_ptr<BackendOptions> clone() const = 0;
  // The back-end's section of a YAML file; `where` names it ("run.yaml: cslam").
  virtual void read(const cv::FileNode& section, const std::string& where) = 0;
  // One `--set` override: path as in the YAML ("features.max_features").
  virtual void set(const std::string& path, const std::string& value, const std::string& where) = 0;
  virtual void check(const std::string& where) const = 0;  // InputError naming where.field
  // Every random seed (the options called "seed") set to `seed`; returns how many were set.
  virtual int setSeeds(int seed) = 0;
  // The bounds that need the image size (core/options.h, checkImage), once it is known.
  virtual void checkAgainstImage(cv::Size image, const std::string& where) const = 0;
  virtual nlohmann::json toJson() const = 0;
  virtual std::string describe() const = 0;  // commented YAML with the defaults
};

template <class Options>
class TypedBackendOptions : public BackendOptions {
 public:
  Options value;

  std::unique_ptr<BackendOptions> clone() const override {
    return std::make_unique<TypedBackendOptions>(*this);
  }
  void read(const cv::FileNode& section, const std::string& where) override {
    readOptions(section, where, value);
  }
  void set(const std::string& path, const std::string& text, const std::string& where) override {
    setOption(path, text, where, value);
  }
  void check(const std::string& where) const override { checkOptions(value, where); }
  int setSeeds(int seed) override { return slamcmp::setSeeds(seed, value); }
  void checkAgainstImage(cv::Size image, const std::string& where) const override {
    checkOptionsAgainstImage(value, image, where);
  }
  nlohmann::json toJson() const override { return optionsToJson(value); }
  std::string describe() const override { return describeOptions(value); }
};

struct BackendRegistration {
  std::string name;
  std::string summary;             // one line for --help
  std::vector<BackendMode> modes;  // the first is the default
  bool takes_init = false;         // accepts --init (board | groundtruth | manual:FILE | none)
  // The stage names its frames' CPU times use (summary.json `stages`), in the order a frame runs them.
  std::vector<std::string> stages;
  // Stages timed only with some options or starts, not in every run (monoslam's two_view).
  std::vector<std::string> optional_stages;
  std::function<std::unique_ptr<BackendOptions>()> default_options;
  // context.mode is one of `modes`; options are checked. Throws InputError for a context the
  // back-end cannot work with (no camera, no target, ...).
  std::function<std::unique_ptr<Tracker>(const TrackerContext&, const BackendOptions&)> make;

  // The mode called `mode` ("" = the default), or nullptr.
  const BackendMode* findMode(const std::string& mode) const {
    if (mode.empty()) return &modes.front();
    for (const BackendMode& m : modes)
      if (m.name == mode) return &m;
    return nullptr;
  }
};

// A registration for a back-end whose options are `Options` (a visit()-able struct) and whose
// factory is make(const TrackerContext&, const Options&).
template <class Options, class Make>
BackendRegistration makeRegistration(std::string name, std::string summary, std::vector<BackendMode> modes,
                                     bool takes_init, Make make) {
  BackendRegistration r;
  r.name = std::move(name);
  r.summary = std::move(summary);
  r.modes = std::move(modes);
  r.takes_init = takes_init;
  r.default_options = [] { return std::make_unique<TypedBackendOptions<Options>>(); };
  r.make = [make](const TrackerContext& context, const BackendOptions& options) -> std::unique_ptr<Tracker> {
    return make(context, dynamic_cast<const TypedBackendOptions<Options>&>(options).value);
  };
  return r;
}

}  // namespace slamcmp
