// libFuzzer target: readFramesCsv (a run's frames.csv, read back by compare).
#include "core/error.h"
#include "core/frames_csv.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    slamcmp::readFramesCsv(slamcmp::fuzz::writeInput("frames.csv", data, size));
  } catch (const slamcmp::InputError&) {  // the expected answer to bad input; anything else is a finding
  }
  return 0;
}
