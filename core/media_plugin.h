#pragma once
// Video files and windows, from OpenCV's videoio and highgui, loaded on first use from the
// slamcmp_media plugin (media/). Those two libraries bring about 120 shared libraries (FFmpeg,
// GStreamer, Qt) whose loading took 0.1 s of every process's start, most runs read image files,
// and the rest of the code never names them.
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace slamcmp {

class VideoReader {
 public:
  virtual ~VideoReader() = default;
  virtual bool read(cv::Mat& bgr) = 0;  // false at the end or on a read error
  virtual double fps() const = 0;       // 0 when the container does not say
  virtual int frameCount() const = 0;   // 0 or less when the container does not say
  virtual cv::Size frameSize() const = 0;
};

class VideoWriter {
 public:
  virtual ~VideoWriter() = default;
  virtual void write(const cv::Mat& bgr) = 0;
};

class ImageWindow {
 public:
  virtual ~ImageWindow() = default;
  // Shows `image`, lets the window handle its events for 1 ms, returns the key pressed or -1.
  virtual int show(const cv::Mat& image) = 0;
  virtual bool visible() const = 0;  // false once the user closed it
};

// What the plugin provides. Each function returns null where OpenCV cannot open the file.
class MediaPlugin {
 public:
  virtual ~MediaPlugin() = default;
  virtual std::unique_ptr<VideoReader> openVideo(const std::string& path) const = 0;
  // `fourcc`: four characters ("MJPG"); written with FFmpeg (the other back-ends print warnings of
  // their own before failing).
  virtual std::unique_ptr<VideoWriter> createVideo(const std::string& path, const std::string& fourcc,
                                                   double fps, cv::Size size) const = 0;
  virtual std::unique_ptr<ImageWindow> openWindow(const std::string& title) const = 0;
};

// Loads the plugin once (thread-safe): $SLAMCMP_MEDIA_PLUGIN if set, else the one this build made.
// Throws InputError naming `needed_for` (the video file, or the option) when it cannot be loaded.
const MediaPlugin& mediaPlugin(const std::string& needed_for);

// The plugin's one exported symbol, `extern "C"`, returning a MediaPlugin that lives as long as
// the process.
constexpr const char* kMediaPluginEntry = "slamcmp_media_plugin";

}  // namespace slamcmp
