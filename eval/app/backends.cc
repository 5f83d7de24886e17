#include "eval/app/backends.h"

#include "core/error.h"
#include "core/yaml.h"
#include "cslam/cslam_tracker.h"
#include "hybrid/hybrid_tracker.h"
#include "monoslam_ekf/monoslam_tracker.h"

namespace slamcmp {

const std::vector<BackendRegistration>& backends() {
  // Explicit, not self-registering objects: no static-initialisation order, and a linker cannot
  // drop an unreferenced registration from a static library.
  static const std::vector<BackendRegistration> all{cslamBackend(), monoslamBackend(), hybridBackend()};
  return all;
}

std::string backendNames(const std::string& separator) {
  std::string names;
  for (const auto& b : backends()) names += (names.empty() ? "" : separator) + b.name;
  return names;
}

const BackendRegistration& findBackend(const std::string& name, const std::string& where) {
  for (const auto& b : backends())
    if (b.name == name) return b;
  throw InputError(where, "unknown back-end '" + name + "' (known: " + backendNames(", ") + ")");
}

void requireTakesInit(const BackendRegistration& backend, const std::string& where) {
  if (!backend.takes_init)
    throw InputError(where, backend.name + " takes no --init (its world frame and start come from the board)");
}

const BackendMode& findMode(const BackendRegistration& backend, const std::string& mode, const std::string& where) {
  if (const BackendMode* m = backend.findMode(mode)) return *m;
  std::string known;
  for (const auto& m : backend.modes) known += (known.empty() ? "" : ", ") + m.name;
  throw InputError(where, backend.name + " has no mode '" + mode + "' (its modes: " + known + ")");
}

namespace {

// Every line of `text` prefixed with `pad`.
std::string indented(const std::string& text, const std::string& pad) {
  std::string out;
  for (size_t start = 0, end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    out += pad + text.substr(start, end - start + 1);
  return out;
}

}  // namespace

std::string backendsHelp() {
  std::string out = "Back-ends (--backend), their modes (--mode, the first is the default) and their options "
                    "(--config FILE: one section per back-end; --set SECTION.KEY=VALUE), with the defaults:\n";
  for (const BackendRegistration& b : backends()) {
    out += "\n" + b.name + ": " + b.summary + "\n  modes:";
    for (const BackendMode& m : b.modes) out += " " + m.name;
    out += b.takes_init ? "\n  takes --init\n" : "\n  takes no --init\n";
    out += indented(b.name + ":\n" + indented(b.default_options()->describe(), "  "), "  ");
  }
  return out;
}

std::unique_ptr<BackendOptions> loadBackendOptions(const BackendRegistration& backend, const std::string& config_path,
                                                   const std::vector<std::string>& sets, std::optional<int> seed,
                                                   cv::Size image_size) {
  std::unique_ptr<BackendOptions> options = backend.default_options();
  std::string where = backend.name;
  if (!config_path.empty()) {
    const YamlFile config(config_path);
    if (config.root().isMap())  // a file of only the %YAML header holds no section: the defaults
      for (const std::string& section : config.root().keys()) {
        // A misspelt section is not ignored.
        const BackendRegistration& other = findBackend(section, config_path + ": " + section);
        // Nor a typo in another back-end's section: the same file runs that back-end (compare) later.
        if (other.name == backend.name) continue;
        const std::unique_ptr<BackendOptions> other_options = other.default_options();
        other_options->read(config.node(section), config_path + ": " + section);
        other_options->check(config_path + ": " + section);
      }
    where = config_path + ": " + backend.name;
    options->read(config.node(backend.name), where);
  }
  if (seed && options->setSeeds(*seed) == 0)
    throw InputError("--seed", backend.name + " has no random seed (no option called seed)");
  for (const std::string& set : sets) {
    const auto eq = set.find('=');
    const auto dot = set.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq)
      throw InputError("--set " + set, "must be SECTION.KEY=VALUE, e.g. cslam.features.max_features=200");
    const std::string section = set.substr(0, dot);
    findBackend(section, "--set " + set);
    if (section != backend.name)
      throw InputError("--set " + set, "this run's back-end is " + backend.name + ", not " + section);
    options->set(set.substr(dot + 1, eq - dot - 1), set.substr(eq + 1), "--set " + backend.name);
  }
  options->check(where);
  if (!image_size.empty()) options->checkAgainstImage(image_size, where);
  return options;
}

}  // namespace slamcmp
