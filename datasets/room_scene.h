#pragma once
// The synthetic presets' scene: a 9x6 chessboard (4 cm squares) on the wall z = 0 of a textured
// room, with boxes standing in front of the wall at varied depths.
#include <cstdint>

#include "datasets/scene.h"

namespace slamcmp {

ChessboardTarget syntheticTarget();

// Textures are drawn from `seed`; the geometry is the same for every seed.
Scene buildRoomScene(std::uint64_t seed);

}  // namespace slamcmp
