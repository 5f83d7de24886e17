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

OptionSetting parseOptionSetting(const std::string& text, const std::string& form) {
  const auto eq = text.find('=');
  const auto dot = text.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq)
    throw InputError("--set " + text, "must be " + form);
  return {&findBackend(text.substr(0, dot), "--set " + text), text.substr(dot + 1, eq - dot - 1), text.substr(eq + 1)};
}

std::vector<const BackendRegistration*> configBackends(const YamlFile& config, const std::string& path) {
  std::vector<const BackendRegistration*> named;
  if (config.root().isMap())
    for (const std::string& section : config.root().keys()) named.push_back(&findBackend(section, path + ": " + section));
  return named;
}

std::unique_ptr<BackendOptions> loadBackendOptions(const BackendRegistration& backend, const std::string& config_path,
                                                   const std::vector<std::string>& sets, std::optional<int> seed,
                                                   cv::Size image_size) {
  std::unique_ptr<BackendOptions> options = backend.default_options();
  std::string where = backend.name;
  if (!config_path.empty()) {
    const YamlFile config(config_path);
    for (const BackendRegistration* other : configBackends(config, config_path)) {  // a misspelt section refused
      // Nor a typo in another back-end's section: the same file runs that back-end (compare) later.
      if (other->name == backend.name) continue;
      const std::unique_ptr<BackendOptions> other_options = other->default_options();
      other_options->read(config.node(other->name), config_path + ": " + other->name);
      other_options->check(config_path + ": " + other->name);
    }
    where = config_path + ": " + backend.name;
    options->read(config.node(backend.name), where);
  }
  if (seed && options->setSeeds(*seed) == 0)
    throw InputError("--seed", backend.name + " has no random seed (no option called seed)");
  for (const std::string& set : sets) {
    const OptionSetting setting = parseOptionSetting(set, "SECTION.KEY=VALUE, e.g. cslam.features.max_features=200");
    if (setting.backend->name != backend.name)
      throw InputError("--set " + set, "this run's back-end is " + backend.name + ", not " + setting.backend->name);
    options->set(setting.key, setting.value, "--set " + backend.name);
  }
  options->check(where);
  if (!image_size.empty()) options->checkAgainstImage(image_size, where);
  return options;
}

}  // namespace slamcmp
