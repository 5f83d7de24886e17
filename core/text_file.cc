#include "core/text_file.h"

#include <cctype>
#include <filesystem>
#include <system_error>

#include "core/error.h"

namespace slamcmp {

// A folder opens as a stream whose reads fail (a trajectory would "hold no pose", a CSV file
// have the wrong header, a JSON file throw "Is a directory" naming no file): say what it is, as
// the YAML readers do.
std::ifstream openTextFile(const std::string& path, std::ios::openmode mode) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) throw InputError(path, "is a folder, not a text file");
  std::ifstream in(path, mode);
  if (!in) throw InputError(path, "cannot be opened (missing or unreadable)");
  return in;
}

nlohmann::json readJsonFile(const std::string& path) {
  std::ifstream in = openTextFile(path);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, std::string("not JSON: ") + e.what());
  }
}

bool isEntryOf(const std::string& path, const std::string& folder) {
  const std::filesystem::path p = path;
  const std::string name = p.filename().string();
  return !p.has_root_path() && p.parent_path() == folder && !name.empty() && name != "." && name != "..";
}

std::string lowerExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

void dropByteOrderMark(std::string* first_line) {
  if (first_line->rfind("\xEF\xBB\xBF", 0) == 0) first_line->erase(0, 3);
}

}  // namespace slamcmp
