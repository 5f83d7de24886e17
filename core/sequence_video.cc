// A video file, through the media plugin (OpenCV videoio); timestamps from its frame rate.
#include <cmath>

#include "core/error.h"
#include "core/image.h"
#include "core/media_plugin.h"
#include "core/sequence_format.h"
#include "core/text_file.h"

namespace fs = std::filesystem;

namespace slamcmp {

namespace {

class VideoSource : public FrameSource {
 public:
  VideoSource(const std::string& path, std::unique_ptr<VideoReader> video, int count, double fps)
      : path_(path), video_(std::move(video)), count_(count), fps_(fps) {}
  int size() const override { return count_; }
  bool claim(Frame* frame) override {  // decodes too: a video's frames come in order
    cv::Mat img;
    if (!video_->read(img)) return false;
    frame->index = index_;
    frame->timestamp = index_ / fps_;
    frame->source = path_ + " frame " + std::to_string(index_);
    ++index_;
    // A fresh image each frame: converting into frame->grey would overwrite, in place, the
    // previous frame a caller still holds (e.g. for optical flow).
    frame->grey = toGrey(img);
    return true;
  }

 private:
  std::string path_;
  std::unique_ptr<VideoReader> video_;
  int count_;
  double fps_;
  int index_ = 0;
};

// Any file: whether it is a video only opening it tells.
class VideoFormat : public SequenceFormat {
 public:
  std::string name() const override { return "video"; }
  bool detect(const fs::path& path) const override {
    std::error_code ec;
    return !fs::is_directory(path, ec);
  }
  Sequence open(const fs::path& path, const SequenceOpenOptions& /*options*/) const override {
    const std::string file = path.string();
    // FFmpeg opens a text file too (its tty demuxer draws the text as 640x400 frames), and the
    // camera file's size was then blamed.
    const std::string extension = lowerExtension(file);
    for (const char* text : {".txt", ".csv", ".yaml", ".yml", ".json", ".md"})
      if (extension == text)
        throw InputError(file, "is a text file, not a video: for a TUM or EuRoC sequence give its folder");
    auto video = mediaPlugin(file).openVideo(file);
    if (!video) throw InputError(file, "is neither a sequence folder nor a video OpenCV can open");
    const double fps = video->fps();
    const int count = video->frameCount();
    Sequence seq;
    seq.image_size = video->frameSize();
    if (seq.image_size.area() <= 0) throw InputError(file, "video has no frames");
    seq.fps = fps > 0 && std::isfinite(fps) ? fps : 30.0;
    seq.frames = std::make_unique<VideoSource>(file, std::move(video), count > 0 ? count : -1, seq.fps);
    return seq;
  }
};

}  // namespace

const SequenceFormat& videoFormat() {
  static const VideoFormat format;
  return format;
}

}  // namespace slamcmp
