#include "hybrid/tail_layout.h"

namespace slamcmp {

std::pair<int, int> TailLayout::find(const EkfState& state, Kind kind, int id) const {
  int offset = state.size() - state.tailSize();
  for (size_t i = 0; i < blocks_.size(); ++i) {
    if (blocks_[i].kind == kind && blocks_[i].id == id) return {static_cast<int>(i), offset};
    offset += blocks_[i].dim;
  }
  return {-1, -1};
}

int TailLayout::offset(const EkfState& state, Kind kind, int id) const { return find(state, kind, id).second; }

void TailLayout::remove(EkfState& state, Kind kind, int id) {
  const auto [index, offset] = find(state, kind, id);
  if (index < 0) return;
  state.remove(offset, blocks_[index].dim);
  blocks_.erase(blocks_.begin() + index);
}

void TailLayout::clear(EkfState& state) {
  if (state.tailSize() > 0) state.remove(state.size() - state.tailSize(), state.tailSize());
  blocks_.clear();
}

bool TailLayout::matches(const EkfState& state) const {
  int dim = 0;
  for (const Block& b : blocks_) dim += b.dim;
  return dim == state.tailSize();
}

}  // namespace slamcmp
