// libFuzzer target: readCameraYaml (camera.yaml, OpenCV FileStorage).
#include "core/camera.h"
#include "core/error.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    slamcmp::readCameraYaml(slamcmp::fuzz::writeInput("camera.yaml", data, size));
  } catch (const slamcmp::InputError&) {  // the expected answer to bad input; anything else is a finding
  }
  return 0;
}
