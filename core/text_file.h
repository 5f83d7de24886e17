#pragma once
// Opening a file the user named (a trajectory, an image list, a PLY map, a run's files read back
// by compare --collect), and telling its kind by its name.
#include <fstream>
#include <ios>
#include <string>

namespace slamcmp {

// `path` opened for reading (`mode` may add std::ios::binary); InputError naming it if it is a
// folder ("is a folder, not a text file": a folder would read as an empty file, or throw from
// the stream's first read) or cannot be opened.
std::ifstream openTextFile(const std::string& path, std::ios::openmode mode = std::ios::in);

// A file's first line without a UTF-8 byte-order mark (a file saved by Windows Notepad as "UTF-8"):
// it is no part of the first field.
void dropByteOrderMark(std::string* first_line);

// The file name's extension in lower case, with its dot (".csv", ".png"; "" if none).
std::string lowerExtension(const std::string& path);

}  // namespace slamcmp
