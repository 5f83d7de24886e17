#pragma once
// Trajectories: timestamped T_world_camera poses. Read in TUM, EuRoC and KITTI formats, written
// in TUM format (what evo and the TUM tools read).
#include <string>
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

struct StampedPose {
  double timestamp = 0;  // seconds
  SE3 T_world_camera;
};
using Trajectory = std::vector<StampedPose>;

enum class TrajectoryFormat { Auto, Tum, Euroc, Kitti };

// Auto: a ".csv" whose first data line is comma-separated is EuRoC; otherwise the field count of
// the first data line decides (8 TUM, 12 KITTI).
// KITTI files carry no time: `kitti_times_path` gives one per line, else frame indices are used.
// Throws InputError naming the file and line for anything malformed: a wrong field count, a value
// that is not a finite number, a quaternion or rotation far from unit, a timestamp that goes back
// in time (a repeated one is kept, as evo keeps it), one that cannot be seconds
// (checkPlausibleSeconds), a position beyond 1e100 (its squares overflow), or a file without a single pose.
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format = TrajectoryFormat::Auto,
                          const std::string& kitti_times_path = "");
// The pose of a TUM file that must hold exactly one (--init manual:FILE): InputError as
// readTrajectory's, or naming the line of a second pose (rather than use the first silently).
StampedPose readSingleTumPose(const std::string& path);
TrajectoryFormat parseTrajectoryFormat(const std::string& name);  // "auto", "tum", "euroc", "kitti"
// What Auto reads `path` as (Tum, Euroc or Kitti); InputError as readTrajectory's.
TrajectoryFormat detectTrajectoryFormat(const std::string& path);

// TUM: "timestamp tx ty tz qx qy qz qw" per line, with a header comment.
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory);
// One TUM line (no newline); shared by the writer and the streaming run recorder.
std::string formatTumLine(const StampedPose& pose);

// Throws InputError(where, ...) unless `seconds` is finite and within 1e11 s of 0 (the year 5138
// since 1970): anything larger is another unit (ns, us or ms since 1970: the message guesses which)
// or garbage, and would print as hundreds of digits.
void checkPlausibleSeconds(double seconds, const std::string& where);

// Splits a text line into numbers at spaces, tabs or commas. Returns false if a field is not a
// number (NaN and infinity are reported by the callers, which know the line).
bool parseNumbers(const std::string& line, std::vector<double>* out);

}  // namespace slamcmp
