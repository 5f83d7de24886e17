#pragma once
// A small generic RANSAC (COLMAP-style): the estimator supplies a minimal solver and a residual,
// RANSAC supplies sampling, MSAC scoring and the adaptive stopping rule.
//
//   struct Estimator {
//     using Model = ...;
//     static constexpr int kMinSamples = 8;
//     int numData() const;
//     std::vector<Model> estimate(const std::vector<int>& sample) const;  // minimal solver
//     double squaredError(const Model& model, int i) const;
//   };
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/error.h"
#include "core/statistics.h"  // ransacTrials

namespace slamcmp {

struct RansacOptions {
  double max_error = 1.0;     // inlier threshold, in the estimator's residual unit (pixels here)
  double confidence = 0.999;  // probability of having drawn one all-inlier sample
  int min_iterations = 20;
  int max_iterations = 300;
  int seed = 1;  // fixed: runs are repeatable
  template <class V>
  void visit(V& v) {
    v("max_error", max_error, "inlier threshold, pixels");
    v("confidence", confidence, "stop when an all-inlier sample was drawn with this probability");
    v("min_iterations", min_iterations, "samples drawn at least");
    v("max_iterations", max_iterations, "samples drawn at most");
    v("seed", seed, "random seed (runs are repeatable)");
  }
  void check() const {
    if (!(max_error > 0)) throw OptionError("max_error", "must be positive");
    if (!(confidence > 0 && confidence < 1)) throw OptionError("confidence", "must be in (0, 1)");
    if (min_iterations < 1 || max_iterations < min_iterations)
      throw OptionError("max_iterations", "need 1 <= min_iterations <= max_iterations");
  }
};

template <class Model>
struct RansacResult {
  bool success = false;
  Model model{};
  std::vector<char> inliers;  // one flag per datum
  int num_inliers = 0;
  int iterations = 0;
  // Stopped at max_iterations before an all-inlier sample was drawn with `confidence` (at the
  // best model's inlier ratio): the result may be a chance one.
  bool capped = false;
};

template <class Estimator>
RansacResult<typename Estimator::Model> ransac(const Estimator& estimator, const RansacOptions& options) {
  using Model = typename Estimator::Model;
  RansacResult<Model> best;
  const int n = estimator.numData();
  constexpr int k = Estimator::kMinSamples;
  if (n < k) return best;
  const double threshold2 = options.max_error * options.max_error;
  std::mt19937 rng(static_cast<unsigned>(options.seed));
  std::vector<int> indices(n);
  for (int i = 0; i < n; ++i) indices[i] = i;
  std::vector<int> sample(k);
  double best_cost = 1e300;
  int needed = options.max_iterations;
  int it = 0;
  for (; it < std::max(options.min_iterations, std::min(needed, options.max_iterations)); ++it) {
    // Partial Fisher-Yates: k distinct indices.
    for (int s = 0; s < k; ++s) {
      std::uniform_int_distribution<int> pick(s, n - 1);
      std::swap(indices[s], indices[pick(rng)]);
      sample[s] = indices[s];
    }
    for (const Model& model : estimator.estimate(sample)) {
      double cost = 0;  // MSAC: truncated squared error
      int count = 0;
      for (int i = 0; i < n && cost < best_cost; ++i) {
        const double e2 = estimator.squaredError(model, i);
        if (e2 < threshold2) {
          cost += e2;
          ++count;
        } else {
          cost += threshold2;
        }
      }
      if (cost >= best_cost) continue;
      best_cost = cost;
      best.model = model;
      best.num_inliers = count;
      best.success = true;
      // Clamped before the cast: a low inlier ratio can ask for more samples than an int holds.
      const double samples = ransacTrials(static_cast<double>(count) / n, k, options.confidence);
      needed = samples < options.max_iterations ? static_cast<int>(samples) : options.max_iterations;
      best.capped = samples > options.max_iterations;
    }
  }
  best.iterations = it;
  if (best.success) {
    best.inliers.assign(n, 0);
    for (int i = 0; i < n; ++i) best.inliers[i] = estimator.squaredError(best.model, i) < threshold2;
  }
  return best;
}

// The local optimisation of LO-RANSAC (Chum, Matas and Kittler 2003): the model refitted by the
// estimator on all of `result`'s inliers (its solver on more than the minimal sample: a least-
// squares fit), then on the inliers of that, while they grow, at most `max_refits` times. A
// minimal sample's model through noisy points misses part of the inliers that this finds. The
// first refit stands with as many inliers as the sample's model had.
template <class Estimator>
void refitOnInliers(const Estimator& estimator, const RansacOptions& options, int max_refits,
                    RansacResult<typename Estimator::Model>* result) {
  if (!result->success) return;
  const int n = estimator.numData();
  const double threshold2 = options.max_error * options.max_error;
  for (int refit = 0; refit < max_refits; ++refit) {
    std::vector<int> inliers;
    for (int i = 0; i < n; ++i)
      if (result->inliers[i]) inliers.push_back(i);
    if (static_cast<int>(inliers.size()) < Estimator::kMinSamples) return;
    for (const auto& model : estimator.estimate(inliers)) {
      std::vector<char> refitted(n);
      int count = 0;
      for (int i = 0; i < n; ++i) count += refitted[i] = estimator.squaredError(model, i) < threshold2;
      if (count < result->num_inliers || (refit > 0 && count == result->num_inliers)) return;
      result->model = model;
      result->num_inliers = count;
      result->inliers = std::move(refitted);
    }
  }
}

}  // namespace slamcmp
