#pragma once
// The EKF state's tail (EkfState::appendToTail) as hybrid's tracked motion fills it: cloned camera
// poses and tracked points, in the order they were appended, each addressed by its kind and id.
// Offsets are counted from the tail's start, so the map's features may come and go before it.
#include <vector>

#include "ekf/ekf_state.h"

namespace slamcmp {

class TailLayout {
 public:
  enum class Kind { kClone, kPoint };

  // A block just appended to the state's tail.
  void push(Kind kind, int id, int dim) { blocks_.push_back({kind, id, dim}); }
  // The block's state offset; -1 when it is not in the tail.
  int offset(const EkfState& state, Kind kind, int id) const;
  // Its rows and columns removed from the state.
  void remove(EkfState& state, Kind kind, int id);
  // The tail's blocks removed from the state, and forgotten.
  void clear(EkfState& state);
  // Whether the state's tail is the one recorded here (not after the filter restarted).
  bool matches(const EkfState& state) const;

 private:
  struct Block {
    Kind kind;
    int id;
    int dim;
  };
  // The block's index and offset; index -1 when it is absent.
  std::pair<int, int> find(const EkfState& state, Kind kind, int id) const;
  std::vector<Block> blocks_;
};

}  // namespace slamcmp
