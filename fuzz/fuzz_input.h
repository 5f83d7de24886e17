#pragma once
// Shared by the libFuzzer targets: each writes the fuzzer's bytes to a file in a private folder
// and hands the path to the real reader (the parsers read files; one implementation is fuzzed).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace slamcmp::fuzz {

// A folder of this process's own, removed at exit.
inline const std::filesystem::path& workDir() {
  static const struct Dir {
    std::filesystem::path path;
    Dir() : path(std::filesystem::temp_directory_path() / ("slamcmp-fuzz-" + std::to_string(getpid()))) {
      std::filesystem::create_directories(path);
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  } dir;
  return dir.path;
}

// Writes bytes to workDir()/name and returns the path.
inline std::string writeInput(const std::string& name, const uint8_t* data, size_t size) {
  const std::filesystem::path p = workDir() / name;
  std::filesystem::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p.string();
}

}  // namespace slamcmp::fuzz
