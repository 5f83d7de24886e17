#pragma once
// Opening a file the user named (a trajectory, an image list, a PLY map, a run's files read back
// by compare --collect), and telling its kind by its name.
#include <fstream>
#include <ios>
#include <string>

#include <nlohmann/json.hpp>

namespace slamcmp {

// `path` opened for reading (`mode` may add std::ios::binary); InputError naming it if it is a
// folder ("is a folder, not a text file": a folder would read as an empty file, or throw from
// the stream's first read) or cannot be opened.
std::ifstream openTextFile(const std::string& path, std::ios::openmode mode = std::ios::in);

// A JSON file read whole (a run's summary.json, a compare's plan.json): InputError naming it if it
// cannot be opened (openTextFile) or is not JSON.
nlohmann::json readJsonFile(const std::string& path);

// A file's first line without a UTF-8 byte-order mark (a file saved by Windows Notepad as "UTF-8"):
// it is no part of the first field.
void dropByteOrderMark(std::string* first_line);

// Whether `path` names an entry right inside `folder`, both relative ("runs/tv1-cslam" in "runs"):
// what a program may remove of what a file it reads back (a plan, a report) says it wrote, and no
// "..", ".", absolute path or deeper entry.
bool isEntryOf(const std::string& path, const std::string& folder);

// The file name's extension in lower case, with its dot (".csv", ".png"; "" if none).
std::string lowerExtension(const std::string& path);

}  // namespace slamcmp
