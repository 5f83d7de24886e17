#include "core/frames_csv.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/format_string.h"
#include "core/text_file.h"

namespace slamcmp {

namespace {

// The columns every frames.csv has had; `reason` came after them (session 42).
constexpr const char* kNumberedColumns = "frame,timestamp,status,ms,cpu_ms,decode_ms,features,measured";

// RFC 4180: in double quotes, a quote doubled; one line (a line break would end the row).
std::string quotedField(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += "\"\"";
    else out += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return out + "\"";
}

// The reason column as written by quotedField (or bare, as a spreadsheet may save it).
std::string unquotedField(const std::string& field, const std::string& where) {
  if (field.empty() || field[0] != '"') return field;
  std::string out;
  size_t i = 1;
  for (; i < field.size(); ++i) {
    if (field[i] != '"') {
      out += field[i];
    } else if (i + 1 < field.size() && field[i + 1] == '"') {
      out += '"';
      ++i;
    } else {
      break;
    }
  }
  if (i + 1 != field.size()) throw InputError(where, "the reason's quotes do not close at the end of the row");
  return out;
}

}  // namespace

const char* framesCsvHeader() { return "frame,timestamp,status,ms,cpu_ms,decode_ms,features,measured,reason"; }

std::string formatFrameRow(const FrameRow& r) {
  return formatString("%d,%.6f,%s,%.4f,%.4f,%.4f,%d,%d,%s\n", r.frame, r.timestamp,
                      statusLabel(r.status, r.source).c_str(), r.ms, r.cpu_ms, r.decode_ms, r.features, r.measured,
                      r.reason.empty() ? "" : quotedField(r.reason).c_str());
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
  if (!std::getline(in, line) || line.rfind(kNumberedColumns, 0) != 0)
    throw InputError(atLine(path, 1), std::string("header must be '") + framesCsvHeader() + "' (or, written before " +
                                          "the reason column, '" + kNumberedColumns + "')");
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
    std::string reason;
    std::getline(ss, reason);  // the rest of the row, commas and all
    if (!reason.empty() && reason.back() == '\r') reason.pop_back();
    r.reason = unquotedField(reason, atLine(path, n));
    rows.push_back(r);
  }
  return rows;
}

}  // namespace slamcmp
