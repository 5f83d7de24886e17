#pragma once
// Image sequences: a TUM-style folder (rgb.txt), a plain folder of images, a video file, or an
// EuRoC camera folder (one file each: core/sequence_format.h); with the camera, target and ground
// truth found beside them (SPEC section 3).
#include <memory>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/target.h"
#include "core/trajectory.h"

namespace slamcmp {

struct Frame {
  int index = 0;         // 0-based position in the sequence
  double timestamp = 0;  // seconds
  cv::Mat grey;          // CV_8UC1; empty when the frame could not be decoded
  std::string source;    // the image file, or "video frame N", for messages
  std::string decode_error;  // why `grey` is empty, when the decoder said ("the file is cut short")
};

// Sequential access to the frames; implementations decode on demand.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Number of frames, or -1 when the container does not say (some videos).
  virtual int size() const = 0;
  // The next frame, false at the end. A frame whose image cannot be decoded is returned with an
  // empty `grey` (the caller skips and reports it); an image of another size than the sequence's
  // throws InputError.
  bool next(Frame* frame) {
    if (!claim(frame)) return false;
    decode(frame);
    return true;
  }
  // next() in two steps, so that frames decode on several threads at once (FramePrefetcher):
  // claim() hands out the next frame in order, with its image when the source must decode in order
  // (a video), without it otherwise (image files); decode() then fills it in, from any thread.
  virtual bool claim(Frame* frame) = 0;
  virtual void decode(Frame* /*frame*/) const {}
};

struct Sequence {
  std::string path;  // what the user named
  std::string name;  // short name for output folders
  std::string kind;  // the SequenceFormat's name: "tum", "euroc", "images", "video"
  cv::Size image_size;
  double fps = 30;   // the video's rate, or from the median spacing of the frames' timestamps
  std::unique_ptr<FrameSource> frames;
  std::optional<CameraModel> camera;        // camera.yaml, or --camera
  std::optional<ChessboardTarget> target;   // target.yaml, or --target
  std::optional<Trajectory> groundtruth;    // groundtruth.txt (EuRoC: body poses moved to cam0)
  std::string camera_path, target_path, groundtruth_path;  // where they came from ("" if none)
};

struct SequenceOpenOptions {
  std::string camera_path;  // overrides camera.yaml beside the sequence
  std::string target_path;  // overrides target.yaml beside the sequence
  double images_fps = 30.0;  // timestamps for a plain image folder (frame index / fps)
  bool allow_symmetric_target = false;  // calibrate and run: see ChessboardTarget::symmetric
  // An interrupt (core/interrupt.h) ends the reading of a long image list; compare's collect, which
  // reads the sequences after its runs were interrupted, reads on.
  bool stop_on_interrupt = true;
  // compare's collect needs a sequence's frame count, ground truth and scene, not its images, which
  // a cluster's user may have deleted to free the disk: false reads an image list without looking
  // for its files. The image size is then unknown (0x0) and the camera and target are not checked
  // against it; a folder of images and a video are still their files.
  bool read_images = true;
  // calibrate makes the camera file: the sequence's own (camera.yaml, EuRoC's sensor.yaml) is not
  // read, so a broken one can be replaced. EuRoC's ground truth is then the body's, not the
  // camera's (sensor.yaml's T_BS is not read either): for calibrate only.
  bool read_camera = true;
};

// Throws InputError for anything missing or malformed; reads the first frame to learn (and check)
// the image size.
Sequence openSequence(const std::string& path, const SequenceOpenOptions& options = {});

// "" if `fps`, a sequence's rate (a video's, or implied by its frames' timestamps), is one a video
// can have; else why not, with the factor when the timestamps look like another unit than seconds:
// "the frames' timestamps imply 3e-08 fps: they look like nanoseconds (1e+09 times seconds)".
std::string implausibleFrameRate(double fps);

// Grey 8-bit image from any image OpenCV reads (colour, grey, 16-bit); empty if it cannot, with
// the reason in `why` when given (e.g. "the file is cut short", or the decoder's own complaint
// "libpng error: IDAT: invalid code lengths set"). An image
// the decoder complains about is not returned half decoded; only libpng's warnings about extra
// chunks (iCCP, tEXt) leave the pixels whole.
cv::Mat readGreyImage(const std::string& path, std::string* why = nullptr);

// What was written to stderr while one image was decoded, sorted: stderr is the process's, so
// other threads' lines (the tracker's, a library's log) may be among the decoder's. `complaint`:
// libpng's first error or libjpeg's first word of corrupt data (the pixels are not whole);
// `others`: the lines neither decoder wrote (to be written to stderr again), libpng's warnings
// about extra chunks dropped.
struct DecoderMessages {
  std::string complaint;
  std::string others;
};
DecoderMessages sortDecoderMessages(const std::string& said);

}  // namespace slamcmp
