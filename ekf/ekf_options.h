#pragma once
// The options of the EKF's pieces (SPEC section 5), shared by the EKF back-ends. Defaults are
// SceneLib's where it has one (monoslam.cpp: 100 particles over 0.5-5 m, 20 particles minimum,
// prune 0.05, 10-12 features a frame, 80x60 initialisation boxes) except the motion noise, the
// promotion ratio and the search's variance floor (search.min_variance_factor; see below).
#include <string>

#include "core/options.h"

namespace slamcmp {

// The motion noise estimated from the filter's own velocity corrections (covariance matching,
// ekf/adaptive_motion_noise.h): sigma_a and sigma_alpha are where it starts and the most it takes;
// it falls towards what the camera's accelerations show, no lower than the floors.
struct AdaptiveMotionOptions {
  bool enabled = false;         // off: sigma_a and sigma_alpha as set (SceneLib)
  // s, of the running mean of the velocity corrections: short, for a hand-held camera's bursts
  // (vamr_checkerboard: 1.4 mm with 0.5 s, 1.7 mm with 2 s, beside a floor of 0.5).
  double time_constant = 0.5;
  double min_sigma_a = 0.1;     // m/s^2 at the reference rate
  double min_sigma_alpha = 0.1; // rad/s^2 at the reference rate
  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "estimate sigma_a, sigma_alpha (at most their set values) from the velocity corrections");
    v("time_constant", time_constant, "s, time constant of the running mean of the velocity corrections");
    v("min_sigma_a", min_sigma_a, "m/s^2, the least linear acceleration noise it takes");
    v("min_sigma_alpha", min_sigma_alpha, "rad/s^2, the least angular acceleration noise it takes");
  }
  void check() const;
};

// Constant velocity with acceleration impulses V = a dt, W = alpha dt. SceneLib's sigma_a and
// sigma_alpha give the impulses at its 30 Hz: std(V) = sigma_a / 30 a frame. At another frame
// interval dt the impulse variance scales linearly with dt, as for continuous white-noise
// acceleration (velocity a random walk): var(V) = (sigma_a / rate)^2 * (dt * rate) with
// rate = reference_rate, i.e. std(V) = sigma_a * sqrt(dt / reference_rate); the same for W.
// At 10 fps that is sqrt(3) times SceneLib's per-frame impulse. The defaults are half SceneLib's
// (its 4 and 6 are for a hand-held camera): the slow synthetic and tripod sequences stay tracked,
// search ellipses shrink about twofold (tv1..tv4 ~10x faster) and fewer false peaks fall inside
// them (board_leaves: ATE 30 cm -> 7 mm; tv3 5.8 -> 2.4 mm; tv1, tv4, vamr within 0.6 mm).
struct MotionModelOptions {
  double sigma_a = 2.0;           // m/s^2, linear acceleration noise at the reference rate
  double sigma_alpha = 3.0;       // rad/s^2, angular acceleration noise at the reference rate
  double reference_rate = 30.0;   // Hz, the frame rate sigma_a and sigma_alpha are defined at
  double default_dt = 1.0 / 30;   // s, used when timestamps do not increase
  AdaptiveMotionOptions adaptive;
  template <class V>
  void visit(V& v) {
    v("sigma_a", sigma_a, "m/s^2, linear acceleration noise at reference_rate");
    v("sigma_alpha", sigma_alpha, "rad/s^2, angular acceleration noise at reference_rate");
    v("reference_rate", reference_rate,
      "Hz; impulse std = sigma * sqrt(dt / reference_rate) (white-noise acceleration)");
    v("default_dt", default_dt, "s, frame interval when timestamps do not increase");
    v("adaptive", adaptive, "motion noise estimated from the filter's velocity corrections");
  }
  void check() const;
};

struct ActiveSearchOptions {
  int patch_size = 11;               // pixels, odd
  double sigma_gate = 3.0;           // search ellipse, in standard deviations
  double min_ncc = 0.8;              // accept a match at or above this correlation
  double min_patch_stddev = 10.0;    // grey levels; flatter templates are not searched
  double pixel_sigma = 1.0;          // pixels, measurement noise
  int features_per_frame = 12;       // measured a frame, the most uncertain first
  double max_search_half_axis = 120; // pixels; features with a larger 3-sigma ellipse are skipped
  int max_candidates = 6;            // correlation peaks kept per feature for the association
  double joint_gate = 0.99;          // joint compatibility test probability (chi2 of 2k dof)
  double consistency_gate = 0.999;   // each match against the others' prediction of it (chi2, 2 dof)
  // That test with the noise the others show (Pope's tau test, 1976): the variance factor of their
  // innovations, at least this, and never a looser test than with S as assumed. An overcautious S
  // (1 px assumed, matches found to a third of it) hides a look-alike a few pixels off (README).
  // 0: S as assumed.
  double min_variance_factor = 0.1;
  // With this many matches or more, each match is also tested against the prediction of the most
  // consistent half of the others (the half with the smallest statistics against all the rest),
  // with their noise: two look-alikes matched off in the same direction, which one pose error
  // explains, mask each other in the test against all the others (vamr_checkerboard frames 307
  // and 325: two patches off the board matched 7-12 px off carried the camera 10 mm). 0: not.
  int consistency_core_min = 6;
  int source_size = 41;              // pixels, the stored crop of the first view the template is warped from
  // A rolling shutter's readout, seconds from the top row's read to the bottom row's (0: a global
  // shutter; ekf/rolling_shutter.h): the map's patch features are searched where their rows are
  // read, hybrid's board corners and tracked points are predicted there, and its window's tracks
  // are turned back to the frame's time by the camera's turn. On handheld_rpy
  // rendered with a 30 ms shutter it takes monoslam's orientation error from 3.8-5.6 to 1.4-2.4
  // degrees and hybrid's ATE from 96 to 3.3-4.1 mm; on tum_fr1_rpy no value helps (README).
  double rolling_shutter_readout = 0.0;
  template <class V>
  void visit(V& v) {
    v("patch_size", patch_size, "pixels, odd");
    v("sigma_gate", sigma_gate, "search ellipse, in standard deviations");
    v("min_ncc", min_ncc, "accept a match at or above this normalised cross-correlation");
    v("min_patch_stddev", min_patch_stddev, "grey levels; flatter templates are not searched");
    v("pixel_sigma", pixel_sigma, "pixels, measurement noise");
    v("features_per_frame", features_per_frame, "features measured a frame, most uncertain first");
    v("max_search_half_axis", max_search_half_axis, "pixels; larger search ellipses are skipped");
    v("max_candidates", max_candidates, "correlation peaks kept per feature for the association");
    v("joint_gate", joint_gate, "joint compatibility test probability (chi2 of 2k dof)");
    v("consistency_gate", consistency_gate,
      "probability of the test of each match against the others' prediction of it (chi2, 2 dof)");
    v("min_variance_factor", min_variance_factor,
      "that test with the noise the other matches show (Pope's tau test): the variance factor of their innovations, "
      "at least this, never looser than the test as assumed; 0: the innovations' covariance as assumed");
    v("consistency_core_min", consistency_core_min,
      "with this many matches or more each is also tested against the most consistent half of the others "
      "(agreeing look-alikes mask each other in the test against all of them); 0: not");
    v("source_size", source_size, "pixels, crop of the first view kept for warping the template");
    v("rolling_shutter_readout", rolling_shutter_readout,
      "seconds from reading the image's top row to its bottom row, the middle row at the frame's time "
      "(0: a global shutter); each map feature (patches, not depth-particle rays) is searched, and each of hybrid's "
      "board corners and tracked points predicted, where the camera sees it when its row is read; hybrid's window "
      "tracks are turned back to the frame's time by the camera's turn");
  }
  void check() const;
  void checkImage(cv::Size image) const;  // the crops fit in the image
};

struct FeatureInitOptions {
  int particles = 100;             // depth hypotheses along the ray
  double min_depth = 0.5;          // m
  double max_depth = 5.0;          // m
  // SceneLib's 0.3 promotes with little parallax; 0.2 waits for more and the point's depth is
  // right (tv4, moving along the optical axis: ATE 5.1 cm -> 2 mm; tv1 5.8 -> 4.8 mm).
  double promote_ratio = 0.2;      // promote when depth std / mean falls below this
  int min_particles = 20;          // fewer surviving particles: the feature is dropped
  double prune_threshold = 0.05;   // particles under this fraction of the best weight are pruned
  int max_frames = 20;             // frames a ray may take to converge before it is dropped
  int max_initialising = 1;        // rays being initialised at once
  int min_visible = 12;            // start a new feature when fewer map features are visible
  int box_width = 80;              // pixels, the image box searched for a new corner
  int box_height = 60;             // pixels
  double min_corner_eigenvalue = 0.002;  // Shi-Tomasi minimum eigenvalue (OpenCV scale, 3x3 block)
  int seed = 0;                    // the boxes are drawn at random from this seed (repeatable runs)
  // A corner whose patch has a look-alike near it (a chessboard's corners, a square away
  // diagonally) is matched there in the first, widest searches of a board-free start, which then
  // takes the look-alike's offset for motion: such corners are taken only when no free box offers
  // one without. Off for the SceneLib baseline, whose board start keeps its searches small.
  std::string distinct = "auto";   // auto (on with --init none) | on | off
  int distinct_radius = 30;        // pixels, the most a look-alike is looked for away (the searches' reach)
  template <class V>
  void visit(V& v) {
    v("particles", particles, "depth hypotheses along a new feature's ray");
    v("min_depth", min_depth, "m, nearest depth hypothesis");
    v("max_depth", max_depth, "m, farthest depth hypothesis");
    v("promote_ratio", promote_ratio, "promote to a 3D point when depth std/mean is below this");
    v("min_particles", min_particles, "a ray with fewer surviving particles is dropped");
    v("prune_threshold", prune_threshold, "particles under this fraction of the best weight are pruned");
    v("max_frames", max_frames, "frames a ray may take to converge before it is dropped");
    v("max_initialising", max_initialising, "rays initialising at once");
    v("min_visible", min_visible, "start a new feature when fewer map features are visible");
    v("box_width", box_width, "pixels, width of the box searched for a new corner");
    v("box_height", box_height, "pixels, height of the box searched for a new corner");
    v("min_corner_eigenvalue", min_corner_eigenvalue, "Shi-Tomasi minimum eigenvalue (OpenCV scale)");
    v("seed", seed, "random seed of the boxes searched for new corners (runs are repeatable)");
    v("distinct", distinct,
      "auto (on with --init none) | on | off: new corners preferably with no look-alike (a place the search "
      "would accept) as far as the last frame's searches reached");
    v("distinct_radius", distinct_radius,
      "pixels, the most a look-alike is looked for away from a new corner (and before any search)");
  }
  void check() const;
  void checkImage(cv::Size image) const;  // the box fits in the image
};

struct MapManagementOptions {
  int max_features = 100;            // mapped points plus initialising rays
  int min_attempts = 10;             // attempts before a feature may be judged
  double min_success_ratio = 0.5;    // a judged feature matching less often than this is deleted
  // A feature missed this many attempts in a row is deleted whatever its record (0: never; the
  // SceneLib baseline judges the record alone): a fast turn can leave a map of features matched
  // well before and no longer, each kept by its record (docs/findings.md, session 35). A board's
  // known corners are kept.
  int max_misses_in_a_row = 0;
  template <class V>
  void visit(V& v) {
    v("max_features", max_features, "mapped points plus initialising rays");
    v("min_attempts", min_attempts, "match attempts before a feature may be deleted");
    v("min_success_ratio", min_success_ratio, "delete a feature matching less often than this");
    v("max_misses_in_a_row", max_misses_in_a_row,
      "delete a feature missed this many attempts in a row, whatever its record (0: never; not a board's corners)");
  }
  void check() const;
};

struct HealthOptions {
  int max_frames_unmeasured = 10;  // consecutive frames without an accepted match: lost
  double max_speed = 10.0;         // m/s; a faster camera estimate is divergence
  double max_angular_speed = 20.0; // rad/s
  double max_position_sigma = 1.0; // m; a larger camera position std is divergence
  template <class V>
  void visit(V& v) {
    v("max_frames_unmeasured", max_frames_unmeasured, "frames without an accepted match before lost");
    v("max_speed", max_speed, "m/s; a faster camera estimate means divergence");
    v("max_angular_speed", max_angular_speed, "rad/s; a faster camera estimate means divergence");
    v("max_position_sigma", max_position_sigma, "m; larger camera position std means divergence");
  }
  void check() const;
};

// The first camera state's uncertainty. SceneLib starts from a known pose with zero uncertainty,
// right for a pose solved from the board or taken from ground truth. A hand-measured start
// (`--init manual:FILE`) gets manual_* instead: with zero uncertainty a 1 cm / 1 degree error is
// never corrected and new features inherit it (tv1: up to 14 cm of drift).
struct StartOptions {
  double position_sigma = 0.0;          // m
  double orientation_sigma = 0.0;       // per quaternion component (about half the angle in rad)
  double manual_position_sigma = 0.02;  // m, for --init manual
  double manual_orientation_sigma = 0.02;  // per quaternion component, for --init manual
  double velocity_sigma = 0.0;          // m/s
  double angular_velocity_sigma = 0.0;  // rad/s
  // A restart from the board after a loss: its velocities are the board's motion between two
  // frames running (motion_model.h's velocityBetween), to within these over the frame interval
  // dt (velocity std = move / dt): the two board poses' error, which a shorter interval makes
  // a larger velocity error.
  double restart_move_per_frame = 0.005;  // m
  double restart_turn_per_frame = 0.01;   // rad
  // --init none: nothing tells the first camera's motion, which a hand-held camera has (tum_fr1_rpy
  // turns 3.7 degrees between its first two frames). Given per frame interval, as Civera 2010's
  // 0.025 rad a frame: velocity std = move / dt, set once the first interval dt is known.
  double board_free_turn_per_frame = 0.03;  // rad, std of the turn over the first frame interval
  double board_free_move_per_frame = 0.01;  // units (the map's, inverse_depth.rho0), std of the move over it
  template <class V>
  void visit(V& v) {
    v("position_sigma", position_sigma, "m, first camera position std (board, groundtruth)");
    v("orientation_sigma", orientation_sigma, "first camera quaternion std per component (board, groundtruth)");
    v("manual_position_sigma", manual_position_sigma, "m, first camera position std for --init manual");
    v("manual_orientation_sigma", manual_orientation_sigma, "first quaternion std per component for --init manual");
    v("velocity_sigma", velocity_sigma, "m/s, first velocity std (board, groundtruth, manual)");
    v("angular_velocity_sigma", angular_velocity_sigma, "rad/s, first angular velocity std (board, groundtruth, manual)");
    v("restart_move_per_frame", restart_move_per_frame,
      "m, a restart after a loss: std of the board's move over the frame interval its velocity is taken from");
    v("restart_turn_per_frame", restart_turn_per_frame,
      "rad, a restart after a loss: std of the board's turn over the frame interval its angular velocity is taken from");
    v("board_free_turn_per_frame", board_free_turn_per_frame,
      "rad, --init none: std of the turn over the first frame interval (angular velocity std = turn / dt)");
    v("board_free_move_per_frame", board_free_move_per_frame,
      "map units, --init none: std of the move over the first frame interval (velocity std = move / dt)");
  }
  void check() const;
};

// When a filter reports a frame lost instead of its extrapolation (SPEC section 4: never a made-up
// pose): too few measurements for several frames running, a camera position std beyond a bound, or
// matches far more at odds with the prediction than the run's own matches have been.
// The filter runs on; its frames are posed again once it measures enough and is certain enough.
struct ReportingOptions {
  int min_measured = 4;              // measurements a frame (points and board corners) for a well-measured frame
  int max_weak_frames = 3;           // this many weakly measured frames running: lost
  // m; a larger camera position std (largest axis): lost (not board-free). 3 cm: turning to
  // wall_turn's other wall, monoslam measures the four or five features left a frame while its
  // pose drifts 4-5 mm a frame, and its std passed 5 cm only after the error had (seeds 1, 7, 15
  // and 18: 1-6 frames over 5 cm, up to 8 cm); at 2 cm the first frames after a start are lost.
  double max_position_sigma = 0.03;
  // The matches' NIS per dof against its median over the last innovation_window frames with
  // matches (once there are kMinInnovationHistory of them since the start), in frames nothing
  // absolute anchors: the innovation covariance as assumed is no yardstick (SceneLib's 1 px and
  // motion noise put a good frame's NIS per dof at 0.001-0.01 on the renders), the run's own level
  // is. A look-alike matched a few pixels off that then carries the pose raised it 237 times on
  // board_leaves seed 7 (the error 18 -> 59 mm) and 78-102 times on wall_turn seeds 4 and 12
  // (21 and 46 mm off); good frames of 42 renders rose at most about 40 times. Board-free runs (1-point
  // RANSAC's matches) too, in every frame but those that find the map again after a loss: on
  // wall_turn seed 32 the filter turned on as the camera reached the other wall, its matches agreeing,
  // and the level climbed from 0.01 to 0.66 by frame 88 (24 degrees off by frame 125, unreported,
  // before); tum_fr1_rpy's never jumps. 0: off.
  double max_innovation_jump = 50;
  int innovation_window = 30;        // frames with matches the run's innovation level is the median of
  static constexpr int kMinInnovationHistory = 10;  // frames with matches before the level is a yardstick
  template <class V>
  void visit(V& v) {
    v("min_measured", min_measured, "measurements a frame (points and board corners) for a well-measured frame");
    v("max_weak_frames", max_weak_frames, "this many weakly measured frames running: the frames are lost");
    v("max_position_sigma", max_position_sigma,
      "m; a larger camera position std (largest axis): lost (not board-free: its scale's std grows by itself)");
    v("max_innovation_jump", max_innovation_jump,
      "the matches' NIS per dof this many times its median over the run's last innovation_window frames: lost "
      "(a mismatch moved the filter); 0: off");
    v("innovation_window", innovation_window,
      "frames with matches the run's innovation level is the median of (at least 10, the frames it waits for)");
  }
  void check() const;
};

// ---------------------------------------------------------------------------------------------
// Board-free start (issue 18, SPEC section 8): features in inverse depth and the 1-point RANSAC
// update. Kept apart from the SceneLib options above. `use` is "auto" (on for a board-free start,
// `--init none`; off when a target starts the map, so the thesis's baseline is unchanged), "on"
// or "off".

// Civera, Davison and Montiel, "Inverse Depth Parametrization for Monocular SLAM" (T-RO 2008):
// a feature is y = (x0, y0, z0, theta, phi, rho), the first camera centre, the ray's azimuth and
// elevation in the world frame and the inverse depth along it, measured from its first
// frame on. The scale of a board-free map is the prior's: new features start at rho0 (depth
// 1 / rho0 units) with std rho_sigma, so the map's unit is arbitrary (Sim(3) evaluation).
struct InverseDepthOptions {
  std::string use = "auto";            // auto | on | off
  double rho0 = 0.5;                   // 1/units, initial inverse depth of a new feature
  double rho_sigma = 0.5;              // 1/units, its std (rho0 +- 2 sigma reaches infinity)
  double linearity_threshold = 0.1;    // convert to a 3D point when L_d (Civera 2008 eq. 15) falls below it
  int new_per_frame = 6;               // features started a frame at most (the first frame: min_visible)
  // The scale of a board-free map: the mean inverse depth of the first frame's features is rho0
  // to within this std, 1/units. With each feature's rho_sigma alone (0) the scale wandered while
  // the map was young: tv4 (orbiting the board) went from 0.43 to 0.195 m a unit in its first 30 frames.
  // Full presets without a board, Sim(3) ATE 0 -> 0.001: tv1..tv4 1.25 / 2.04 / 1.78 / 13.8 ->
  // 1.00 / 1.07 / 1.09 / 8.2 mm, wall_turn s1-s3 1.06 / 2.02 / 18.1 -> 0.87 / 1.54 / 2.45,
  // board_leaves s1-s2 1.51 / 3.84 -> 1.02 / 1.97, roll_distortion 0.87 both; 0.0003-0.01 alike.
  double scale_gauge_sigma = 0.001;
  template <class V>
  void visit(V& v) {
    v("use", use, "auto (on with --init none) | on | off: features in inverse depth instead of depth particles");
    v("rho0", rho0, "1/units, initial inverse depth of a new feature (fixes a board-free map's scale)");
    v("rho_sigma", rho_sigma, "1/units, std of the initial inverse depth");
    v("linearity_threshold", linearity_threshold, "convert to a 3D point when the linearity index is below this");
    v("new_per_frame", new_per_frame, "features started a frame at most");
    v("scale_gauge_sigma", scale_gauge_sigma,
      "1/units, board-free start: the mean inverse depth of the first frame's features is rho0 to within this std "
      "(the map's scale); 0: each feature's rho_sigma alone");
  }
  void check() const;
};

// Civera, Grasa, Davison and Montiel, "1-Point RANSAC for EKF Filtering" (JFR 2010), Algorithm 1:
// hypotheses from single matches (state-only EKF updates), the largest set within inlier_pixels
// updates the filter, then the remaining matches within the rescue gate of the updated
// prediction update it again. Replaces the joint compatibility test when on.
struct OnePointRansacOptions {
  std::string use = "auto";      // auto | on | off
  double inlier_pixels = 2.0;    // pixels, a low-innovation inlier's distance to a hypothesis' prediction
  double probability = 0.99;     // of drawing at least one all-inlier hypothesis (sets the count)
  int max_hypotheses = 100;      // upper bound of the adaptive count
  double rescue_gate = 0.99;     // chi2 (2 dof) probability for high-innovation inliers
  // One match fixes a hypothesis only under a tight prior (Civera 2010 section 3): with the first
  // motion unknown, one match is explained by a pan where the camera rolled, and the others miss.
  // Two matches also resist a wrong one better where the prior is loose: at 0.01 rad (pairs on most
  // frames at 10 fps or hand-held) tum_fr1_rpy's seeds 0-3 kept within 22 degrees of the ground
  // truth; at 0.025 (pairs only at the start) one posed frames 160 degrees off.
  double max_turn_sigma = 0.01;  // rad; under a wider predicted orientation std a hypothesis draws two matches
  template <class V>
  void visit(V& v) {
    v("use", use, "auto (on with --init none) | on | off: 1-point RANSAC instead of joint compatibility");
    v("inlier_pixels", inlier_pixels, "pixels, a match this close to a hypothesis' prediction is its inlier");
    v("probability", probability, "probability of drawing an all-inlier hypothesis (adaptive count)");
    v("max_hypotheses", max_hypotheses, "most hypotheses a frame");
    v("rescue_gate", rescue_gate, "chi2 (2 dof) probability that rescues a match after the first update");
    v("max_turn_sigma", max_turn_sigma,
      "rad; under a wider predicted orientation std each hypothesis is drawn from two matches");
  }
  void check() const;
};

// A board-free run that lost its frames has nothing but its own map to anchor it again: each
// feature keeps the ORB descriptor (Rublee et al. 2011) of its first view, and while the frames are
// lost the frame's corners (Shi-Tomasi, as the features were chosen) are described alike and
// matched to the map's, and the camera is the PnP RANSAC pose of the matched points (the
// relocalisation of PTAM and ORB-SLAM); the filter resumes from that pose. (A board-started run
// is anchored by the board.)
struct RelocalisationOptions {
  bool enabled = true;           // with --init none
  int interval = 1;              // frames between attempts while lost (a lost frame has nothing else to do)
  int frame_corners = 1000;      // corners of the frame described and matched
  double ratio = 0.8;            // a match's Hamming distance under this times the second best's (Lowe)
  // PnP RANSAC inliers to accept a pose (a map of 12 features), counting only those whose map
  // point the filter knows to within max_error_px where it projects (its covariance's largest std
  // there): a point uncertain beyond the inlier test passes it for poses far apart, and PnP takes
  // it as exact (docs/findings.md, session 31). The covariances are the map's own, drift
  // included, so an old map confirms fewer of its points.
  int min_inliers = 6;
  double min_inlier_ratio = 0.3; // and at least this fraction of the matches
  double max_error_px = 3.0;     // PnP RANSAC inlier threshold, pixels
  double position_sigma = 0.05;  // units, the relocalised camera position's std
  double orientation_sigma = 0.02;  // per quaternion component
  int retired_points = 200;      // the points of features deleted while posed, matched as well (newest kept)
  // Where all the frame's corners give no pose: each point matched among the corners this near
  // where the lost filter's last pose projects it (0: not), within this Hamming distance of 256
  // bits (as ORB-SLAM's search by projection, whose bounds are 50-100).
  double guided_radius_px = 40;
  int guided_max_hamming = 50;
  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "--init none: relocalise lost frames against the map (ORB descriptors, PnP RANSAC)");
    v("interval", interval, "frames between relocalisation attempts while lost");
    v("frame_corners", frame_corners, "strongest corners of the frame described and matched to the map");
    v("ratio", ratio, "Lowe's ratio test for the descriptor matches");
    v("min_inliers", min_inliers,
      "PnP RANSAC inliers needed to accept a pose, counting those whose map point's std where it projects is "
      "within max_error_px");
    v("min_inlier_ratio", min_inlier_ratio, "fraction of the descriptor matches the pose must explain");
    v("max_error_px", max_error_px, "PnP RANSAC inlier threshold, pixels");
    v("position_sigma", position_sigma, "units (metres with a board), std of the relocalised camera position");
    v("orientation_sigma", orientation_sigma, "std of each quaternion component of the relocalised camera");
    v("retired_points", retired_points,
      "the points of this many features deleted while the frames were posed are matched too (the newest)");
    v("guided_radius_px", guided_radius_px,
      "pixels; where the whole frame gives no pose, points matched among the corners this near where the lost filter's "
      "pose projects them (0: not)");
    v("guided_max_hamming", guided_max_hamming, "the largest Hamming distance of a match near the projection");
  }
  void check() const;
};

// "auto" resolved: on for a board-free start.
bool usesOption(const std::string& use, bool board_free);

}  // namespace slamcmp
