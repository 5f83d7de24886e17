// libFuzzer target: a --config options file, through the registry's loadBackendOptions for every
// back-end (each reads its own section; a section naming no back-end is refused), then the bounds
// that need the image size (BackendOptions::checkAgainstImage) for a small and a large image.
#include "core/error.h"
#include "eval/app/backends.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace slamcmp;
  const std::string path = fuzz::writeInput("config.yaml", data, size);
  for (const BackendRegistration& backend : backends()) {
    try {
      const std::unique_ptr<BackendOptions> options = loadBackendOptions(backend, path, {});
      for (const cv::Size image : {cv::Size(160, 120), cv::Size(1920, 1080)})
        options->checkAgainstImage(image, path + ": " + backend.name);
    } catch (const InputError&) {  // the expected answer to bad input; anything else is a finding
    }
  }
  return 0;
}
