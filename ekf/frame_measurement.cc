#include "ekf/frame_measurement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "core/image.h"
#include "core/statistics.h"
#include "ekf/ekf_update.h"
#include "ekf/inverse_depth.h"
#include "ekf/joint_compatibility.h"
#include "ekf/measurement_model.h"
#include "ekf/one_point_ransac.h"
#include "ekf/patch_search.h"
#include "ekf/rolling_shutter.h"

namespace slamcmp {

namespace {

// Pope's tau test needs the others to say something of the noise: at least this many matches.
constexpr int kMinMatchesForVarianceFactor = 4;

// Fisher's F(2, dof) quantile at probability p: (dof / 2)((1 - p)^(-2 / dof) - 1).
double fisherQuantile2(int dof, double p) {
  const double n = dof;
  return n / 2 * (std::pow(1 - p, -2 / n) - 1);
}

// The threshold of a match's chi2 (2 dof) against the others when the variance factor of S is the
// others' own, others_d2 over its dof (at least min_variance_factor): the statistic (d2 / 2) /
// factor is F(2, dof), with f_quantile its quantile. Never above chi2_threshold, the test with S as
// assumed: others noisier than assumed do not loosen it.
double tauThreshold(double others_d2, int dof, double f_quantile, double chi2_threshold, double min_variance_factor) {
  const double factor = std::max(others_d2 / dof, min_variance_factor);
  const double threshold = 2 * factor * f_quantile;
  return std::isfinite(threshold) ? std::min(threshold, chi2_threshold) : chi2_threshold;
}

// The matches `others` as a prediction of any other match k, from the joint innovation
// covariance S and innovations nu of all the matches: factorised once, asked for each k.
class ConditionalOn {
 public:
  ConditionalOn(const Eigen::MatrixXd& S, const Eigen::VectorXd& nu, const std::vector<int>& others)
      : S_(S), nu_(nu) {
    for (int o : others) rows_.insert(rows_.end(), {2 * o, 2 * o + 1});
    S_oo_.compute(S(rows_, rows_));
    const Eigen::VectorXd nu_o = nu(rows_);
    S_oo_inv_nu_ = S_oo_.solve(nu_o);
    others_nis_ = nu_o.dot(S_oo_inv_nu_);
    dof_ = 2 * static_cast<int>(others.size());
  }
  // The chi2 (2 dof) of match k (not among the others) given them.
  double d2(int k) const {
    const Eigen::MatrixXd S_ko = S_({2 * k, 2 * k + 1}, rows_);
    const Vec2 r = nu_.segment<2>(2 * k) - S_ko * S_oo_inv_nu_;  // k's innovation about the others' prediction
    const Mat2 C = S_.block<2, 2>(2 * k, 2 * k) - S_ko * S_oo_.solve(S_ko.transpose());
    return r.dot(C.inverse() * r);
  }
  double othersNis() const { return others_nis_; }  // the others' own joint NIS
  int dof() const { return dof_; }

 private:
  const Eigen::MatrixXd& S_;
  const Eigen::VectorXd& nu_;
  std::vector<int> rows_;
  Eigen::LDLT<Eigen::MatrixXd> S_oo_;
  Eigen::VectorXd S_oo_inv_nu_;
  double others_nis_ = 0;
  int dof_ = 0;
};

// Joint compatibility among each searched feature's candidates, then each match against the
// others' prediction of it. Sets the chosen z and returns the indices kept, in increasing order,
// and the kept matches' joint NIS in *nis.
std::vector<size_t> jointlyCompatible(const EkfState& state, std::vector<PointObservation>& searched,
                                      const std::vector<std::vector<Vec2>>& candidates_uv,
                                      const ActiveSearchOptions& so, double* nis) {
  std::vector<Vec2> predicted;
  for (const PointObservation& o : searched) predicted.push_back(o.h.uv_distorted);
  const std::vector<int> choice = jointCompatibleAssociation(
      predicted, innovationCovariance(state, searched, so.pixel_sigma), candidates_uv, so.joint_gate);
  std::vector<PointObservation> observations;
  std::vector<size_t> kept;
  for (size_t k = 0; k < searched.size(); ++k) {
    if (choice[k] < 0) continue;
    searched[k].z = candidates_uv[k][choice[k]];
    observations.push_back(searched[k]);
    kept.push_back(k);
  }
  // Each match against the prediction the others make of it: a patch sliding along an occluding
  // edge drifts a few pixels a frame, inside its own (large, at 10 fps) ellipse and jointly
  // compatible, yet it disagrees with the rest; drop the worst such match until all agree.
  const double consistency_threshold = chiSquaredQuantile(2, so.consistency_gate);
  *nis = 0;
  while (!observations.empty()) {
    const int m = static_cast<int>(observations.size());
    const Eigen::MatrixXd S_full = innovationCovariance(state, observations, so.pixel_sigma);
    const Eigen::LDLT<Eigen::MatrixXd> S(S_full);
    Eigen::VectorXd nu(2 * m);
    for (int k = 0; k < m; ++k) nu.segment<2>(2 * k) = observations[k].z - observations[k].h.uv_distorted;
    const Eigen::VectorXd S_inv_nu = S.solve(nu);
    const double joint = nu.dot(S_inv_nu);
    *nis = joint;
    if (m <= 2) break;
    const Eigen::MatrixXd S_inv = S.solve(Eigen::MatrixXd::Identity(2 * m, 2 * m));
    const bool tau = so.min_variance_factor > 0 && m >= kMinMatchesForVarianceFactor;
    const double f_quantile = tau ? fisherQuantile2(2 * m - 2, so.consistency_gate) : 0;
    std::vector<double> d2_all(m);  // each match's chi2 given all the others
    for (int k = 0; k < m; ++k) {
      // (S^-1 nu)_k^T ((S^-1)_kk)^-1 (S^-1 nu)_k: the chi2 of match k given all the others.
      const Vec2 a = S_inv_nu.segment<2>(2 * k);
      d2_all[k] = a.dot(S_inv.block<2, 2>(2 * k, 2 * k).inverse() * a);
    }
    // The most consistent half of the matches (the smallest d2_all), for the test against them:
    // a match outside it is tested against all of it (factorised once), one inside it against the
    // rest of it.
    std::vector<int> core;
    std::optional<ConditionalOn> on_core;
    if (so.consistency_core_min > 0 && m >= so.consistency_core_min) {
      std::vector<int> order(m);
      for (int k = 0; k < m; ++k) order[k] = k;
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return d2_all[a] < d2_all[b]; });
      core.assign(order.begin(), order.begin() + (m + 1) / 2);
      on_core.emplace(S_full, nu, core);
    }
    int worst = -1;
    double worst_d2 = consistency_threshold;
    for (int k = 0; k < m; ++k) {
      double d2 = d2_all[k];
      // On the chi2 threshold's scale, so that the worst is the least likely (a statistic that is
      // not a number counts as the worst).
      if (tau)
        d2 *= consistency_threshold /
              tauThreshold(joint - d2, 2 * m - 2, f_quantile, consistency_threshold, so.min_variance_factor);
      if (on_core) {  // and against the core (k left out of it), with the core's noise
        std::optional<ConditionalOn> on_rest;
        if (std::find(core.begin(), core.end(), k) != core.end()) {
          std::vector<int> others;
          for (int c : core)
            if (c != k) others.push_back(c);
          on_rest.emplace(S_full, nu, others);
        }
        const ConditionalOn& c = on_rest ? *on_rest : *on_core;
        double d2_core = c.d2(k);
        if (tau)
          d2_core *= consistency_threshold / tauThreshold(c.othersNis(), c.dof(),
                                                          fisherQuantile2(c.dof(), so.consistency_gate),
                                                          consistency_threshold, so.min_variance_factor);
        d2 = std::isfinite(d2_core) ? std::max(d2, d2_core) : std::numeric_limits<double>::infinity();
      }
      if (!std::isfinite(d2)) d2 = std::numeric_limits<double>::infinity();
      if (d2 > worst_d2) {
        worst_d2 = d2;
        worst = k;
      }
    }
    if (worst < 0) break;
    observations.erase(observations.begin() + worst);
    kept.erase(kept.begin() + worst);
  }
  return kept;
}

// nu^T S^-1 nu of the observations `kept` (their z against their prior h), S restricted to them
// from the prior's innovation covariance of all `observations`.
double jointNis(const Eigen::MatrixXd& S, const std::vector<PointObservation>& observations,
                const std::vector<size_t>& kept) {
  std::vector<int> rows;
  Eigen::VectorXd nu(2 * kept.size());
  for (size_t i = 0; i < kept.size(); ++i) {
    rows.push_back(static_cast<int>(2 * kept[i]));
    rows.push_back(static_cast<int>(2 * kept[i] + 1));
    nu.segment<2>(2 * i) = observations[kept[i]].z - observations[kept[i]].h.uv_distorted;
  }
  const Eigen::MatrixXd S_kept = S(rows, rows);
  return nu.dot(S_kept.ldlt().solve(nu));
}

}  // namespace

bool predictFeature(const CameraModel& camera, const Eigen::VectorXd& x, const MapFeature& feature,
                    PointMeasurement* h) {
  return predictFeature(camera, x.segment<3>(EkfState::kR), x.segment<4>(EkfState::kQ), x, feature, h);
}

bool predictFeature(const CameraModel& camera, const Vec3& r, const Vec4& q, const Eigen::VectorXd& x,
                    const MapFeature& feature, PointMeasurement* h) {
  if (feature.is_ray) return false;
  if (feature.inverse_depth) return predictInverseDepthMeasurement(camera, r, q, x.segment<6>(feature.offset), h);
  return predictMeasurement(camera, r, q, x.segment<3>(feature.offset), h);
}

Vec3 featurePoint(const Eigen::VectorXd& x, const MapFeature& feature) {
  if (feature.inverse_depth) return inverseDepthPoint(x.segment<6>(feature.offset));
  if (feature.is_ray) return x.segment<3>(feature.offset) + feature.particles.mean() * x.segment<3>(feature.offset + 3);
  return x.segment<3>(feature.offset);
}

Mat3 featurePointCovariance(const EkfState& state, const MapFeature& feature) {
  if (!feature.inverse_depth) return state.P().block<3, 3>(feature.offset, feature.offset);
  Eigen::Matrix<double, 3, 6> J;
  inverseDepthToPoint(state.x().segment<6>(feature.offset), &J);
  return J * state.P().block<6, 6>(feature.offset, feature.offset) * J.transpose();
}

FrameMeasurement measureFeatures(EkfState& state, std::vector<MapFeature>& features, const CameraModel& camera,
                                 const cv::Mat& grey, const ActiveSearchOptions& so,
                                 const OnePointRansacOptions* ransac, std::mt19937* rng) {
  FrameMeasurement out;
  const int half = so.patch_size / 2;
  std::vector<PointMeasurement> h_visible;  // parallel to out.features
  std::vector<size_t> selectable;           // into out.features
  for (size_t i = 0; i < features.size(); ++i) {
    const MapFeature& f = features[i];
    PointMeasurement h;
    if (!predictFeature(camera, state.x(), f, &h)) continue;
    if (!camera.inImage(h.uv_distorted, half + 1)) continue;
    FeatureSearch s;
    s.index = i;
    s.uv_predicted = h.uv_distorted;
    s.S = pointInnovationCovariance(state, h, f.offset, so.pixel_sigma);
    s.half_axis = so.sigma_gate * largestStd(s.S);
    if (s.half_axis <= so.max_search_half_axis) selectable.push_back(out.features.size());
    out.features.push_back(s);
    h_visible.push_back(h);
  }
  out.visible = static_cast<int>(out.features.size());
  // The most uncertain features first: they tell the filter the most.
  std::sort(selectable.begin(), selectable.end(), [&](size_t a, size_t b) {
    return out.features[a].S.determinant() > out.features[b].S.determinant();
  });
  if (static_cast<int>(selectable.size()) > so.features_per_frame) selectable.resize(so.features_per_frame);

  // Search each selected feature's ellipse with its warped template.
  const SE3 T_world_camera = state.T_world_camera();
  std::vector<PointObservation> searched;
  std::vector<std::vector<Vec2>> candidates_uv;  // nearest the prediction first
  std::vector<Vec2> best_uv;                      // the best-correlating candidate
  std::vector<size_t> searched_slot;  // into out.features
  for (size_t slot : selectable) {
    FeatureSearch& s = out.features[slot];
    MapFeature& f = features[s.index];
    s.outcome = SearchOutcome::Failed;
    ++f.attempts;
    ++f.misses_in_a_row;
    cv::Mat templ;
    if (!warpTemplate(f.source, camera, T_world_camera, featurePoint(state.x(), f), s.uv_predicted,
                      so.patch_size, &templ) ||
        patchStdDev(templ) < so.min_patch_stddev)
      continue;
    // Searched where its row is read; its matches are taken back to the frame's time by that shift.
    s.rolling_shift = rollingShutterShift(camera, so.rolling_shutter_readout, state.x(), f, s.uv_predicted);
    const Vec2 uv_search = s.uv_predicted + s.rolling_shift;
    std::vector<PatchMatch> matches = searchEllipses(grey, templ, {{uv_search, s.S}}, so.sigma_gate, so.min_ncc);
    if (matches.empty()) continue;
    for (PatchMatch& m : matches) m.uv -= s.rolling_shift;
    best_uv.push_back(matches.front().uv);
    // The candidates nearest the prediction (Mahalanobis): on a chessboard many peaks correlate
    // equally well and the correct one is the most likely, not the best scoring.
    const Mat2 S_inv = s.S.inverse();
    auto distance = [&](const PatchMatch& m) {
      const Vec2 d = m.uv - s.uv_predicted;
      return d.dot(S_inv * d);
    };
    std::sort(matches.begin(), matches.end(),
              [&](const PatchMatch& a, const PatchMatch& b) { return distance(a) < distance(b); });
    if (static_cast<int>(matches.size()) > so.max_candidates) matches.resize(so.max_candidates);
    PointObservation o;
    o.offset = f.offset;
    o.h = h_visible[slot];
    searched.push_back(o);
    candidates_uv.emplace_back();
    for (const PatchMatch& m : matches) candidates_uv.back().push_back(m.uv);
    searched_slot.push_back(slot);
  }
  if (searched.empty()) return out;

  std::vector<size_t> kept;
  if (ransac) {
    for (size_t k = 0; k < searched.size(); ++k) searched[k].z = best_uv[k];
    const ObservationPredictor predict = [&](const Eigen::VectorXd& x, size_t k, PointMeasurement* h) {
      return predictFeature(camera, x, features[out.features[searched_slot[k]].index], h);
    };
    // The prior's innovation covariance, for the kept matches' joint NIS (as joint compatibility's).
    const Eigen::MatrixXd S_prior = innovationCovariance(state, searched, so.pixel_sigma);
    kept = onePointRansacUpdate(state, searched, predict, *ransac, so.pixel_sigma, *rng);
    if (kept.empty()) return out;
    out.nis = jointNis(S_prior, searched, kept);
    out.nis_dof = 2 * static_cast<int>(kept.size());
  } else {
    double nis = 0;
    kept = jointlyCompatible(state, searched, candidates_uv, so, &nis);
    std::vector<PointObservation> observations;
    for (size_t k : kept) observations.push_back(searched[k]);
    // An innovation covariance that is not positive definite means the filter's numbers broke: no
    // update, and the frame counts as unmeasured (the health check then ends the run of frames).
    if (observations.empty() || !batchUpdate(state, observations, so.pixel_sigma)) return out;
    out.nis = nis;
    out.nis_dof = 2 * static_cast<int>(kept.size());
  }
  for (size_t k : kept) {
    FeatureSearch& s = out.features[searched_slot[k]];
    s.outcome = SearchOutcome::Matched;
    s.uv_matched = searched[k].z + s.rolling_shift;
    ++features[s.index].successes;
    features[s.index].misses_in_a_row = 0;
  }
  out.matched = static_cast<int>(kept.size());
  return out;
}

}  // namespace slamcmp
