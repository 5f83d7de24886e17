#include "eval/report/results_table.h"

#include <charconv>
#include <cmath>
#include <fstream>

#include "core/error.h"

namespace slamcmp {

namespace {

double jsonNumber(const nlohmann::json& j, std::initializer_list<const char*> path) {
  const nlohmann::json* p = &j;
  for (const char* k : path) {
    if (!p->is_object() || !p->contains(k)) return NAN;
    p = &(*p)[k];
  }
  return p->is_number() ? p->get<double>() : NAN;
}

double errorOf(const RunResult& r, double RunErrors::*field) { return r.errors ? (*r.errors).*field : NAN; }

// Over summary.json's board_view gaps: the worst ratio to the allowance (max) or the frames lost
// (sum); NaN without a gap that has the number (a gap wholly lost has no ratio).
double overGaps(const RunResult& r, const char* key, bool sum) {
  const nlohmann::json* gaps = nullptr;
  if (r.summary.contains("board_view") && r.summary["board_view"].contains("gaps")) gaps = &r.summary["board_view"]["gaps"];
  if (!gaps || !gaps->is_array()) return NAN;
  double out = NAN;
  for (const nlohmann::json& g : *gaps) {
    const double v = jsonNumber(g, {key});
    if (std::isnan(v)) continue;
    out = std::isnan(out) ? v : sum ? out + v : std::max(out, v);
  }
  return out;
}


}  // namespace

std::string csvText(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

const std::vector<RunColumn>& runColumns() {
  static const std::vector<RunColumn> columns{
      {"frames", [](const RunResult& r) { return jsonNumber(r.summary, {"frames"}); }},
      {"tracked", [](const RunResult& r) { return jsonNumber(r.summary, {"tracked"}); }},
      {"posed_percent",
       [](const RunResult& r) { return 100.0 * jsonNumber(r.summary, {"tracked"}) / jsonNumber(r.summary, {"frames"}); }},
      {"scale", [](const RunResult& r) { return r.errors ? r.errors->T_gt_estimate.scale : NAN; }},
      {"ate_trans_rmse_m", [](const RunResult& r) { return errorOf(r, &RunErrors::ate_trans_rmse); }},
      {"ate_rot_rmse_deg", [](const RunResult& r) { return errorOf(r, &RunErrors::ate_rot_rmse_deg); }},
      // 1 where the matched positions lie nearly on a line: the rotation error is not determined.
      {"ate_rot_undetermined",
       [](const RunResult& r) { return r.errors ? (r.errors->ate_rot_warning.empty() ? 0.0 : 1.0) : NAN; }},
      {"rpe_trans_rmse_m", [](const RunResult& r) { return errorOf(r, &RunErrors::rpe_trans_rmse); }},
      {"rpe_rot_rmse_deg", [](const RunResult& r) { return errorOf(r, &RunErrors::rpe_rot_rmse_deg); }},
      {"drift_trans_percent",
       [](const RunResult& r) { return r.errors && r.errors->drift ? r.errors->drift->trans_percent : NAN; }},
      {"drift_rot_deg_per_m",
       [](const RunResult& r) { return r.errors && r.errors->drift ? r.errors->drift->rot_deg_per_m : NAN; }},
      {"ms_median", [](const RunResult& r) { return jsonNumber(r.summary, {"ms_per_frame", "median"}); }},
      {"cpu_ms_median", [](const RunResult& r) { return jsonNumber(r.summary, {"cpu_ms_per_frame", "median"}); }},
      {"cpu_ms_mean", [](const RunResult& r) { return jsonNumber(r.summary, {"cpu_ms_per_frame", "mean"}); }},
      {"map_points",
       [](const RunResult& r) { return r.map_errors ? static_cast<double>(r.map_errors->stats.distance.count) : NAN; }},
      {"map_median_m", [](const RunResult& r) { return r.map_errors ? r.map_errors->stats.distance.median : NAN; }},
      {"map_within_1cm", [](const RunResult& r) { return r.map_errors ? r.map_errors->stats.within_1cm : NAN; }},
      {"nees_mean", [](const RunResult& r) { return jsonNumber(r.summary, {"nees", "mean"}); }},
      {"nees_position_mean", [](const RunResult& r) { return jsonNumber(r.summary, {"nees", "position", "mean"}); }},
      {"nees_orientation_mean",
       [](const RunResult& r) { return jsonNumber(r.summary, {"nees", "orientation", "mean"}); }},
      {"gap_worst_over_allowance", [](const RunResult& r) { return overGaps(r, "worst_over_allowance", false); }},
      {"gap_lost", [](const RunResult& r) { return overGaps(r, "lost", true); }},
      {"after_return_over_settled",
       [](const RunResult& r) { return jsonNumber(r.summary, {"board_view", "after_return_over_settled"}); }},
      {"partial_over_whole", [](const RunResult& r) { return jsonNumber(r.summary, {"board_view", "partial_over_whole"}); }},
  };
  return columns;
}

double runValue(const RunResult& r, const std::string& column) {
  if (!r.finished()) return NAN;
  for (const RunColumn& c : runColumns())
    if (column == c.name) return c.value(r);
  throw std::logic_error("no results column " + column);
}

std::string exactNumber(double v) {
  if (!std::isfinite(v)) return "";
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::string(buf, end);
}

void writeResultsCsv(const Plan& plan, const std::vector<RunResult>& runs, const std::string& path) {
  std::ofstream out(path);
  out << "sequence,method,trial,seed_kind,seed";
  if (!plan.configs.empty()) out << ",config";
  for (const std::string& key : plan.swept_keys) out << "," << csvText(key);
  out << ",status,first_lost_frame,align";
  for (const RunColumn& c : runColumns()) out << "," << c.name;
  out << ",run,error\n";
  for (size_t k = 0; k < runs.size(); ++k) {
    const PlannedRun& p = plan.runs[k];
    const RunResult& r = runs[k];
    out << csvText(plan.sequence_names[p.sequence]) << "," << csvText(plan.methods[p.method].base()) << "," << p.trial
        << "," << p.seed_kind << "," << (p.seed ? std::to_string(*p.seed) : "");
    if (!plan.configs.empty()) out << "," << csvText(p.config);
    for (const std::string& key : plan.swept_keys) out << "," << csvText(sweptValue(p, key));
    const nlohmann::json* first_lost = r.summary.is_object() && r.summary.contains("first_lost_frame")
                                           ? &r.summary["first_lost_frame"]
                                           : nullptr;
    out << "," << r.status << "," << (r.finished() && first_lost && first_lost->is_number() ? first_lost->dump() : "")
        << "," << (r.finished() && r.errors ? r.errors->align : "");
    for (const RunColumn& c : runColumns()) out << "," << exactNumber(runValue(r, c.name));
    out << "," << csvText(p.dir) << "," << csvText(r.error) << "\n";
  }
  if (!out) throw InputError(path, "cannot be written");
}

}  // namespace slamcmp
