#include "core/frames_csv.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/format_string.h"
#include "core/text_file.h"

namespace slamcmp {

const char* framesCsvHeader() { return "frame,timestamp,status,ms,cpu_ms,decode_ms,features,measured"; }

std::string formatFrameRow(const FrameRow& r) {
  return formatString("%d,%.6f,%s,%.4f,%.4f,%.4f,%d,%d\n", r.frame, r.timestamp,
                      statusLabel(r.status, r.source).c_str(), r.ms, r.cpu_ms, r.decode_ms, r.features, r.measured);
}

void parseStatusColumn(const std::string& s, const std::string& where, FrameRow* row) {
  row->source.clear();
  if (s == toString(TrackStatus::Initialising)) {
    row->status = TrackStatus::Initialising;
  } else if (s == toString(TrackStatus::Lost)) {
    row->status = TrackStatus::Lost;
  } else if (!s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return std::islower(c) || c == '_'; })) {
    row->status = TrackStatus::Tracked;
    row->source = s;
  } else {
    throw InputError(where, "status '" + s + "' is neither initialising, lost nor a pose source");
  }
}

std::vector<FrameRow> readFramesCsv(const std::string& path) {
  std::ifstream in = openTextFile(path);  // a folder would have the wrong header
  std::string line;
  if (!std::getline(in, line) || line.rfind(framesCsvHeader(), 0) != 0)
    throw InputError(atLine(path, 1), std::string("header must be '") + framesCsvHeader() + "'");
  std::vector<FrameRow> rows;
  int n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::string field[8];
    int k = 0;
    while (k < 8 && std::getline(ss, field[k], ',')) ++k;
    if (k != 8) throw InputError(atLine(path, n), "expected 8 comma-separated fields");
    FrameRow r;
    try {
      r.frame = std::stoi(field[0]);
      r.timestamp = std::stod(field[1]);
      r.ms = std::stod(field[3]);
      r.cpu_ms = std::stod(field[4]);
      r.decode_ms = std::stod(field[5]);
      r.features = std::stoi(field[6]);
      r.measured = std::stoi(field[7]);
    } catch (const std::exception&) {
      throw InputError(atLine(path, n), "a field is not a number");
    }
    parseStatusColumn(field[2], atLine(path, n), &r);
    rows.push_back(r);
  }
  return rows;
}

}  // namespace slamcmp
