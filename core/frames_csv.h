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
  double ms = 0;         // back-end time, decoding excluded
  double decode_ms = 0;  // image decoding
  int features = 0;
  int measured = 0;
};

const char* framesCsvHeader();  // "frame,timestamp,status,ms,decode_ms,features,measured"
std::string formatFrameRow(const FrameRow& row);  // with a trailing newline
std::vector<FrameRow> readFramesCsv(const std::string& path);  // InputError naming file:line
TrackStatus parseTrackStatus(const std::string& s, const std::string& where);

}  // namespace slamcmp
