#include "preflight.hpp"

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace marchcheck::meshes::detail {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw MeshError(path + ": " + problem);
}

std::string line_no(std::size_t line) { return "line " + std::to_string(line) + ": "; }

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

std::string_view strip_comment(std::string_view line) {
  const std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

// Walks the text line by line (LF or CRLF), counting from 1.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    line = text_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  // The next line with tokens once comments are stripped; false at the end.
  bool next_tokens(std::vector<std::string_view>& tokens, bool comments) {
    std::string_view line;
    while (next(line)) {
      tokens = split(comments ? strip_comment(line) : line);
      if (!tokens.empty()) return true;
    }
    return false;
  }
  std::size_t number() const { return number_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

// Empty when the token is a finite number that a float can hold (OpenMesh stores floats), else the problem.
std::string coordinate_problem(std::string_view token) {
  std::string_view digits = token;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  long double value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  const std::string quoted = "'" + std::string(token) + "'";
  if (ec == std::errc::result_out_of_range) return "coordinate " + quoted + " is out of range";
  if (ec != std::errc() || end != digits.data() + digits.size()) return "coordinate " + quoted + " is not a number";
  if (!std::isfinite(value)) return "coordinate " + quoted + " is not finite";
  if (std::fabs(value) > static_cast<long double>(FLT_MAX))
    return "coordinate " + quoted + " is beyond the float range (OpenMesh reads floats)";
  return {};
}

template <class Int>
bool parse_int(std::string_view token, Int& value) {
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

void check_coordinates(const std::string& path, std::size_t line, const std::vector<std::string_view>& tokens,
                       std::size_t first, const std::string& what) {
  if (tokens.size() < first + 3) fail(path, line_no(line) + what + " has fewer than three coordinates");
  for (std::size_t k = first; k < first + 3; ++k)
    if (const std::string problem = coordinate_problem(tokens[k]); !problem.empty())
      fail(path, line_no(line) + what + ": " + problem);
}

// "v", "v/t", "v//n" or "v/t/n" with whole-number indices (their range is checked after reading). OpenMesh's OBJ reader asserts (aborting the
// program) on a face whose corners it cannot parse, such as "f /1 2 3" or "f 1 2 3x" (both found by fuzz_mesh_obj).
bool obj_corner(std::string_view token) {
  int index = 0;
  const std::size_t first = token.find('/');
  if (!parse_int(token.substr(0, first), index)) return false;
  if (first == std::string_view::npos) return true;
  const std::string_view rest = token.substr(first + 1);
  const std::size_t second = rest.find('/');
  if (second == std::string_view::npos) return parse_int(rest, index);
  return (second == 0 || parse_int(rest.substr(0, second), index)) && parse_int(rest.substr(second + 1), index);
}

Expected preflight_obj(const std::string& path, std::string_view content) {
  Expected expected{0, 0};
  Lines lines(content);
  std::vector<std::string_view> tokens;
  while (lines.next_tokens(tokens, true)) {
    if (tokens[0] == "v") {
      ++*expected.vertices;
      check_coordinates(path, lines.number(), tokens, 1, "vertex " + std::to_string(*expected.vertices));
    } else if (tokens[0] == "f") {
      ++*expected.faces;
      if (tokens.size() < 4)
        fail(path, line_no(lines.number()) + "face " + std::to_string(*expected.faces) + " has " +
                       std::to_string(tokens.size() - 1) + " vertices (at least 3 needed)");
      for (std::size_t k = 1; k < tokens.size(); ++k)
        if (!obj_corner(tokens[k]))
          fail(path, line_no(lines.number()) + "face " + std::to_string(*expected.faces) + ": corner '" +
                         std::string(tokens[k].substr(0, 40)) + "' is not v, v/t, v//n or v/t/n (whole numbers)");
    }
  }
  return expected;
}

Expected preflight_off(const std::string& path, std::string_view content) {
  Lines lines(content);
  std::vector<std::string_view> tokens;
  if (!lines.next_tokens(tokens, false)) fail(path, "no OFF header");
  const std::string_view keyword = tokens[0];
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
    fail(path, "not an OFF file: it starts with '" + std::string(keyword.substr(0, 40)) + "'");
  // OpenMesh's binary OFF reader never returns on some malformed files (fuzz_mesh_off found "OFF\rBINARY" with
  // text after it), and nothing here writes binary or n-dimensional OFF: refuse both.
  if (std::find(tokens.begin(), tokens.end(), "BINARY") != tokens.end())
    fail(path, "binary OFF is not supported (OpenMesh's reader can hang on a damaged one); use ASCII OFF, PLY or STL");
  if (keyword.front() == 'n') fail(path, "n-dimensional OFF ('nOFF') is not supported");
  // Prefixes (C, N, ST, 4) announce extra numbers per vertex that OpenMesh reads from the stream whether or not
  // the lines hold them (fuzz_mesh_off found "NOFF" with three values a vertex allocating 2 GB): plain OFF only.
  if (keyword != "OFF")
    fail(path, "only plain OFF is supported, not '" + std::string(keyword.substr(0, 40)) +
                   "' (per-vertex colours, normals or texture coordinates)");
  // OpenMesh's OFF reader takes '#' as data (even reading uninitialised values), and wants the counts on a line
  // of their own: refuse both rather than load garbage.
  if (const std::size_t hash = content.find('#'); hash != std::string_view::npos)
    fail(path, line_no(static_cast<std::size_t>(std::count(content.begin(), content.begin() +
                                                               static_cast<std::ptrdiff_t>(hash), '\n')) + 1) +
                   "'#' comments are not supported (OpenMesh's OFF reader misreads them)");
  if (tokens.size() > 1)
    fail(path, line_no(lines.number()) + "put the counts on the line after '" + std::string(keyword) +
                   "' (OpenMesh's OFF reader expects them there)");
  if (!lines.next_tokens(tokens, false)) fail(path, "the OFF header has no element counts");
  std::uint64_t n_vertices = 0, n_faces = 0;
  // All three counts: OpenMesh reads the edge count wherever the next number is, shifting every later value
  // (fuzz_mesh_off found "4 1" turning a coordinate into a face size of 2^32 - 840).
  std::uint64_t n_edges = 0;
  if (tokens.size() != 3 || !parse_int(tokens[0], n_vertices) || !parse_int(tokens[1], n_faces) ||
      !parse_int(tokens[2], n_edges))
    fail(path, line_no(lines.number()) + "expected the vertex, face and edge counts (three whole numbers)");
  if (n_vertices + n_faces > content.size())
    fail(path, "the header announces " + std::to_string(n_vertices) + " vertices and " + std::to_string(n_faces) +
                   " faces, more than the file's " + std::to_string(content.size()) + " bytes can hold");
  for (std::uint64_t v = 0; v < n_vertices; ++v) {
    if (!lines.next_tokens(tokens, false))
      fail(path, "the file ends after " + std::to_string(v) + " of " + std::to_string(n_vertices) +
                     " vertices (truncated?)");
    check_coordinates(path, lines.number(), tokens, 0, "vertex " + std::to_string(v));
    // OpenMesh reads a plain OFF as one stream of numbers: a fourth value on a vertex line shifts every later
    // one (fuzz_mesh_off found it turning an index into a face size of 2^64 - 2 and a 1.6 GB allocation).
    if (tokens.size() != 3)
      fail(path, line_no(lines.number()) + "vertex " + std::to_string(v) + " has " + std::to_string(tokens.size()) +
                     " values; a plain OFF vertex has exactly three");
  }
  for (std::uint64_t f = 0; f < n_faces; ++f) {
    if (!lines.next_tokens(tokens, false))
      fail(path, "the file ends after " + std::to_string(f) + " of " + std::to_string(n_faces) +
                     " faces (truncated?)");
    const std::string where = line_no(lines.number()) + "face " + std::to_string(f);
    std::uint64_t size = 0;
    if (!parse_int(tokens[0], size)) fail(path, where + " does not start with its vertex count");
    if (size < 3) fail(path, where + " has " + std::to_string(size) + " vertices (at least 3 needed)");
    if (tokens.size() < size + 1) fail(path, where + " lists fewer than its " + std::to_string(size) + " vertices");
    if (tokens.size() > size + 1)  // read as the next face's size otherwise (see the vertices above)
      fail(path, where + " has values after its " + std::to_string(size) + " vertex indices (face colours are not supported)");
    for (std::uint64_t k = 1; k <= size; ++k) {
      std::int64_t index = 0;
      if (!parse_int(tokens[k], index)) fail(path, where + ": vertex index '" + std::string(tokens[k]) + "' is not an integer");
      if (index < 0 || static_cast<std::uint64_t>(index) >= n_vertices)
        fail(path, where + " refers to vertex " + std::to_string(index) + ", but the file has " +
                       std::to_string(n_vertices) + " vertices");
    }
  }
  return {n_vertices, n_faces};
}

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<std::string> properties;  // names; lists have their name too
  std::vector<bool> is_list;
};

bool ply_type(std::string_view type) {
  for (const char* known : {"char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8",
                            "int16", "uint16", "int32", "uint32", "float32", "float64"})
    if (type == known) return true;
  return false;
}

Expected preflight_ply(const std::string& path, std::string_view content) {
  Lines lines(content);
  std::vector<std::string_view> tokens;
  std::string_view line;
  if (!lines.next(line) || split(line) != std::vector<std::string_view>{"ply"})
    fail(path, "not a PLY file: the first line is not 'ply'");
  std::string format;
  std::vector<PlyElement> elements;
  bool end_header = false;
  while (!end_header && lines.next(line)) {
    tokens = split(line);
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    const std::string where = line_no(lines.number());
    // OpenMesh reads the header word by word: a line one word short shifts everything after it (a list
    // property without a name swallows end_header, and the reader then loops forever at the end of the file).
    if (tokens[0] == "format" && tokens.size() == 3) {
      // OpenMesh reads the version as a float; one that does not parse (fuzzing found "\xb1.0") leaves its
      // stream failed and its header loop spinning forever.
      double version = 0;
      const auto [end, ec] = std::from_chars(tokens[2].data(), tokens[2].data() + tokens[2].size(), version);
      if (ec != std::errc() || end != tokens[2].data() + tokens[2].size() || version != 1.0)
        fail(path, where + "PLY version '" + std::string(tokens[2].substr(0, 20)) + "' is not 1.0");
      format = tokens[1];
    } else if (tokens[0] == "element" && tokens.size() == 3) {
      PlyElement element{std::string(tokens[1]), 0, {}, {}};
      if (!parse_int(tokens[2], element.count))
        fail(path, where + "element count '" + std::string(tokens[2]) + "' is not a count");
      elements.push_back(element);
    } else if (tokens[0] == "property" && !elements.empty() &&
               ((tokens.size() == 3 && ply_type(tokens[1])) ||
                (tokens.size() == 5 && tokens[1] == "list" && ply_type(tokens[2]) && ply_type(tokens[3])))) {
      elements.back().properties.emplace_back(tokens.back());
      elements.back().is_list.push_back(tokens.size() == 5);
    } else if (tokens[0] == "end_header" && tokens.size() == 1) {
      end_header = true;
    } else {
      fail(path, where + "malformed PLY header line '" + std::string(line.substr(0, 60)) + "'");
    }
  }
  if (!end_header) fail(path, "the PLY header has no end_header (truncated or not a PLY file)");
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    fail(path, "unknown PLY format '" + format + "'");
  Expected expected;
  std::uint64_t total = 0;
  for (const PlyElement& element : elements) {
    total += element.count;
    if (element.name == "vertex") expected.vertices = element.count;
    if (element.name == "face") expected.faces = element.count;
  }
  if (total > content.size())
    fail(path, "the header announces " + std::to_string(total) + " elements, more than the file's " +
                   std::to_string(content.size()) + " bytes can hold");
  if (format != "ascii") return expected;
  for (const PlyElement& element : elements) {
    // Coordinates are checked where x, y, z come before any list property (the usual layout).
    std::vector<std::size_t> xyz;
    if (element.name == "vertex") {
      for (const char* axis : {"x", "y", "z"}) {
        const auto it = std::find(element.properties.begin(), element.properties.end(), axis);
        const auto k = static_cast<std::size_t>(it - element.properties.begin());
        if (it == element.properties.end())
          fail(path, "the vertex element has no '" + std::string(axis) + "' property");
        if (std::find(element.is_list.begin(), element.is_list.begin() + static_cast<std::ptrdiff_t>(k), true) ==
            element.is_list.begin() + static_cast<std::ptrdiff_t>(k))
          xyz.push_back(k);
      }
    }
    for (std::uint64_t i = 0; i < element.count; ++i) {
      if (!lines.next_tokens(tokens, false))
        fail(path, "the file ends after " + std::to_string(i) + " of " + std::to_string(element.count) + " " +
                       element.name + " elements (truncated?)");
      for (const std::size_t k : xyz) {
        if (k >= tokens.size()) fail(path, line_no(lines.number()) + "vertex " + std::to_string(i) + " is incomplete");
        if (const std::string problem = coordinate_problem(tokens[k]); !problem.empty())
          fail(path, line_no(lines.number()) + "vertex " + std::to_string(i) + ": " + problem);
      }
    }
  }
  return expected;
}

float read_float_le(const char* bytes) {
  std::uint32_t bits = 0;
  for (int k = 3; k >= 0; --k) bits = (bits << 8) | static_cast<unsigned char>(bytes[k]);
  float value = 0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

Expected preflight_stl(const std::string& path, std::string_view content) {
  const std::size_t size = content.size();
  std::uint64_t announced = 0;
  if (size >= 84) {
    for (int k = 3; k >= 0; --k) announced = (announced << 8) | static_cast<unsigned char>(content[80 + static_cast<std::size_t>(k)]);
    if (size == 84 + 50 * announced) {
      for (std::uint64_t t = 0; t < announced; ++t) {
        const char* record = content.data() + 84 + 50 * t;
        for (int k = 3; k < 12; ++k)  // the normal (floats 0..2) does not matter
          if (!std::isfinite(read_float_le(record + 4 * k)))
            fail(path, "triangle " + std::to_string(t) + " has a NaN or infinite vertex coordinate");
      }
      return {std::nullopt, announced};
    }
  }
  const std::size_t first = content.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos || content.substr(first, 5) != "solid") {
    if (size < 84)
      fail(path, "neither an ASCII STL (no 'solid' keyword) nor a binary STL (" + std::to_string(size) +
                     " bytes, a binary STL has at least 84)");
    fail(path, "neither an ASCII STL (no 'solid' keyword) nor a binary STL: its header announces " +
                   std::to_string(announced) + " triangles (" + std::to_string(84 + 50 * announced) +
                   " bytes) but the file has " + std::to_string(size) + " bytes (truncated?)");
  }
  if (content.find('\0') != std::string_view::npos)
    fail(path, "starts with 'solid' but holds binary data: a binary STL whose size (" + std::to_string(size) +
                   " bytes) does not match its triangle count (truncated?)");
  Expected expected{std::nullopt, 0};
  Lines lines(content);
  std::vector<std::string_view> tokens;
  while (lines.next_tokens(tokens, false)) {
    if (tokens[0] == "facet") ++*expected.faces;
    if (tokens[0] == "vertex") check_coordinates(path, lines.number(), tokens, 1, "vertex");
  }
  return expected;
}

}  // namespace

Expected preflight(Format format, const std::string& path, std::string_view content) {
  switch (format) {
    case Format::obj: return preflight_obj(path, content);
    case Format::off: return preflight_off(path, content);
    case Format::ply: return preflight_ply(path, content);
    case Format::stl: return preflight_stl(path, content);
  }
  return {};
}

}  // namespace marchcheck::meshes::detail
