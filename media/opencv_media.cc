// The slamcmp_media plugin: core/media_plugin.h's interfaces on OpenCV's videoio and highgui.
#include <opencv2/highgui.hpp>
#include <opencv2/videoio.hpp>

#include "core/media_plugin.h"

namespace slamcmp {

namespace {

class OpenCvVideoReader : public VideoReader {
 public:
  explicit OpenCvVideoReader(cv::VideoCapture capture) : capture_(std::move(capture)) {}
  bool read(cv::Mat& bgr) override {
    try {
      return capture_.read(bgr) && !bgr.empty();
    } catch (const cv::Exception&) {
      return false;
    }
  }
  double fps() const override { return capture_.get(cv::CAP_PROP_FPS); }
  int frameCount() const override { return static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_COUNT)); }
  cv::Size frameSize() const override {
    return {static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_WIDTH)),
            static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_HEIGHT))};
  }

 private:
  cv::VideoCapture capture_;
};

class OpenCvVideoWriter : public VideoWriter {
 public:
  explicit OpenCvVideoWriter(cv::VideoWriter writer) : writer_(std::move(writer)) {}
  void write(const cv::Mat& bgr) override { writer_.write(bgr); }

 private:
  cv::VideoWriter writer_;
};

class OpenCvWindow : public ImageWindow {
 public:
  explicit OpenCvWindow(std::string title) : title_(std::move(title)) {
    cv::namedWindow(title_, cv::WINDOW_AUTOSIZE);
  }
  ~OpenCvWindow() override { cv::destroyWindow(title_); }
  int show(const cv::Mat& image) override {
    cv::imshow(title_, image);
    return cv::waitKey(1);
  }
  bool visible() const override { return cv::getWindowProperty(title_, cv::WND_PROP_VISIBLE) >= 1; }

 private:
  std::string title_;
};

class OpenCvMedia : public MediaPlugin {
 public:
  std::unique_ptr<VideoReader> openVideo(const std::string& path) const override {
    // Only the back-ends that read files: CAP_ANY would go on to the camera back-ends, and
    // gphoto2's probe of USB cameras took a second for every file that is not a video.
    for (const int api : {cv::CAP_FFMPEG, cv::CAP_GSTREAMER, cv::CAP_OPENCV_MJPEG}) {
      cv::VideoCapture capture;
      try {
        capture.open(path, api);
      } catch (const cv::Exception&) {
      }
      if (capture.isOpened()) return std::make_unique<OpenCvVideoReader>(std::move(capture));
    }
    return nullptr;
  }

  std::unique_ptr<VideoWriter> createVideo(const std::string& path, const std::string& fourcc, double fps,
                                           cv::Size size) const override {
    if (fourcc.size() != 4) return nullptr;
    cv::VideoWriter writer;
    try {
      writer.open(path, cv::CAP_FFMPEG, cv::VideoWriter::fourcc(fourcc[0], fourcc[1], fourcc[2], fourcc[3]), fps,
                  size, true);
    } catch (const cv::Exception&) {
    }
    if (!writer.isOpened()) return nullptr;
    return std::make_unique<OpenCvVideoWriter>(std::move(writer));
  }

  std::unique_ptr<ImageWindow> openWindow(const std::string& title) const override {
    return std::make_unique<OpenCvWindow>(title);
  }
};

}  // namespace

}  // namespace slamcmp

extern "C" __attribute__((visibility("default"))) const slamcmp::MediaPlugin* slamcmp_media_plugin() {
  static const slamcmp::OpenCvMedia media;
  return &media;
}
