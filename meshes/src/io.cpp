#include "marchcheck/meshes/io.hpp"

#include "marchcheck/files/atomic_file.hpp"
#include "marchcheck/files/loadable_module.hpp"

#include "marchcheck/meshes/procedural.hpp"
#include "openmesh_io.hpp"
#include "preflight.hpp"

#include <bit>
#include <cfloat>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <unordered_map>

namespace marchcheck::meshes {
namespace {

namespace fs = std::filesystem;
using detail::Format;

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw MeshError(path + ": " + problem);
}

std::optional<Format> format_of(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return Format::obj;
  if (ext == ".off") return Format::off;
  if (ext == ".ply") return Format::ply;
  if (ext == ".stl") return Format::stl;
  return std::nullopt;
}

Format format_or_fail(const std::string& path) {
  const auto format = format_of(path);
  if (!format) {
    const std::string ext = fs::path(path).extension().string();
    fail(path, (ext.empty() ? std::string("no file extension") : "unknown extension '" + ext + "'") +
                   " (expected .obj, .off, .ply or .stl)");
  }
  return *format;
}

// Where the format starts counting vertices and faces (what a user sees in the file and in their tools).
std::uint32_t first_number(Format format) { return format == Format::off || format == Format::ply ? 0 : 1; }

const char* name_of(Format format) {
  switch (format) {
    case Format::obj: return "OBJ";
    case Format::off: return "OFF";
    case Format::ply: return "PLY";
    case Format::stl: return "STL";
  }
  return "";
}

std::string read_all(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) fail(path, "no such file");
  if (!fs::is_regular_file(status)) fail(path, "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open it for reading");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) fail(path, "cannot read it");
  return std::move(content).str();
}

// STL repeats each corner per facet; identical positions (-0 and +0 alike) become one vertex.
void merge_identical_vertices(Mesh& mesh) {
  struct Key {
    std::uint64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return std::hash<std::uint64_t>()(k.x ^ (k.y * 0x9E3779B97F4A7C15ull) ^ (k.z * 0xC2B2AE3D27D4EB4Full));
    }
  };
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v == 0 ? 0.0 : v); };
  std::unordered_map<Key, std::uint32_t, Hash> first;
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  std::vector<glm::dvec3> merged;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const glm::dvec3 p = mesh.vertices[i];
    const auto [it, inserted] = first.try_emplace(Key{bits(p.x), bits(p.y), bits(p.z)},
                                                  static_cast<std::uint32_t>(merged.size()));
    if (inserted) merged.push_back(p);
    remap[i] = it->second;
  }
  for (auto& triangle : mesh.triangles)
    for (auto& index : triangle) index = remap[index];
  mesh.vertices = std::move(merged);
  mesh.vertex_numbers.clear();  // a merged corner has no one number in the file
}

Mesh to_triangles(const std::string& path, Format format, const detail::Polygons& polygons) {
  Mesh mesh;
  if (polygons.vertices.size() > INT_MAX) fail(path, "too many vertices");
  const std::uint32_t first = first_number(format);
  const std::string numbered = " numbered from " + std::to_string(first);
  mesh.vertices = polygons.vertices;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const glm::dvec3 p = mesh.vertices[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(path, "vertex " + std::to_string(v + first) + " has a NaN or infinite coordinate (vertices" + numbered +
                     ")");
    mesh.vertex_numbers.push_back(static_cast<std::uint32_t>(v + first));
  }
  const std::size_t n_faces = polygons.offsets.size() - 1;
  for (std::size_t f = 0; f < n_faces; ++f) {
    const std::size_t begin = polygons.offsets[f], end = polygons.offsets[f + 1];
    const std::string face =
        "face " + std::to_string(f + first) + " of " + std::to_string(n_faces) + " (faces" + numbered + ")";
    if (end - begin < 3) fail(path, face + " has " + std::to_string(end - begin) + " vertices (at least 3 needed)");
    for (std::size_t k = begin; k < end; ++k) {
      const int index = polygons.indices[k];
      if (index < 0 || static_cast<std::size_t>(index) >= mesh.vertices.size())
        fail(path, face + " refers to a vertex that does not exist (vertex " +
                       std::to_string(static_cast<long long>(index) + first) + "; the file has " +
                       std::to_string(mesh.vertices.size()) + " vertices," + numbered + ")");
    }
    const auto at = [&](std::size_t k) { return static_cast<std::uint32_t>(polygons.indices[k]); };
    for (std::size_t k = begin + 1; k + 1 < end; ++k) {
      mesh.triangles.push_back({at(begin), at(k), at(k + 1)});
      mesh.face_numbers.push_back(static_cast<std::uint32_t>(f + first));
    }
  }
  if (mesh.triangles.empty()) fail(path, "no triangles in the file");
  return mesh;
}

void check_writable(const std::string& path, const Mesh& mesh) {
  if (mesh.triangles.empty()) fail(path, "cannot save a mesh without triangles");
  if (mesh.vertices.size() > INT_MAX || mesh.triangles.size() > INT_MAX) fail(path, "mesh too large to save");
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    for (int k = 0; k < 3; ++k)
      if (!(std::fabs(mesh.vertices[v][k]) <= FLT_MAX))
        fail(path, "cannot save vertex " + std::to_string(v) +
                       ": a coordinate is NaN, infinite or beyond the float range the formats store");
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const std::uint32_t index : mesh.triangles[t])
      if (index >= mesh.vertices.size())
        fail(path, "cannot save triangle " + std::to_string(t) + ": vertex " + std::to_string(index) +
                       " does not exist (" + std::to_string(mesh.vertices.size()) + " vertices)");
}

}  // namespace

Mesh load_mesh(const std::string& path) {
  const Format format = format_or_fail(path);
  const std::string content = read_all(path);
  if (content.empty()) fail(path, "the file is empty");
  const detail::Expected expected = detail::preflight(format, path, content);

  detail::Polygons polygons;
  std::string reason;
  if (!detail::openmesh().read(path, polygons, reason))
    fail(path, reason.empty() ? std::string("OpenMesh cannot read it as ") + name_of(format) +
                                    " (malformed or truncated)"
                              : reason);
  // OpenMesh skips what it cannot parse; a count that differs from the file's own means something was lost.
  const std::size_t n_faces = polygons.offsets.size() - 1;
  if (expected.vertices && polygons.vertices.size() != *expected.vertices)
    fail(path, "OpenMesh read " + std::to_string(polygons.vertices.size()) + " of the file's " +
                   std::to_string(*expected.vertices) + " vertices");
  if (expected.faces && n_faces != *expected.faces)
    fail(path, "OpenMesh read " + std::to_string(n_faces) + " of the file's " + std::to_string(*expected.faces) +
                   " faces");

  Mesh mesh = to_triangles(path, format, polygons);
  if (format == Format::stl) merge_identical_vertices(mesh);
  return mesh;
}

Mesh load_mesh_source(const std::string& source) {
  constexpr std::string_view kProcedural = "procedural:";
  if (source.starts_with(kProcedural)) {
    try {
      return procedural_mesh(source.substr(kProcedural.size())).mesh;
    } catch (const MeshError& e) {
      throw MeshError(std::string(kProcedural) + e.what());  // the spec and the problem, named as the scene names it
    }
  }
  return load_mesh(source);
}

void save_mesh(const Mesh& mesh, const std::string& path) {
  const Format format = format_or_fail(path);
  check_writable(path, mesh);
  try {
    files::write_atomically(path, [&](const std::string& temporary) {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) throw std::runtime_error("cannot create " + temporary + " (missing folder or no permission?)");
      std::string reason;
      const bool written = detail::openmesh().write(mesh, format, out, reason);
      out.close();  // the last buffer reaches the disk here: its failure counts too
      if (!written || out.fail()) throw std::runtime_error(reason.empty() ? "cannot write " + temporary + " (disk full?)" : reason);
    });
  } catch (const std::runtime_error& e) {
    throw MeshError(e.what());  // "PATH: problem"
  }
}

namespace detail {

const OpenMeshModule& openmesh() {
  static const OpenMeshModule& module = files::module_table<OpenMeshModule>(
      reinterpret_cast<const void*>(&openmesh), "libmarchcheck_openmesh.so", "marchcheck_openmesh_module");
  return module;
}

}  // namespace detail

}  // namespace marchcheck::meshes
