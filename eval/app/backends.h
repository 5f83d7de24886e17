#pragma once
// The registered back-ends (core/backend_registry.h): the one list that names them.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/backend_registry.h"

namespace slamcmp {

// Every back-end built in, in the order tables and figures show them.
const std::vector<BackendRegistration>& backends();

// The back-end called `name`; throws InputError(where, ...) listing the known names.
const BackendRegistration& findBackend(const std::string& name, const std::string& where = "--backend");

// "a|b|c" of the registered names, for help texts.
std::string backendNames(const std::string& separator = "|");

// The back-end's mode: `mode` ("" = its default); throws InputError(where, ...) listing its modes.
const BackendMode& findMode(const BackendRegistration& backend, const std::string& mode,
                            const std::string& where = "--mode");

// Throws InputError(where, ...) unless the back-end takes --init (a start other than the board).
void requireTakesInit(const BackendRegistration& backend, const std::string& where = "--init");

// A --set's "SECTION.KEY=VALUE": the back-end SECTION names, the option's KEY (a path: a.b.c) and
// VALUE as written; InputError("--set " + text, ...) unless it has that form (`form`: how the
// message spells it, with an example) and SECTION is a back-end.
struct OptionSetting {
  const BackendRegistration* backend;
  std::string key, value;
};
OptionSetting parseOptionSetting(const std::string& text, const std::string& form);

// The back-ends an option file (`path`, read as `config`) has sections for, in its order; a section
// naming no back-end is an InputError naming the file and the section. A file of only the %YAML
// header has none.
class YamlFile;
std::vector<const BackendRegistration*> configBackends(const YamlFile& config, const std::string& path);

// Every back-end with its modes and its options with their defaults, as commented YAML (run --help).
std::string backendsHelp();

// The back-end's options: defaults, then its section of the YAML file `config_path` ("" = none),
// then every random seed set to `seed` when given (run --seed), then each `--set section.key=value`
// naming this back-end, checked, and when `image_size` is given (the sequence's, known once its
// first frame is read) checked against it too. A top-level section of the file that names no
// back-end, an option another back-end's section gives that back-end does not take (or a value it
// refuses), a --set for another back-end, or a seed for a back-end without one is an InputError.
std::unique_ptr<BackendOptions> loadBackendOptions(const BackendRegistration& backend, const std::string& config_path,
                                                   const std::vector<std::string>& sets,
                                                   std::optional<int> seed = std::nullopt,
                                                   cv::Size image_size = cv::Size());

}  // namespace slamcmp
