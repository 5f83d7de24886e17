#include "core/media_plugin.h"

#include <dlfcn.h>

#include <cstdlib>
#include <mutex>

#include "core/error.h"

namespace slamcmp {

namespace {

std::string pluginPath() {
  const char* path = std::getenv("SLAMCMP_MEDIA_PLUGIN");
  return path && *path ? path : SLAMCMP_MEDIA_PLUGIN_PATH;  // set by core/CMakeLists.txt
}

}  // namespace

const MediaPlugin& mediaPlugin(const std::string& needed_for) {
  static std::once_flag once;
  static const MediaPlugin* plugin = nullptr;
  static std::string failure;
  std::call_once(once, [] {
    const std::string path = pluginPath();
    // Never closed: its objects and OpenCV's back-ends live until the process ends.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      failure = "needs the video and window plugin, which could not be loaded (" +
                (why ? why : path + ": unknown error") + "); set SLAMCMP_MEDIA_PLUGIN to its path";
      return;
    }
    using Entry = const MediaPlugin* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(handle, kMediaPluginEntry));
    if (!entry) {
      failure = "needs the video and window plugin, but " + path + " has no " + kMediaPluginEntry;
      return;
    }
    plugin = entry();
  });
  if (!plugin) throw InputError(needed_for, failure);
  return *plugin;
}

}  // namespace slamcmp
