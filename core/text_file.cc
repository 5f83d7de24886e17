#include "core/text_file.h"

#include <filesystem>
#include <system_error>

#include "core/error.h"

namespace slamcmp {

// A folder opens as an empty stream, which a trajectory reader would say "holds no pose" and a
// CSV reader would say has the wrong header: say what it is, as the YAML readers do.
std::ifstream openTextFile(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) throw InputError(path, "is a folder, not a text file");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be opened (missing or unreadable)");
  return in;
}

}  // namespace slamcmp
