#include "core/map_ply.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "core/format_string.h"
#include "core/text_file.h"

namespace slamcmp {

void writeMapPly(const std::string& path, const std::vector<MapPoint>& points) {
  std::ofstream out(path);
  if (!out) throw InputError(path, "cannot be written");
  out << "ply\nformat ascii 1.0\ncomment slamcmp map, world (board) frame, metres\n"
      << "element vertex " << points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property int id\nproperty int observations\nproperty float sigma\nend_header\n";
  for (const auto& p : points) {
    // sigma with significant digits, not decimals: a tiny one must not read back as 0 (known).
    out << formatString("%.6f %.6f %.6f %d %d %.6g\n", p.p_world.x(), p.p_world.y(), p.p_world.z(), p.id,
                        p.observations, p.sigma);
  }
  if (!out) throw InputError(path, "write failed");
}

namespace {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };
enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

// The PLY type names, with the sized aliases that Open3D (via rply) and others write.
std::optional<PlyType> parseType(const std::string& s) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [name, type] : names)
    if (s == name) return type;
  return std::nullopt;
}

size_t typeSize(PlyType t) {
  switch (t) {
    case PlyType::Int8: case PlyType::UInt8: return 1;
    case PlyType::Int16: case PlyType::UInt16: return 2;
    case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;  // lists only
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  int lines = 0;  // header lines, end_header included
};

std::vector<std::string> splitWords(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// One line, without the '\r' of files written on Windows. False at the end of the file.
bool getLine(std::istream& in, std::string* line) {
  if (!std::getline(in, *line)) return false;
  if (!line->empty() && line->back() == '\r') line->pop_back();
  return true;
}

PlyHeader readHeader(std::istream& in, const std::string& path) {
  PlyHeader h;
  std::string line;
  bool has_format = false;
  auto fail = [&](const std::string& what) { throw InputError(atLine(path, h.lines), what); };
  while (true) {
    if (!getLine(in, &line)) throw InputError(path, "the PLY header has no end_header line");
    ++h.lines;
    if (h.lines == 1) {
      if (line != "ply") fail("not a PLY file (the first line must be 'ply')");
      continue;
    }
    const auto w = splitWords(line);
    if (w.empty()) continue;
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") break;
    if (w[0] == "format") {
      if (w.size() != 3) fail("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      if (w[1] == "ascii") h.format = PlyFormat::Ascii;
      else if (w[1] == "binary_little_endian") h.format = PlyFormat::BinaryLittleEndian;
      else if (w[1] == "binary_big_endian") h.format = PlyFormat::BinaryBigEndian;
      else fail("unknown format '" + w[1] + "'");
      if (w[2] != "1.0") fail("unsupported PLY version '" + w[2] + "' (1.0 expected)");
      has_format = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) fail("expected 'element NAME COUNT'");
      PlyElement e;
      e.name = w[1];
      char* end = nullptr;
      const unsigned long long count = std::strtoull(w[2].c_str(), &end, 10);
      if (w[2][0] == '-' || *end != '\0') fail("element count '" + w[2] + "' is not a count");
      e.count = count;
      h.elements.push_back(e);
    } else if (w[0] == "property") {
      if (h.elements.empty()) fail("a property before any element");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        const auto count_type = parseType(w[2]), type = parseType(w[3]);
        if (!count_type || !type) fail("unknown type in '" + line + "'");
        if (*count_type == PlyType::Float32 || *count_type == PlyType::Float64)
          fail("a list count must have an integer type");
        p.is_list = true;
        p.count_type = *count_type;
        p.type = *type;
        p.name = w[4];
      } else if (w.size() == 3) {
        const auto type = parseType(w[1]);
        if (!type) fail("unknown type '" + w[1] + "'");
        p.type = *type;
        p.name = w[2];
      } else {
        fail("expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
      }
      h.elements.back().properties.push_back(p);
    } else {
      fail("unknown header keyword '" + w[0] + "'");
    }
  }
  if (!has_format) throw InputError(path, "the PLY header has no format line");
  // An element without properties takes no bytes: a huge count of it would spin, not fail.
  for (const PlyElement& e : h.elements)
    if (e.count > 0 && e.properties.empty())
      throw InputError(path, "element '" + e.name + "' has " + std::to_string(e.count) + " instances but no properties");
  return h;
}

// A number from a binary file in the file's byte order.
double decodeBinary(const unsigned char* bytes, PlyType type, bool swap) {
  unsigned char b[8];
  const size_t n = typeSize(type);
  for (size_t i = 0; i < n; ++i) b[i] = swap ? bytes[n - 1 - i] : bytes[i];
  switch (type) {
    case PlyType::Int8: { int8_t v; std::memcpy(&v, b, 1); return v; }
    case PlyType::UInt8: { uint8_t v; std::memcpy(&v, b, 1); return v; }
    case PlyType::Int16: { int16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::UInt16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::Int32: { int32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::UInt32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::Float32: { float v; std::memcpy(&v, b, 4); return v; }
    case PlyType::Float64: { double v; std::memcpy(&v, b, 8); return v; }
  }
  return 0;
}

bool hostIsLittleEndian() {
  const uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// Reads one element instance into `values` (one per scalar property; lists are skipped).
// Returns false when the file ends first.
class BinaryElementReader {
 public:
  BinaryElementReader(std::istream& in, bool swap) : in_(in), swap_(swap) {}
  bool read(const PlyElement& e, std::vector<double>* values) {
    values->clear();
    unsigned char buf[8];
    for (const PlyProperty& p : e.properties) {
      if (!p.is_list) {
        if (!in_.read(reinterpret_cast<char*>(buf), typeSize(p.type))) return false;
        values->push_back(decodeBinary(buf, p.type, swap_));
        continue;
      }
      if (!in_.read(reinterpret_cast<char*>(buf), typeSize(p.count_type))) return false;
      const double count = decodeBinary(buf, p.count_type, swap_);
      if (count < 0) return false;
      const auto bytes = static_cast<std::streamsize>(count) * static_cast<std::streamsize>(typeSize(p.type));
      in_.ignore(bytes);
      if (in_.gcount() != bytes) return false;
      values->push_back(count);
    }
    return true;
  }

 private:
  std::istream& in_;
  bool swap_;
};

// One ascii element instance (one line) into `values`, as BinaryElementReader does; throws for
// a malformed line.
void parseAsciiElement(const std::string& line, const PlyElement& e, const std::string& where,
                       std::vector<double>* values) {
  const auto words = splitWords(line);
  values->clear();
  size_t k = 0;
  auto next = [&]() {
    if (k >= words.size())
      throw InputError(where, "too few values for element '" + e.name + "' (" + std::to_string(words.size()) +
                                  " found)");
    const std::string& w = words[k++];
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end == w.c_str() || *end != '\0') throw InputError(where, "'" + w + "' is not a number");
    return v;
  };
  for (const PlyProperty& p : e.properties) {
    const double v = next();
    values->push_back(v);
    if (!p.is_list) continue;
    if (v < 0 || v != std::floor(v)) throw InputError(where, "list count '" + words[k - 1] + "' is not a count");
    for (double i = 0; i < v; ++i) next();
  }
  if (k != words.size())
    throw InputError(where, "expected " + std::to_string(k) + " values for element '" + e.name + "', found " +
                                std::to_string(words.size()));
}

}  // namespace

std::vector<MapPoint> readMapPly(const std::string& path) {
  std::ifstream in = openTextFile(path, std::ios::binary);  // a folder would have "no end_header line"
  const PlyHeader header = readHeader(in, path);

  const auto vertex = std::find_if(header.elements.begin(), header.elements.end(),
                                   [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex == header.elements.end()) throw InputError(path, "the PLY header has no 'element vertex'");
  auto column = [&](const char* name) -> int {
    for (size_t i = 0; i < vertex->properties.size(); ++i)
      if (vertex->properties[i].name == name && !vertex->properties[i].is_list) return static_cast<int>(i);
    return -1;
  };
  const int ix = column("x"), iy = column("y"), iz = column("z");
  if (ix < 0 || iy < 0 || iz < 0) throw InputError(path, "the vertex element has no x, y and z properties");
  const int i_id = column("id"), i_obs = column("observations"), i_sigma = column("sigma");

  const bool ascii = header.format == PlyFormat::Ascii;
  const bool swap = !ascii && (header.format == PlyFormat::BinaryLittleEndian) != hostIsLittleEndian();
  BinaryElementReader binary(in, swap);
  int line_number = header.lines;
  std::string line;
  std::vector<double> values;
  // The next instance of `e`; `where` names it for messages.
  auto readInstance = [&](const PlyElement& e, uint64_t index) {
    if (ascii) {
      do {
        if (!getLine(in, &line))
          throw InputError(path, "the file ends before " + e.name + " " + std::to_string(index) + " of " +
                                     std::to_string(e.count));
        ++line_number;
      } while (line.find_first_not_of(" \t") == std::string::npos);
      parseAsciiElement(line, e, atLine(path, line_number), &values);
    } else if (!binary.read(e, &values)) {
      throw InputError(path, "the file ends before " + e.name + " " + std::to_string(index) + " of " +
                                 std::to_string(e.count));
    }
  };
  // A header that says binary over text (a file converted by hand, or its header copied from
  // another) decodes as garbage that only looks like points.
  if (!ascii) {
    char head[32];
    in.read(head, sizeof head);
    const std::streamsize n = in.gcount();
    in.clear();
    in.seekg(-n, std::ios::cur);
    if (n > 0 && std::all_of(head, head + n, [](char c) { return std::strchr("0123456789.eE+- \t\r\n", c) && c; }))
      throw InputError(path, "the header says " + std::string(header.format == PlyFormat::BinaryLittleEndian
                                                                     ? "binary_little_endian"
                                                                     : "binary_big_endian") +
                                 " but the data is text: its format line must be 'format ascii 1.0'");
  }
  // Elements before the vertices (rare, but allowed) are read past.
  for (auto e = header.elements.begin(); e != vertex; ++e)
    for (uint64_t i = 0; i < e->count; ++i) readInstance(*e, i);

  std::vector<MapPoint> points;
  points.reserve(static_cast<size_t>(std::min<uint64_t>(vertex->count, 1 << 20)));
  for (uint64_t i = 0; i < vertex->count; ++i) {
    readInstance(*vertex, i);
    MapPoint p;
    p.p_world = Vec3(values[ix], values[iy], values[iz]);
    if (!p.p_world.allFinite())
      throw InputError(ascii ? atLine(path, line_number) : path + ": vertex " + std::to_string(i),
                       "x, y or z is not finite");
    auto integer = [&](int column_index, const char* name) {
      const double v = values[column_index];
      if (!(v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max()))
        throw InputError(ascii ? atLine(path, line_number) : path + ": vertex " + std::to_string(i),
                         std::string(name) + " is not an integer in range");
      return static_cast<int>(v);
    };
    p.id = i_id >= 0 ? integer(i_id, "id") : static_cast<int>(i);
    p.observations = i_obs >= 0 ? integer(i_obs, "observations") : 0;
    p.sigma = i_sigma >= 0 ? values[i_sigma] : -1.0;
    points.push_back(p);
  }
  // Data beyond what the header declares: a count that was not updated when points were added.
  for (auto e = vertex + 1; e != header.elements.end(); ++e)
    for (uint64_t i = 0; i < e->count; ++i) readInstance(*e, i);
  const std::string declared =
      "the " + std::to_string(vertex->count) + " vertices (and other elements) the header declares";
  if (ascii) {
    while (getLine(in, &line)) {
      ++line_number;
      if (line.find_first_not_of(" \t") != std::string::npos)
        throw InputError(atLine(path, line_number), "data beyond " + declared + ": is the element vertex count wrong?");
    }
  } else if (in.peek() != std::char_traits<char>::eof()) {
    throw InputError(path, "data beyond " + declared + ": is the element vertex count wrong?");
  }
  return points;
}

}  // namespace slamcmp
