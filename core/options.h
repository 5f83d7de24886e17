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
// types are errors), write it to JSON (every run records the settings it used) and describe it.
#include <set>
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

// Loads the fields present in `section` (a YAML map) into `options`, then runs its check().
// `where` names the source for messages, e.g. "config.yaml: cslam".
template <class Options>
void loadOptions(const cv::FileNode& section, const std::string& where, Options& options) {
  if (!section.empty()) {
    if (!section.isMap()) throw InputError(where, "must be a map of options");
    options_detail::Loader loader{section, where, {}};
    options.visit(loader);
    loader.rejectUnknown();
  }
  options.check();
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
