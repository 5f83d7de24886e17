#include "eval/report/experiment_plan.h"

#include <cstdint>
#include <cstdio>

#include "core/error.h"

namespace slamcmp {

std::string Method::slug() const {
  std::string s = mode.empty() ? backend : backend + "-" + mode;
  if (!init.empty()) s += "-init-" + init;
  if (!config.empty()) s += "-config=" + config;
  if (!setting.empty()) s += "-" + setting;
  for (char& c : s)
    if (c == ' ' || c == '/' || c == ':') c = '_';  // a folder name
  // A file name holds 255 bytes, and the run's log adds the sequence and trial: a setting of many
  // options is cut and told apart from the others by a hash of the whole (FNV-1a, 64 bits).
  constexpr size_t kMaxSlug = 120;
  if (s.size() <= kMaxSlug) return s;
  std::uint64_t hash = 14695981039346656037ull;
  for (const unsigned char c : s) hash = (hash ^ c) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  return s.substr(0, kMaxSlug - 17) + "-" + hex;
}

std::string sweptValue(const PlannedRun& run, const std::string& key) {
  for (const std::string& set : run.sets)
    if (set.size() > key.size() && set.compare(0, key.size(), key) == 0 && set[key.size()] == '=')
      return set.substr(key.size() + 1);
  return "";
}

nlohmann::json planToJson(const Plan& plan) {
  nlohmann::json methods = nlohmann::json::array(), runs = nlohmann::json::array();
  for (const Method& m : plan.methods)
    methods.push_back({{"backend", m.backend},
                       {"mode", m.mode},
                       {"colour", m.colour},
                       {"thesis_method", m.thesis_method},
                       {"setting", m.setting},
                       {"config", m.config},
                       {"init", m.init}});
  for (const PlannedRun& r : plan.runs) {
    nlohmann::json j = {{"sequence", r.sequence}, {"method", r.method},  {"trial", r.trial},
                        {"seed_kind", r.seed_kind}, {"sequence_path", r.sequence_path},
                        {"dir", r.dir},           {"log", r.log},       {"sets", r.sets},
                        {"config", r.config},     {"argv", r.argv}};
    j["seed"] = r.seed ? nlohmann::json(*r.seed) : nlohmann::json();
    runs.push_back(j);
  }
  return {{"slamcmp_plan", 1},
          {"sequences", plan.sequences},
          {"sequence_names", plan.sequence_names},
          {"methods", methods},
          {"swept_keys", plan.swept_keys},
          {"configs", plan.configs},
          {"trials", plan.trials},
          {"max_frames", plan.max_frames},
          {"dir", plan.dir},
          {"runs", runs}};
}

Plan planFromJson(const nlohmann::json& j, const std::string& where) {
  Plan plan;
  try {
    if (j.value("slamcmp_plan", 0) != 1) throw InputError(where, "not a slamcmp plan (no slamcmp_plan: 1)");
    plan.sequences = j.at("sequences").get<std::vector<std::string>>();
    plan.sequence_names = j.at("sequence_names").get<std::vector<std::string>>();
    for (const auto& m : j.at("methods")) {
      Method method;
      method.backend = m.at("backend").get<std::string>();
      method.mode = m.at("mode").get<std::string>();
      method.colour = m.at("colour").get<std::string>();
      method.thesis_method = m.at("thesis_method").get<std::string>();
      method.setting = m.at("setting").get<std::string>();
      method.config = m.value("config", "");  // plans written before --config
      method.init = m.value("init", "");
      plan.methods.push_back(method);
    }
    plan.swept_keys = j.at("swept_keys").get<std::vector<std::string>>();
    plan.configs = j.value("configs", std::vector<std::string>{});  // plans written before --config
    plan.trials = j.at("trials").get<int>();
    plan.max_frames = j.at("max_frames").get<int>();
    plan.dir = j.value("dir", "");  // plans written before it
    for (const auto& r : j.at("runs")) {
      PlannedRun run;
      run.sequence = r.at("sequence").get<size_t>();
      run.method = r.at("method").get<size_t>();
      run.trial = r.at("trial").get<int>();
      run.seed_kind = r.at("seed_kind").get<std::string>();
      if (!r.at("seed").is_null()) run.seed = r.at("seed").get<int>();
      run.sequence_path = r.at("sequence_path").get<std::string>();
      run.dir = r.at("dir").get<std::string>();
      run.log = r.at("log").get<std::string>();
      run.sets = r.at("sets").get<std::vector<std::string>>();
      run.config = r.value("config", "");
      run.argv = r.at("argv").get<std::vector<std::string>>();
      if (run.sequence >= plan.sequences.size() || run.method >= plan.methods.size())
        throw InputError(where, "runs: a run names a sequence or method the plan does not list");
      plan.runs.push_back(run);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where, std::string("malformed plan: ") + e.what());
  }
  if (plan.sequences.size() != plan.sequence_names.size() || plan.trials < 1)
    throw InputError(where, "malformed plan: sequences and sequence_names differ in length, or trials < 1");
  return plan;
}

}  // namespace slamcmp
