// libFuzzer target: readTargetYaml (target.yaml, OpenCV FileStorage).
#include "core/error.h"
#include "core/target.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    slamcmp::readTargetYaml(slamcmp::fuzz::writeInput("target.yaml", data, size));
  } catch (const slamcmp::InputError&) {  // the expected answer to bad input; anything else is a finding
  }
  return 0;
}
