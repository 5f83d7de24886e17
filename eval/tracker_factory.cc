#include "eval/tracker_factory.h"

#include <functional>
#include <map>

#include "core/error.h"
#include "cslam/cslam_tracker.h"
#include "monoslam_ekf/monoslam_tracker.h"

namespace slamcmp {

namespace {

using Maker = std::function<std::unique_ptr<Tracker>(const TrackerContext&)>;

// One line per back-end.
const std::map<std::string, Maker>& makers() {
  static const std::map<std::string, Maker> m = {
      {"cslam", [](const TrackerContext& c) { return makeCslamTracker(c); }},
      {"monoslam", [](const TrackerContext& c) { return makeMonoslamTracker(c); }},
  };
  return m;
}

}  // namespace

std::vector<std::string> trackerNames() {
  std::vector<std::string> names;
  for (const auto& [name, maker] : makers()) names.push_back(name);
  return names;
}

std::unique_ptr<Tracker> makeTracker(const std::string& name, const TrackerContext& context) {
  const auto it = makers().find(name);
  if (it == makers().end()) {
    std::string known;
    for (const auto& n : trackerNames()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("--backend", "unknown back-end '" + name + "' (known: " + known + ")");
  }
  return it->second(context);
}

}  // namespace slamcmp
