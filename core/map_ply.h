#pragma once
// map.ply (SPEC section 4): a run's map points in the world frame, as PLY that MeshLab,
// CloudCompare and Open3D read. The reader takes what writeMapPly writes and PLY point clouds in
// general (ascii, binary_little_endian, binary_big_endian; any vertex properties beside x y z).
#include <string>
#include <vector>

#include "core/tracker.h"

namespace slamcmp {

// PLY (ascii) with x y z, id, observations and sigma per point. Throws InputError if the file
// cannot be written.
void writeMapPly(const std::string& path, const std::vector<MapPoint>& points);

// The vertices of a PLY file. `id`, `observations` and `sigma` are read when the vertex element
// has them (any numeric type); otherwise id is the vertex index, observations 0 and sigma -1.
// Throws InputError naming the file and the header line, data line (ascii) or vertex (binary)
// for anything malformed, cut short or not finite.
std::vector<MapPoint> readMapPly(const std::string& path);

}  // namespace slamcmp
