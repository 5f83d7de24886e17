#pragma once
// Validated reading of OpenCV FileStorage YAML files: every problem becomes an InputError that
// names the file and the field.
#include <string>

#include <opencv2/core.hpp>

namespace slamcmp {

class YamlFile {
 public:
  // Required: OpenCV's own files (camera.yaml, --config), which must start "%YAML:1.0". Optional:
  // plain YAML without it (a synthetic sequence's info.yaml), read as if it had it.
  enum class Header { Required, Optional };
  // Throws InputError: missing, unreadable, malformed.
  explicit YamlFile(const std::string& path, Header header = Header::Required);

  const std::string& path() const { return path_; }
  bool has(const std::string& key) const;
  cv::FileNode node(const std::string& key) const { return fs_[key]; }
  cv::FileNode root() const { return fs_.root(); }

  int getInt(const std::string& key) const;
  double getDouble(const std::string& key) const;  // finite
  std::string getString(const std::string& key) const;
  cv::Mat getMatrix(const std::string& key) const;  // CV_64F, all finite

 private:
  cv::FileNode required(const std::string& key) const;
  std::string path_;
  cv::FileStorage fs_;
};

// Typed reads of one node, the messages naming `where` (e.g. "file.yaml: cslam.max_features").
int readInt(const cv::FileNode& node, const std::string& where);
double readDouble(const cv::FileNode& node, const std::string& where);
bool readBool(const cv::FileNode& node, const std::string& where);
std::string readString(const cv::FileNode& node, const std::string& where);

}  // namespace slamcmp
