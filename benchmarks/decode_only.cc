// The whole-run baseline of scripts/bench.sh: a process that only decodes a sequence's frames, one
// after the other, as `slamcmp run` reads them (openSequence), so that both are timed the same way,
// process start and library loading included.
//   decode_only SEQUENCE
#include <cstdio>
#include <exception>

#include "core/frame_memory.h"
#include "core/sequence.h"

int main(int argc, char** argv) {
  slamcmp::keepFreedMemoryForReuse();  // as slamcmp does, before the decoding threads start
  if (argc != 2) {
    std::fprintf(stderr, "usage: decode_only SEQUENCE\n");
    return 2;
  }
  try {
    slamcmp::Sequence seq = slamcmp::openSequence(argv[1]);
    slamcmp::Frame frame;
    int frames = 0;
    while (seq.frames->next(&frame)) frames += !frame.grey.empty();
    std::printf("%d frames decoded\n", frames);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "decode_only: %s\n", e.what());
    return 2;
  }
  return 0;
}
