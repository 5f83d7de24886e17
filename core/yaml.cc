#include "core/yaml.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <system_error>
#include <vector>

#include <yaml.h>

#include "core/error.h"
#include "core/text_file.h"

namespace slamcmp {

namespace {

// libyaml checks the syntax before OpenCV parses: OpenCV 4.6's parser loops forever on some
// malformed files (fuzz/known_hangs). OpenCV's header "%YAML:1.0" is not YAML's "%YAML 1.1".
// The same pass finds a key written twice in one mapping: OpenCV keeps the first silently.
struct YamlProblem {
  std::string where;  // "" or the dotted path of the key concerned, e.g. "cslam.board.track"
  std::string what;   // "" when the text is well-formed YAML without repeated keys
};

// False for an integer OpenCV would wrap: its parser reads one with strtol (any base) and keeps
// the low 32 bits, so 4294967305 becomes 9 and 2147483648 a negative number. Anything else
// (a real, a string) is true here; its type is checked where it is read.
bool fitsOpenCvInt(const std::string& value) {
  const char* begin = value.c_str();
  const char* digits = begin + (*begin == '-' || *begin == '+');
  if (!std::isdigit(static_cast<unsigned char>(*digits))) return true;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(begin, &end, 0);
  if (*end != '\0') return true;  // a real ("1e3", "2.5") or not a number
  return errno != ERANGE && v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max();
}

YamlProblem yamlSyntaxProblem(std::string text) {
  int added_lines = 0;  // lines inserted above the text: subtracted from libyaml's line numbers
  if (text.rfind("%YAML:", 0) == 0) {
    // OpenCV also reads the header without a "---" after it; YAML needs one after a directive.
    const size_t eol = text.find('\n');
    const bool has_start = eol != std::string::npos && text.compare(eol + 1, 3, "---") == 0;
    text.replace(0, eol, has_start ? "%YAML 1.1" : "%YAML 1.1\n---");
    if (!has_start) added_lines = 1;
  }
  yaml_parser_t parser;
  if (!yaml_parser_initialize(&parser)) return {};  // out of memory: leave the check to OpenCV
  yaml_parser_set_input_string(&parser, reinterpret_cast<const unsigned char*>(text.data()), text.size());
  // The open collections, innermost last: a mapping alternates key and value nodes.
  struct Level {
    bool mapping = false;
    bool expect_key = true;
    std::string path;                  // dotted path of this collection
    std::string key;                   // the key whose value comes next
    std::map<std::string, int> lines;  // key -> line it was first written on
  };
  std::vector<Level> open;
  const auto lineOf = [&](const yaml_mark_t& mark) {
    return static_cast<int>(mark.line) + 1 - added_lines;
  };
  YamlProblem problem;
  for (;;) {
    yaml_event_t event;
    if (!yaml_parser_parse(&parser, &event)) {
      problem.what = std::string(parser.problem ? parser.problem : "syntax error") + " at line " +
                     std::to_string(lineOf(parser.problem_mark));
      break;
    }
    const yaml_event_type_t type = event.type;
    const bool node_start = type == YAML_SCALAR_EVENT || type == YAML_ALIAS_EVENT ||
                            type == YAML_MAPPING_START_EVENT || type == YAML_SEQUENCE_START_EVENT;
    std::string child_path = open.empty() ? "" : open.back().path;
    const bool is_key = node_start && !open.empty() && open.back().mapping && open.back().expect_key;
    if (node_start && !open.empty() && open.back().mapping) {
      Level& level = open.back();
      if (level.expect_key) {
        level.key = type == YAML_SCALAR_EVENT
                        ? std::string(reinterpret_cast<const char*>(event.data.scalar.value),
                                      event.data.scalar.length)
                        : std::string("?");
        const std::string key_path = level.path.empty() ? level.key : level.path + "." + level.key;
        const int line = lineOf(event.start_mark);
        if (type == YAML_SCALAR_EVENT) {
          const auto [first, inserted] = level.lines.emplace(level.key, line);
          if (!inserted) {
            problem = {key_path, "written twice in one mapping (lines " + std::to_string(first->second) + " and " +
                                     std::to_string(line) + "); keep one"};
            yaml_event_delete(&event);
            break;
          }
        }
        child_path = key_path;
      } else {
        child_path = level.path.empty() ? level.key : level.path + "." + level.key;
      }
      level.expect_key = !level.expect_key;
    }
    if (type == YAML_SCALAR_EVENT && !is_key && event.data.scalar.style == YAML_PLAIN_SCALAR_STYLE) {
      const std::string value(reinterpret_cast<const char*>(event.data.scalar.value), event.data.scalar.length);
      if (!fitsOpenCvInt(value)) {
        problem = {child_path, value + " is out of range: OpenCV reads integers as 32 bits (" +
                                   std::to_string(std::numeric_limits<int>::min()) + " to " +
                                   std::to_string(std::numeric_limits<int>::max()) + ") and would wrap it"};
        yaml_event_delete(&event);
        break;
      }
    }
    if (type == YAML_MAPPING_START_EVENT || type == YAML_SEQUENCE_START_EVENT) {
      Level level;
      level.mapping = type == YAML_MAPPING_START_EVENT;
      level.path = child_path;
      open.push_back(std::move(level));
    } else if ((type == YAML_MAPPING_END_EVENT || type == YAML_SEQUENCE_END_EVENT) && !open.empty()) {
      open.pop_back();
    }
    const bool end = type == YAML_STREAM_END_EVENT;
    yaml_event_delete(&event);
    if (end) break;
  }
  yaml_parser_delete(&parser);
  return problem;
}

}  // namespace

YamlFile::YamlFile(const std::string& path, Header header) : path_(path) {
  // A symbolic link loop or a folder without permission: say so, rather than "missing".
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec && status.type() != std::filesystem::file_type::not_found)
    throw InputError(path, "cannot be read: " + ec.message());
  if (std::filesystem::is_directory(status)) throw InputError(path, "is a folder, not a YAML file");
  std::ifstream probe(path);
  if (!probe) throw InputError(path, "cannot be opened (missing or unreadable)");
  std::string first;
  std::getline(probe, first);
  if (!probe && first.empty()) throw InputError(path, "is empty");
  const size_t first_length = first.size();
  dropByteOrderMark(&first);
  const bool byte_order_mark = first.size() != first_length;  // OpenCV's parser refuses one
  std::stringstream text;
  text << first << '\n' << probe.rdbuf();
  if (const YamlProblem problem = yamlSyntaxProblem(text.str()); !problem.what.empty()) {
    if (!problem.where.empty()) throw InputError(path + ": " + problem.where, problem.what);
    throw InputError(path, "is not valid YAML: " + problem.what);
  }
  const bool add_header = header == Header::Optional && first.rfind("%YAML", 0) != 0;
  try {
    if (add_header || byte_order_mark)
      fs_.open((add_header ? "%YAML:1.0\n---\n" : "") + text.str(),
               cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
    else
      fs_.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    // OpenCV's message spans several lines; keep its last meaningful part.
    std::string msg = e.err.empty() ? e.what() : e.err;
    for (char& c : msg)
      if (c == '\n') c = ' ';
    // OpenCV reads YAML only after its "%YAML:1.0" line; say so rather than "Input file is invalid".
    if (first.rfind("%YAML", 0) != 0)
      throw InputError(path, "is not OpenCV YAML: its first line must be %YAML:1.0 (OpenCV: " + msg + ")");
    throw InputError(path, "is not valid YAML: " + msg);
  } catch (const std::exception& e) {  // OpenCV's parser also lets std::length_error escape
    throw InputError(path, std::string("is not valid YAML (") + e.what() + ")");
  }
  if (!fs_.isOpened()) throw InputError(path, "is not valid YAML");
  // Fields are looked up by name; OpenCV asserts when the top level is a list or a single value.
  const cv::FileNode top = fs_.root();
  if (!top.empty() && !top.isMap())
    throw InputError(path, "must hold named fields at its top level, not a list or a single value");
}

bool YamlFile::has(const std::string& key) const { return !fs_[key].empty(); }

cv::FileNode YamlFile::required(const std::string& key) const {
  cv::FileNode n = fs_[key];
  if (n.empty()) throw InputError(path_ + ": " + key, "missing field");
  return n;
}

int YamlFile::getInt(const std::string& key) const { return readInt(required(key), path_ + ": " + key); }

double YamlFile::getDouble(const std::string& key) const {
  return readDouble(required(key), path_ + ": " + key);
}

std::string YamlFile::getString(const std::string& key) const {
  return readString(required(key), path_ + ": " + key);
}

cv::Mat YamlFile::getMatrix(const std::string& key) const {
  const cv::FileNode n = required(key);
  const std::string where = path_ + ": " + key;
  cv::Mat m;
  try {
    if (n.isMap()) {
      // Sizes first: OpenCV allocates whatever rows x cols says before it reads the data.
      const int rows = readInt(n["rows"], where + ".rows"), cols = readInt(n["cols"], where + ".cols");
      if (rows < 0 || cols < 0 || static_cast<double>(rows) * cols > 1e6)
        throw InputError(where, std::to_string(rows) + "x" + std::to_string(cols) +
                                    " is not a plausible matrix size");
      n >> m;
    } else if (n.isSeq()) {  // a plain list [a, b, c] is read as a row vector
      std::vector<double> v;
      for (const auto& e : n) v.push_back(readDouble(e, where));
      m = cv::Mat(v, true).reshape(1, 1);
    }
  } catch (const cv::Exception&) {
    throw InputError(where, "is not a valid matrix (rows, cols, dt, data)");
  }
  if (m.empty()) throw InputError(where, "is not a matrix");
  m.convertTo(m, CV_64F);
  if (!cv::checkRange(m)) throw InputError(where, "has a NaN or infinite value");
  return m;
}

int readInt(const cv::FileNode& node, const std::string& where) {
  if (node.isInt()) return static_cast<int>(node);
  if (node.isReal()) {
    const double v = static_cast<double>(node);
    if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 2e9) return static_cast<int>(v);
    if (std::isfinite(v) && v == std::floor(v))
      throw InputError(where, "must be an integer from -2e9 to 2e9");
  }
  throw InputError(where, "must be an integer");
}

double readDouble(const cv::FileNode& node, const std::string& where) {
  if (!node.isInt() && !node.isReal()) throw InputError(where, "must be a number");
  const double v = static_cast<double>(node);
  if (!std::isfinite(v)) throw InputError(where, "must be finite");
  return v;
}

bool readBool(const cv::FileNode& node, const std::string& where) {
  if (node.isInt()) {
    const int v = static_cast<int>(node);
    if (v == 0 || v == 1) return v == 1;
  }
  if (node.isString()) {
    const std::string s = static_cast<std::string>(node);
    if (s == "true" || s == "True") return true;
    if (s == "false" || s == "False") return false;
  }
  throw InputError(where, "must be true or false");
}

std::string readString(const cv::FileNode& node, const std::string& where) {
  if (!node.isString()) throw InputError(where, "must be a string");
  return static_cast<std::string>(node);
}

}  // namespace slamcmp
