#include "eval/overlay/overlay_writer.h"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/run_files.h"
#include "core/sequence.h"
#include "core/text_file.h"

namespace slamcmp {

namespace {

namespace fs = std::filesystem;

// FourCC for a video container, or "" when `extension` (lower case, with the dot) is none.
std::string videoFourcc(const std::string& extension) {
  if (extension == ".avi") return "MJPG";
  if (extension == ".mp4" || extension == ".mkv") return "mp4v";
  return "";
}

void createFolder(const fs::path& folder, const std::string& path) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec || !fs::is_directory(folder))
    throw InputError(path, "cannot be created" + (ec ? " (" + ec.message() + ")" : std::string()));
}

}  // namespace

OverlayWriter::OverlayWriter(const std::string& path, cv::Size image_size, double fps) : path_(path) {
  const fs::path p(path);
  const std::string extension = lowerExtension(path);
  std::error_code ec;
  const bool png_folder = fs::is_directory(p, ec) || extension.empty();
  if (png_folder) {
    createFolder(p, path);
    csv_path_ = (p / run_files::kOverlay).string();
  } else {
    const std::string fourcc = videoFourcc(extension);
    if (fourcc.empty())
      throw InputError(path, "'" + extension +
                                 "' is not a supported video container: use .avi, .mp4, .mkv, or a folder name "
                                 "without an extension for PNG frames");
    if (const std::string why = implausibleFrameRate(fps); !why.empty())
      throw InputError(path, "cannot be written as a video: " + why);
    if (p.has_parent_path()) createFolder(p.parent_path(), path);
    video_ = mediaPlugin(path).createVideo(path, fourcc, fps, image_size);
    if (!video_) throw InputError(path, "cannot be written as a video");
    csv_path_ = path + ".csv";
  }
  csv_.open(csv_path_);
  if (!csv_) throw InputError(csv_path_, "cannot be written");
  csv_ << "frame,kind,id,u,v,state\n";
}

void OverlayWriter::write(int frame_index, const cv::Mat& image, const std::vector<DrawnPrimitive>& drawn) {
  if (video_) {
    video_->write(image);
  } else {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", frame_index);
    const std::string file = (fs::path(path_) / name).string();
    bool written = false;
    try {
      written = cv::imwrite(file, image);
    } catch (const cv::Exception&) {
    }
    if (!written) throw InputError(file, "cannot be written");
  }
  for (const auto& d : drawn) {
    char uv[64];
    std::snprintf(uv, sizeof uv, "%.3f,%.3f", d.uv.x(), d.uv.y());
    csv_ << frame_index << ',' << d.kind << ',' << d.id << ',' << uv << ',' << d.state << '\n';
  }
  if (!csv_) throw InputError(csv_path_, "cannot be written");
}

}  // namespace slamcmp
