#pragma once
// Opening a text file the user named (a trajectory, an image list, a run's files read back).
#include <fstream>
#include <string>

namespace slamcmp {

// `path` opened for reading; InputError naming it if it is a folder ("is a folder, not a text
// file": a folder would read as an empty file) or cannot be opened.
std::ifstream openTextFile(const std::string& path);

}  // namespace slamcmp
