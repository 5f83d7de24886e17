#pragma once
// The one place that knows the back-ends: a factory keyed by name.
#include <memory>
#include <string>
#include <vector>

#include "core/tracker.h"

namespace slamcmp {

// Names accepted by makeTracker, e.g. {"cslam", "monoslam"}.
std::vector<std::string> trackerNames();
// Throws InputError for an unknown name or a context the back-end cannot work with.
std::unique_ptr<Tracker> makeTracker(const std::string& name, const TrackerContext& context);

}  // namespace slamcmp
