#pragma once
// Options that explain themselves. An options struct lists its fields once,
//
//   template <class V> void visit(V& v) {
//     v("patch_size", patch_size, "pixels, odd");
//     v("search", search, "active search");   // a nested options struct
//   }
//   void check() const;  // throws InputError naming the field
//
// and from that one list these functions load it from a YAML section (unknown keys and wrong
// types are errors), override single fields (`--set section.key=value`), check every nested struct
// with the full path in messages, write it to JSON (every run records the settings it used) and
// describe it. A check() tests its own scalar fields only and names them as they are spelt in
// visit(); checkOptions walks the nested structs and adds the path:
//   run.yaml: cslam.map_refinement.max_iterations: must be >= 0
// Windows, borders, patches and distances that only the image size can bound (an OpenCV window
// larger than the image allocates without limit or fails an assertion on its region) are checked
// once the first frame's size is known, by the same walk: a struct declares
//   void checkImage(cv::Size image) const;  // throws OptionError naming the field
// and checkOptionsAgainstImage calls it wherever it is nested.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/error.h"
#include "core/yaml.h"

namespace slamcmp {

namespace options_detail {

template <class T, class = void>
struct IsOptionsStruct : std::false_type {};
template <class T>
struct IsOptionsStruct<T, std::void_t<decltype(std::declval<const T&>().check())>> : std::true_type {};

struct Loader {
  const cv::FileNode& section;
  std::string where;
  std::set<std::string> known;

  template <class T>
  void operator()(const char* key, T& value, const char* /*doc*/) {
    known.insert(key);
    const cv::FileNode n = section[key];
    if (n.empty()) return;
    const std::string field = where + "." + key;
    if constexpr (std::is_same_v<T, bool>) {
      value = readBool(n, field);
    } else if constexpr (std::is_integral_v<T>) {
      value = static_cast<T>(readInt(n, field));
    } else if constexpr (std::is_floating_point_v<T>) {
      value = static_cast<T>(readDouble(n, field));
    } else if constexpr (std::is_same_v<T, std::string>) {
      value = readString(n, field);
    } else {
      static_assert(IsOptionsStruct<T>::value, "unsupported option type");
      if (!n.isMap()) throw InputError(field, "must be a map of options");
      Loader inner{n, field, {}};
      value.visit(inner);
      inner.rejectUnknown();
    }
  }

  void rejectUnknown() const {
    for (const auto& key : section.keys())
      if (!known.count(key)) throw InputError(where + "." + key, "unknown option");
  }
};

template <class T, class = void>
struct HasImageCheck : std::false_type {};
template <class T>
struct HasImageCheck<T, std::void_t<decltype(std::declval<const T&>().checkImage(cv::Size()))>> : std::true_type {};

template <class Options>
void checkTree(const Options& options, const std::string& where);
template <class Options>
void checkImageTree(const Options& options, cv::Size image, const std::string& where);

struct Checker {
  const std::string& where;
  template <class T>
  void operator()(const char* key, T& value, const char* /*doc*/) {
    const std::string field = where + "." + key;
    if constexpr (IsOptionsStruct<T>::value) {
      checkTree(value, field);
    } else if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(value)) throw InputError(field, "must be a finite number");
    }
  }
};

template <class Options>
void checkTree(const Options& options, const std::string& where) {
  Options copy = options;  // visit() takes a mutable struct; checking reads only
  Checker checker{where};
  copy.visit(checker);
  try {
    options.check();
  } catch (const OptionError& e) {
    throw InputError(where + "." + e.field(), e.what());
  }
}

struct ImageChecker {
  const std::string& where;
  cv::Size image;
  template <class T>
  void operator()(const char* key, T& value, const char* /*doc*/) {
    if constexpr (IsOptionsStruct<T>::value) checkImageTree(value, image, where + "." + key);
  }
};

template <class Options>
void checkImageTree(const Options& options, cv::Size image, const std::string& where) {
  Options copy = options;
  ImageChecker checker{where, image};
  copy.visit(checker);
  if constexpr (HasImageCheck<Options>::value) {
    try {
      options.checkImage(image);
    } catch (const OptionError& e) {
      throw InputError(where + "." + e.field(), e.what());
    }
  }
}

// A `--set` value as the field's type: the whole text must parse.
template <class T>
T parseScalar(const std::string& text, const std::string& field) {
  if constexpr (std::is_same_v<T, std::string>) {
    return text;
  } else if constexpr (std::is_same_v<T, bool>) {
    if (text == "true" || text == "1") return true;
    if (text == "false" || text == "0") return false;
    throw InputError(field, "must be true or false, got '" + text + "'");
  } else {
    const char* begin = text.c_str();
    char* end = nullptr;
    errno = 0;
    if constexpr (std::is_integral_v<T>) {
      const long long v = std::strtoll(begin, &end, 10);
      if (text.empty() || *end != '\0' || errno == ERANGE || v < std::numeric_limits<T>::min() ||
          v > std::numeric_limits<T>::max())
        throw InputError(field, "must be an integer, got '" + text + "'");
      return static_cast<T>(v);
    } else {
      const double v = std::strtod(begin, &end);
      if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw InputError(field, "must be a finite number, got '" + text + "'");
      return static_cast<T>(v);
    }
  }
}

// Sets the field at `path` (keys joined by '.') from its text, parsed as YAML would parse it.
struct Setter {
  const std::string& path;   // what is left to walk, e.g. "refinement.max_iterations"
  const std::string& text;
  const std::string& field;  // the whole path, for messages
  bool found = false;

  template <class T>
  void operator()(const char* key, T& value, const char* /*doc*/) {
    const std::string k = key;
    if constexpr (IsOptionsStruct<T>::value) {
      if (path.size() > k.size() && path.compare(0, k.size(), k) == 0 && path[k.size()] == '.') {
        const std::string rest = path.substr(k.size() + 1);
        Setter inner{rest, text, field};
        value.visit(inner);
        if (!inner.found) throw InputError(field, "unknown option");
        found = true;
      }
    } else if (path == k) {
      value = parseScalar<T>(text, field);
      found = true;
    }
  }
};

struct JsonWriter {
  nlohmann::json& out;
  template <class T>
  void operator()(const char* key, T& value, const char* /*doc*/) {
    if constexpr (IsOptionsStruct<T>::value) {
      nlohmann::json inner = nlohmann::json::object();
      JsonWriter w{inner};
      value.visit(w);
      out[key] = inner;
    } else {
      out[key] = value;
    }
  }
};

// Sets every integer field called "seed", at any depth: a back-end's random seeds (RANSAC's, the
// EKF's new-feature boxes) are the options it names so, whatever their section.
struct SeedSetter {
  int seed;
  int count = 0;
  template <class T>
  void operator()(const char* key, T& value, const char* /*doc*/) {
    if constexpr (IsOptionsStruct<T>::value) {
      value.visit(*this);
    } else if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
      if (std::string(key) == "seed") {
        value = static_cast<T>(seed);
        ++count;
      }
    }
  }
};

struct Describer {
  std::string& out;
  std::string indent;
  template <class T>
  void operator()(const char* key, T& value, const char* doc) {
    if constexpr (IsOptionsStruct<T>::value) {
      out += indent + key + ":  # " + doc + "\n";
      Describer inner{out, indent + "  "};
      value.visit(inner);
    } else {
      out += indent + key + ": " + nlohmann::json(value).dump() + "  # " + doc + "\n";
    }
  }
};

}  // namespace options_detail

// Checks every nested struct and finite number; a message names `where` and the field's path.
template <class Options>
void checkOptions(const Options& options, const std::string& where) {
  options_detail::checkTree(options, where);
}

// Checks the bounds that depend on the image size (checkImage() of every nested struct); a
// message names `where`, the field's path and the size.
template <class Options>
void checkOptionsAgainstImage(const Options& options, cv::Size image, const std::string& where) {
  options_detail::checkImageTree(options, image, where);
}

// For checkImage(): `value` pixels of `field` must be at most `limit` in `image`-sized frames.
inline void requireWithinImage(const char* field, double value, double limit, cv::Size image) {
  if (value > limit) {
    const auto number = [](double x) {
      std::ostringstream s;
      if (x == std::floor(x) && std::abs(x) < 1e15) s << static_cast<long long>(x); else s << x;
      return s.str();
    };
    throw OptionError(field, "must be at most " + number(limit) + " px for " + std::to_string(image.width) + "x" +
                                 std::to_string(image.height) + " images, got " + number(value));
  }
}

// Loads the fields present in `section` (a YAML map) into `options`, without checking them.
// `where` names the source for messages, e.g. "config.yaml: cslam".
template <class Options>
void readOptions(const cv::FileNode& section, const std::string& where, Options& options) {
  if (section.empty()) return;
  if (!section.isMap()) throw InputError(where, "must be a map of options");
  options_detail::Loader loader{section, where, {}};
  options.visit(loader);
  loader.rejectUnknown();
}

// Sets one field from `--set`: `path` as in the YAML ("refinement.max_iterations"), `text` its
// value. `where` names the section for messages ("--set cslam").
template <class Options>
void setOption(const std::string& path, const std::string& text, const std::string& where, Options& options) {
  const std::string field = where + "." + path;
  options_detail::Setter setter{path, text, field};
  options.visit(setter);
  if (!setter.found) throw InputError(field, "unknown option");
}

// `run --seed N`: every option called "seed" set to N; returns how many there are.
template <class Options>
int setSeeds(int seed, Options& options) {
  options_detail::SeedSetter setter{seed};
  options.visit(setter);
  return setter.count;
}

// readOptions then checkOptions.
template <class Options>
void loadOptions(const cv::FileNode& section, const std::string& where, Options& options) {
  readOptions(section, where, options);
  checkOptions(options, where);
}

template <class Options>
nlohmann::json optionsToJson(const Options& options) {
  nlohmann::json out = nlohmann::json::object();
  options_detail::JsonWriter w{out};
  Options copy = options;  // visit() takes a mutable struct; writing reads only
  copy.visit(w);
  return out;
}

// The options as commented YAML, defaults and units: what `--help` and the docs print.
template <class Options>
std::string describeOptions(const Options& options) {
  std::string out;
  options_detail::Describer d{out, ""};
  Options copy = options;
  copy.visit(d);
  return out;
}

}  // namespace slamcmp
