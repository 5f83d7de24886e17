#include "eval/report/experiment_figures.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <sstream>

#include "core/statistics.h"
#include "eval/report/plot.h"
#include "eval/report/results_table.h"

namespace slamcmp {

namespace {

// The finished trials' values of a column, for sequence s and method m.
std::vector<double> trialValues(const Plan& plan, const std::vector<RunResult>& runs, size_t s, size_t m,
                                const std::string& column) {
  return cellValues(cellRuns(plan, runs, s, m), column);
}

double meanOf(const std::vector<double>& v) { return v.empty() ? NAN : computeStatistics(v).mean; }

std::vector<std::pair<double, std::string>> methodTics(const Plan& plan) {
  std::vector<std::pair<double, std::string>> tics;
  for (size_t m = 0; m < plan.methods.size(); ++m) tics.emplace_back(static_cast<double>(m), plan.methods[m].label());
  return tics;
}

// Per method, a box of its trials' ATE (mm) with the trials as points over it; one panel a sequence.
Figure ateBoxplot(const Plan& plan, const std::vector<SequenceInfo>& seqs, const std::vector<RunResult>& runs) {
  Figure fig;
  fig.title = "ATE rmse over " + std::to_string(plan.trials) + " trials";
  fig.columns = seqs.size() > 1 ? 2 : 1;
  fig.panel_height_px = 400;
  for (size_t s = 0; s < seqs.size(); ++s) {
    PlotPanel p;
    p.title = seqs[s].name;
    p.ylabel = "ATE rmse [mm]";
    p.xtics = methodTics(plan);
    for (size_t m = 0; m < plan.methods.size(); ++m) {
      PlotSeries box, points;
      box.label = points.label = plan.methods[m].label();
      box.color = points.color = plan.methods[m].colour;
      box.boxplot = true;
      points.points = true;
      for (const double ate : trialValues(plan, runs, s, m, "ate_trans_rmse_m")) {
        box.x.push_back(static_cast<double>(m));
        box.y.push_back(ate * 1e3);
      }
      points.x = box.x;
      points.y = box.y;
      points.label = "";
      if (box.y.empty()) continue;
      p.series.push_back(box);
      p.series.push_back(points);
    }
    if (!p.series.empty()) fig.panels.push_back(p);  // a sequence without ground truth has no ATE
  }
  return fig;
}

}  // namespace

std::string sweepPointLabel(const std::string& setting) {
  std::istringstream words(setting);
  std::string label;
  for (std::string word; words >> word;) {
    const size_t eq = word.find('=');
    const size_t dot = word.rfind('.', eq);
    label += (label.empty() ? "" : " ") + (dot == std::string::npos ? word : word.substr(dot + 1));
  }
  return label;
}

namespace {

// Each setting at (median CPU ms, ATE), the settings of one back-end and mode joined in order and
// labelled with their values; means over the trials. One panel a sequence.
Figure sweepFigure(const Plan& plan, const std::vector<SequenceInfo>& seqs, const std::vector<RunResult>& runs) {
  Figure fig;
  fig.title = "sweep: accuracy against CPU time (mean over trials)";
  fig.columns = seqs.size() > 1 ? 2 : 1;
  fig.panel_height_px = 400;
  for (size_t s = 0; s < seqs.size(); ++s) {
    PlotPanel p;
    p.title = seqs[s].name;
    p.xlabel = "CPU ms per frame (median)";
    p.ylabel = "ATE rmse [mm]";
    std::map<std::string, PlotSeries> by_line;  // one line per back-end, mode and option file
    std::vector<std::string> order;
    for (size_t m = 0; m < plan.methods.size(); ++m) {
      const Method& method = plan.methods[m];
      const std::string key = method.configured();
      if (!by_line.count(key)) {
        order.push_back(key);
        PlotSeries& line = by_line[key];
        line.label = key;
        line.color = method.colour;
        line.points = method.setting.empty();  // an unswept method: one point
      }
      PlotSeries& line = by_line[key];
      const double cpu_ms = meanOf(trialValues(plan, runs, s, m, "cpu_ms_median"));
      const double ate_mm = meanOf(trialValues(plan, runs, s, m, "ate_trans_rmse_m")) * 1e3;
      if (!std::isfinite(cpu_ms) || !std::isfinite(ate_mm)) continue;  // not run, or no ground truth
      line.x.push_back(cpu_ms);
      line.y.push_back(ate_mm);
      line.point_labels.push_back(sweepPointLabel(method.setting));
    }
    for (const std::string& key : order) {
      if (by_line[key].x.empty()) continue;
      PlotSeries line = by_line[key], points = line;
      line.point_labels.clear();
      points.points = true;
      points.label = "";  // one key entry a method: the line's (or, unswept, the point's)
      if (line.points) std::swap(line.label, points.label);
      else p.series.push_back(line);
      p.series.push_back(points);
    }
    if (!p.series.empty()) fig.panels.push_back(p);
  }
  return fig;
}

// Mean CPU ms per frame in each stage (a stage's mean per call x calls / frames), stacked, and what
// no stage timed; means over the trials. Nothing when no run has stages.
Figure stagesFigure(const Plan& plan, const SequenceInfo& seq, size_t s, const std::vector<RunResult>& runs) {
  std::vector<std::string> stages;  // every back-end's vocabulary, in order of appearance
  std::vector<std::map<std::string, double>> per_method(plan.methods.size());
  std::vector<double> untimed(plan.methods.size(), NAN);
  for (size_t m = 0; m < plan.methods.size(); ++m) {
    std::map<std::string, std::vector<double>> trial_ms;
    std::vector<double> rest;
    for (const RunResult* run : cellRuns(plan, runs, s, m)) {
      const RunResult& r = *run;
      if (!r.finished()) continue;
      if (!r.summary.contains("stages") || !r.summary["stages"].is_object()) continue;
      const double frames = r.summary.value("frames", 0);
      if (frames <= 0) continue;
      double timed = 0;
      for (const auto& [name, st] : r.summary["stages"].items()) {
        const double ms = st.value("mean", 0.0) * st.value("calls", 0) / frames;
        if (std::find(stages.begin(), stages.end(), name) == stages.end()) stages.push_back(name);
        trial_ms[name].push_back(ms);
        timed += ms;
      }
      rest.push_back(std::max(0.0, runValue(r, "cpu_ms_mean") - timed));
    }
    for (const auto& [name, v] : trial_ms) per_method[m][name] = meanOf(v);
    untimed[m] = meanOf(rest);
  }
  Figure fig;
  if (stages.empty()) return fig;
  fig.title = seq.name + ": CPU time per frame by stage (mean, tracking thread)";
  fig.panel_height_px = 420;
  PlotPanel p;
  p.ylabel = "CPU ms per frame";
  p.xtics = methodTics(plan);
  p.stacked_bars = true;
  // A colour per stage (matplotlib's tab10), grey for the untimed rest.
  static const char* const palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                        "#8c564b", "#e377c2", "#bcbd22", "#17becf", "#7f7f7f"};
  for (size_t k = 0; k <= stages.size(); ++k) {
    PlotSeries bar;
    bar.label = k < stages.size() ? stages[k] : "not in a stage";
    bar.color = k < stages.size() ? palette[k % std::size(palette)] : "#dddddd";
    for (size_t m = 0; m < plan.methods.size(); ++m) {
      bar.x.push_back(static_cast<double>(m));
      const auto it = k < stages.size() ? per_method[m].find(stages[k]) : per_method[m].end();
      bar.y.push_back(k < stages.size() ? (it == per_method[m].end() ? 0.0 : it->second)
                                        : (std::isfinite(untimed[m]) ? untimed[m] : 0.0));
    }
    p.series.push_back(bar);
  }
  fig.panels.push_back(p);
  return fig;
}

// Each method's ANEES per frame over the trials (log scale) with its 95 % interval, dashed: the
// frames where the filter is over- or underconfident (ov_eval's NEES plot). Nothing when no method
// scored its covariances in 2 trials or more.
Figure aneesFigure(const Plan& plan, const SequenceInfo& seq, size_t s, const std::vector<RunResult>& runs) {
  Figure fig;
  PlotPanel p;
  p.xlabel = "time [s]";
  p.ylabel = "ANEES (6 dof)";
  p.log_y = true;
  for (size_t m = 0; m < plan.methods.size(); ++m) {
    const auto mc = trialsMonteCarloNees(plan, runs, s, m);
    if (!mc) continue;
    PlotSeries anees, lower, upper;
    anees.label = plan.methods[m].label() + " (" + fmt(100.0 * mc->inside / mc->steps(), 0) + " % inside)";
    lower.label = upper.label = "";
    anees.color = lower.color = upper.color = plan.methods[m].colour;
    lower.dashed = upper.dashed = true;
    lower.width = upper.width = 1;
    anees.x = lower.x = upper.x = mc->timestamps;
    anees.y = mc->anees;
    lower.y = mc->lower;
    upper.y = mc->upper;
    p.series.push_back(anees);
    p.series.push_back(lower);
    p.series.push_back(upper);
  }
  if (p.series.empty()) return fig;
  fig.title = seq.name + ": NEES averaged over the trials, with its 95 % interval (dashed)";
  fig.panel_height_px = 420;
  fig.panels.push_back(p);
  return fig;
}

}  // namespace

std::vector<std::string> writeExperimentFigures(const Plan& plan, const std::vector<SequenceInfo>& seqs,
                                                const std::vector<RunResult>& runs, const std::string& fig_dir) {
  std::vector<std::string> written;
  auto save = [&](const Figure& fig, const std::string& name) {
    if (fig.panels.empty()) return;
    const std::string path = fig_dir + "/" + name + ".png";
    writeFigurePng(fig, path);
    written.push_back(path);
  };
  if (plan.trials > 1) save(ateBoxplot(plan, seqs, runs), "ate_boxplot");
  if (!plan.swept_keys.empty()) save(sweepFigure(plan, seqs, runs), "sweep_ate_cpu");
  for (size_t s = 0; s < seqs.size(); ++s) save(stagesFigure(plan, seqs[s], s, runs), seqs[s].name + "_stages");
  if (plan.trials > 1)
    for (size_t s = 0; s < seqs.size(); ++s) save(aneesFigure(plan, seqs[s], s, runs), seqs[s].name + "_anees");
  return written;
}

}  // namespace slamcmp
