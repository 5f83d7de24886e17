#pragma once
// frames.csv (SPEC section 4): one row a frame, written by RunRecorder, read by eval.
#include <string>
#include <vector>

#include "core/tracker.h"

namespace slamcmp {

struct FrameRow {
  int frame = 0;
  double timestamp = 0;
  TrackStatus status = TrackStatus::Lost;
  std::string source;    // Tracked: the pose's source, written in the status column
  double ms = 0;         // back-end wall time, decoding excluded
  double cpu_ms = 0;     // the tracking thread's CPU time for the frame (stable on a loaded machine)
  double decode_ms = 0;  // image decoding
  int features = 0;
  int measured = 0;
  // Why the frame is lost or initialising, or a note on a posed one ("no feature matched:
  // prediction only"); empty otherwise. Quoted in the file (it may hold commas).
  std::string reason;
};

// "frame,timestamp,status,ms,cpu_ms,decode_ms,features,measured,reason"
const char* framesCsvHeader();
std::string formatFrameRow(const FrameRow& row);  // with a trailing newline
// InputError naming file:line. Files written before the reason column are read too.
std::vector<FrameRow> readFramesCsv(const std::string& path);
// The status column: "initialising", "lost", or else the source of a tracked frame's pose (a
// lower-case word: "board", "two_view", "ekf").
void parseStatusColumn(const std::string& s, const std::string& where, FrameRow* row);

}  // namespace slamcmp
