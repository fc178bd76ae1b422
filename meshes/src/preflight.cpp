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
  std::size_t offset() const { return pos_; }  // where the next line starts

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

// Empty when the token is a finite number that a float can hold (OpenMesh stores floats), else the problem
// ("'TOKEN' is ...").
std::string float_problem(std::string_view token) {
  std::string_view digits = token;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  long double value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  const std::string quoted = "'" + std::string(token) + "'";
  if (ec == std::errc::result_out_of_range) return quoted + " is out of range";
  if (ec != std::errc() || end != digits.data() + digits.size()) return quoted + " is not a number";
  if (!std::isfinite(value)) return quoted + " is not finite";
  if (std::fabs(value) > static_cast<long double>(FLT_MAX))
    return quoted + " is beyond the float range (OpenMesh reads floats)";
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
    if (const std::string problem = float_problem(tokens[k]); !problem.empty())
      fail(path, line_no(line) + what + ": coordinate " + problem);
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

struct PlyProperty {
  std::string name;
  std::string type;        // a list's entry type
  std::string count_type;  // a list's count type; empty for a scalar
  std::size_t line = 0;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// Bytes a binary PLY value of this type takes; 0 for a name that is not a PLY type.
std::size_t ply_size(std::string_view type) {
  for (const auto& [name, size] : std::initializer_list<std::pair<std::string_view, std::size_t>>{
           {"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2}, {"ushort", 2}, {"int16", 2},
           {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4}, {"uint32", 4}, {"float", 4}, {"float32", 4},
           {"double", 8}, {"float64", 8}})
    if (type == name) return size;
  return 0;
}

bool ply_is_float(std::string_view type) {
  return type == "float" || type == "float32" || type == "double" || type == "float64";
}

// OpenMesh reads one list, a face's vertex_indices, and every other list as a single value (so a file with one
// reads shifted); it also takes every list count as unsigned, so "-1" or a damaged binary count asks it for four
// billion indices (fuzz_mesh_ply found that: a 2 GB allocation).
bool ply_is_face_indices(const PlyElement& element, const PlyProperty& property) {
  return element.name == "face" && (property.name == "vertex_indices" || property.name == "vertex_index");
}

bool ply_is_colour(const PlyElement& element, const PlyProperty& property) {
  const std::string_view name = property.name;
  return (element.name == "vertex" || element.name == "face") &&
         (name == "red" || name == "green" || name == "blue" || name == "alpha" ||
          (element.name == "vertex" && (name == "diffuse_red" || name == "diffuse_green" || name == "diffuse_blue")));
}

// What OpenMesh 9 would misread in this property, or empty. Misreading one value shifts every later one, and a
// shifted binary list count can be anything up to four billion.
std::string ply_property_problem(const PlyElement& element, const PlyProperty& property, bool binary) {
  const std::string quoted = "'" + property.name + "'";
  if (ply_size(property.name) != 0)  // OpenMesh takes the type from whichever of the two words is a type name
    return "a property named " + quoted + " (a type name) is not supported";
  if (!property.count_type.empty()) {
    if (!ply_is_face_indices(element, property))
      return "the list property " + quoted + " of element '" + element.name +
             "' is not supported (OpenMesh reads only a face's vertex_indices list)";
    if (property.count_type != "uchar" && property.count_type != "uint8" && property.count_type != "uint16" &&
        property.count_type != "int")  // OpenMesh fails on any other
      return "list count type '" + property.count_type + "' is not supported (OpenMesh reads uchar, uint8, uint16 or int)";
    if (ply_is_float(property.type)) return "vertex indices of type '" + property.type + "' are not whole numbers";
  }
  // OpenMesh reads a colour either as float or as an integer, so a double one is read as an integer: nothing
  // from binary, and from ASCII only up to the decimal point.
  if (ply_is_colour(element, property) && ply_is_float(property.type) && ply_size(property.type) == 8)
    return "the colour property " + quoted + " of type '" + property.type +
           "' is not supported (OpenMesh reads colours as float or integer)";
  // OpenMesh's binary reader reads positions, normals and texture coordinates only as floats: from an integer
  // it reads nothing.
  static constexpr std::string_view kFloatOnly[] = {"x", "y", "z", "nx", "ny", "nz", "u", "v", "s", "t"};
  if (binary && element.name == "vertex" && !ply_is_float(property.type) &&
      std::ranges::find(kFloatOnly, std::string_view(property.name)) != std::end(kFloatOnly))
    return "the vertex property " + quoted + " is '" + property.type + "'; a binary PLY must store it as float or double";
  return {};
}

// OpenMesh reads ASCII PLY as one stream of words, so each element's line must hold exactly the values its
// properties describe, each a number of its type (a "1.5" read as an integer leaves ".5" as the next value).
void check_ply_ascii(const std::string& path, const std::vector<PlyElement>& elements, Lines& lines) {
  std::vector<std::string_view> tokens;
  for (const PlyElement& element : elements) {
    if (element.properties.empty()) continue;  // takes no words
    for (std::uint64_t i = 0; i < element.count; ++i) {
      if (!lines.next_tokens(tokens, false))
        fail(path, "the file ends after " + std::to_string(i) + " of " + std::to_string(element.count) + " " +
                       element.name + " elements (truncated?)");
      const std::string where = line_no(lines.number()) + element.name + " " + std::to_string(i);
      std::size_t next = 0;
      const auto take = [&](const PlyProperty& property, const std::string& type) {
        if (next >= tokens.size()) fail(path, where + " is incomplete: '" + property.name + "' is missing");
        const std::string_view token = tokens[next++];
        if (ply_is_float(type)) {
          if (const std::string problem = float_problem(token); !problem.empty())
            fail(path, where + ": " + property.name + " value " + problem);
          return std::uint64_t{0};
        }
        std::int64_t value = 0;
        if (!parse_int(token, value))
          fail(path, where + ": '" + property.name + "' value '" + std::string(token.substr(0, 40)) +
                         "' is not a whole number");
        // What OpenMesh reads into an int (colours) or an unsigned (the list): beyond that its stream fails and
        // every later value reads as zero.
        const std::int64_t most = property.count_type.empty() ? INT32_MAX : UINT32_MAX;
        if ((ply_is_colour(element, property) || !property.count_type.empty()) && (value < INT32_MIN || value > most))
          fail(path, where + ": '" + property.name + "' value '" + std::string(token) + "' is out of range");
        return static_cast<std::uint64_t>(std::max<std::int64_t>(value, 0));
      };
      for (const PlyProperty& property : element.properties) {
        if (property.count_type.empty()) {
          take(property, property.type);
          continue;
        }
        const std::string_view count_token = next < tokens.size() ? tokens[next] : std::string_view();
        const std::uint64_t count = take(property, property.count_type);
        if (count_token.starts_with('-') || count > tokens.size() - next)
          fail(path, where + ": the list '" + property.name + "' announces " + std::string(count_token) +
                         " values but the line holds " + std::to_string(tokens.size() - next));
        for (std::uint64_t k = 0; k < count; ++k) take(property, property.type);
      }
      if (next != tokens.size())
        fail(path, where + " has " + std::to_string(tokens.size()) + " values; its properties describe " +
                       std::to_string(next));
    }
  }
}

std::uint64_t read_uint(const char* bytes, std::size_t size, bool big_endian) {
  std::uint64_t value = 0;
  for (std::size_t k = 0; k < size; ++k)
    value = (value << 8) | static_cast<unsigned char>(bytes[big_endian ? k : size - 1 - k]);
  return value;
}

// Walks the binary body: every element must fit in the file, and every list count must be one OpenMesh reads
// as the same number (a signed count's sign bit set would be four billion to it).
void check_ply_binary(const std::string& path, const std::vector<PlyElement>& elements, std::string_view body,
                      bool big_endian) {
  std::size_t at = 0;
  const auto truncated = [&](const PlyElement& element, std::uint64_t i) {
    fail(path, "the binary data ends inside " + element.name + " " + std::to_string(i) + " of " +
                   std::to_string(element.count) + " (truncated?)");
  };
  for (const PlyElement& element : elements) {
    for (std::uint64_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& property : element.properties) {
        const std::size_t size = ply_size(property.type);
        if (property.count_type.empty()) {
          if (body.size() - at < size) truncated(element, i);
          at += size;
          continue;
        }
        const std::size_t count_size = ply_size(property.count_type);
        if (body.size() - at < count_size) truncated(element, i);
        const std::uint64_t count = read_uint(body.data() + at, count_size, big_endian);
        at += count_size;
        if (!property.count_type.starts_with('u') && (count >> (8 * count_size - 1)) != 0)
          fail(path, element.name + " " + std::to_string(i) + ": the list '" + property.name +
                         "' has a negative count");
        if (count > (body.size() - at) / size) truncated(element, i);
        at += count * size;
      }
    }
  }
}

Expected preflight_ply(const std::string& path, std::string_view content) {
  Lines lines(content);
  std::vector<std::string_view> tokens;
  std::string_view line;
  if (!lines.next(line) || split(line) != std::vector<std::string_view>{"ply"})
    fail(path, "not a PLY file: the first line is not 'ply'");
  std::string format;
  std::vector<PlyElement> elements;
  std::string_view previous;  // the header line before end_header, to see where OpenMesh puts the binary body
  bool end_header = false;
  while (!end_header && lines.next(line)) {
    tokens = split(line);
    const std::string where = line_no(lines.number());
    // OpenMesh reads the header word by word: a line one word short shifts everything after it (a list
    // property without a name swallows end_header, and the reader then loops forever at the end of the file).
    // It would read an obj_info line's words as keywords: those lines are malformed here.
    if (tokens.empty() || tokens[0] == "comment") {
    } else if (tokens[0] == "format" && tokens.size() == 3) {
      // OpenMesh reads the version as a float; one that does not parse (fuzzing found "\xb1.0") leaves its
      // stream failed and its header loop spinning forever.
      double version = 0;
      const auto [end, ec] = std::from_chars(tokens[2].data(), tokens[2].data() + tokens[2].size(), version);
      if (ec != std::errc() || end != tokens[2].data() + tokens[2].size() || version != 1.0)
        fail(path, where + "PLY version '" + std::string(tokens[2].substr(0, 20)) + "' is not 1.0");
      format = tokens[1];
    } else if (tokens[0] == "element" && tokens.size() == 3) {
      PlyElement element{std::string(tokens[1]), 0, {}};
      if (!parse_int(tokens[2], element.count))
        fail(path, where + "element count '" + std::string(tokens[2]) + "' is not a count");
      // OpenMesh reads every face element with the last one's count and keeps only the last vertex count.
      if ((element.name == "vertex" || element.name == "face") &&
          std::ranges::any_of(elements, [&](const PlyElement& e) { return e.name == element.name; }))
        fail(path, where + "a second '" + element.name + "' element");
      elements.push_back(element);
    } else if (tokens[0] == "property" && !elements.empty() && tokens.size() == 3 && ply_size(tokens[1]) != 0) {
      elements.back().properties.push_back({std::string(tokens[2]), std::string(tokens[1]), {}, lines.number()});
    } else if (tokens[0] == "property" && !elements.empty() && tokens.size() == 5 && tokens[1] == "list" &&
               ply_size(tokens[2]) != 0 && ply_size(tokens[3]) != 0) {
      elements.back().properties.push_back(
          {std::string(tokens[4]), std::string(tokens[3]), std::string(tokens[2]), lines.number()});
    } else if (tokens[0] == "end_header" && tokens.size() == 1) {
      end_header = true;
      continue;
    } else {
      fail(path, where + "malformed PLY header line '" + std::string(line.substr(0, 60)) + "'");
    }
    previous = line;
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
  for (const PlyElement& element : elements)
    for (const PlyProperty& property : element.properties)
      if (const std::string problem = ply_property_problem(element, property, format != "ascii"); !problem.empty())
        fail(path, line_no(property.line) + problem);
  for (const PlyElement& element : elements) {
    if (element.name != "vertex") continue;
    for (const char* axis : {"x", "y", "z"})
      if (std::none_of(element.properties.begin(), element.properties.end(),
                       [&](const PlyProperty& p) { return p.name == axis; }))
        fail(path, "the vertex element has no '" + std::string(axis) + "' property");
  }
  if (format == "ascii") {
    check_ply_ascii(path, elements, lines);
    return expected;
  }
  // OpenMesh finds the binary body 12 bytes after the end of the last word before end_header (14 after CRLF):
  // anything but "LAST_WORD\nend_header\n" (a comment, a blank line or a trailing space before end_header) puts
  // it off by a few bytes and every value after shifted.
  const std::size_t line_start = static_cast<std::size_t>(line.data() - content.data());
  const std::size_t body = std::min(lines.offset(), content.size());
  const std::string_view newline = content.substr(line_start + line.size(), body - line_start - line.size());
  const std::size_t previous_end = static_cast<std::size_t>(previous.data() - content.data()) + previous.size();
  const std::vector<std::string_view> previous_tokens = split(previous);
  if (line != "end_header" || previous_tokens.empty() || previous_tokens[0] == "comment" ||
      std::isspace(static_cast<unsigned char>(previous.back())) ||
      content.substr(previous_end, line_start - previous_end) != newline)
    fail(path, line_no(lines.number()) + "a binary PLY header must end with 'end_header' on the line right after "
                                         "the last element or property line, with no spaces or comment between "
                                         "(OpenMesh misplaces the binary data otherwise)");
  check_ply_binary(path, elements, content.substr(body), format == "binary_big_endian");
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
