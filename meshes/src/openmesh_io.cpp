#include "openmesh_io.hpp"

// MeshIO.hh first: it registers the readers and writers (and must precede any kernel header).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/BaseKernel.hh>

#include <glm/geometric.hpp>

#include <mutex>
#include <ostream>

namespace marchcheck::meshes::detail {
namespace {

using namespace OpenMesh;
using IO::BaseExporter;
using IO::BaseImporter;
using StatusInfo = Attributes::StatusInfo;

// OpenMesh's IOManager and reader singletons keep state: one file at a time.
std::mutex& openmesh_mutex() {
  static std::mutex mutex;
  return mutex;
}

void silence_openmesh() {
  static const bool once = [] {
    omlog().disable();
    omerr().disable();
    omout().disable();
    return true;
  }();
  (void)once;
}

// Records vertices and polygons verbatim; everything else a reader may offer is ignored.
class Recorder final : public BaseImporter {
 public:
  explicit Recorder(Polygons& out) : out_(out) {}

  VertexHandle add_vertex(const Vec3f& p) override { return push(glm::dvec3(p[0], p[1], p[2])); }
  VertexHandle add_vertex(const Vec3d& p) override { return push(glm::dvec3(p[0], p[1], p[2])); }
  VertexHandle add_vertex() override { return push(glm::dvec3(0)); }
  void set_point(VertexHandle vh, const Vec3f& p) override {
    if (vh.idx() >= 0 && static_cast<std::size_t>(vh.idx()) < out_.vertices.size())
      out_.vertices[static_cast<std::size_t>(vh.idx())] = glm::dvec3(p[0], p[1], p[2]);
  }
  FaceHandle add_face(const VHandles& handles) override {
    for (const VertexHandle vh : handles) out_.indices.push_back(vh.idx());
    out_.offsets.push_back(out_.indices.size());
    return FaceHandle(static_cast<int>(out_.offsets.size() - 2));
  }
  std::size_t n_vertices() const override { return out_.vertices.size(); }
  std::size_t n_faces() const override { return out_.offsets.size() - 1; }
  std::size_t n_edges() const override { return 0; }

  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  VertexHandle push(glm::dvec3 p) {
    out_.vertices.push_back(p);
    return VertexHandle(static_cast<int>(out_.vertices.size() - 1));
  }
  Polygons& out_;
};

// Hands a validated Mesh to the writers: positions, triangles and face normals, nothing else.
class Feeder final : public BaseExporter {
 public:
  explicit Feeder(const Mesh& mesh) : mesh_(mesh) {}

  Vec3f point(VertexHandle vh) const override {
    const glm::dvec3 p = vertex(vh);
    return Vec3f(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
  }
  Vec3d pointd(VertexHandle vh) const override {
    const glm::dvec3 p = vertex(vh);
    return Vec3d(p.x, p.y, p.z);
  }
  bool is_point_double() const override { return true; }
  unsigned int get_vhandles(FaceHandle fh, std::vector<VertexHandle>& out) const override {
    out.clear();
    for (const std::uint32_t i : mesh_.triangles[static_cast<std::size_t>(fh.idx())])
      out.emplace_back(static_cast<int>(i));
    return 3;
  }
  Vec3f normal(FaceHandle fh) const override {
    const Vec3d n = normald(fh);
    return Vec3f(static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2]));
  }
  Vec3d normald(FaceHandle fh) const override {
    const auto& t = mesh_.triangles[static_cast<std::size_t>(fh.idx())];
    const glm::dvec3 a = mesh_.vertices[t[0]], b = mesh_.vertices[t[1]], c = mesh_.vertices[t[2]];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double length = glm::length(n);
    return length > 0 ? Vec3d(n.x / length, n.y / length, n.z / length) : Vec3d(0, 0, 0);
  }
  const BaseKernel* kernel() override { return &no_properties_; }  // the PLY writer asks it for custom properties
  std::size_t n_vertices() const override { return mesh_.vertices.size(); }
  std::size_t n_faces() const override { return mesh_.triangles.size(); }
  std::size_t n_edges() const override { return 0; }
  bool is_triangle_mesh() const override { return true; }

  Vec3f normal(VertexHandle) const override { return {0, 0, 0}; }
  Vec3d normald(VertexHandle) const override { return {0, 0, 0}; }
  bool is_normal_double() const override { return true; }
  Vec3uc color(VertexHandle) const override { return {0, 0, 0}; }
  Vec4uc colorA(VertexHandle) const override { return {0, 0, 0, 0}; }
  Vec3ui colori(VertexHandle) const override { return {0, 0, 0}; }
  Vec4ui colorAi(VertexHandle) const override { return {0, 0, 0, 0}; }
  Vec3f colorf(VertexHandle) const override { return {0, 0, 0}; }
  Vec4f colorAf(VertexHandle) const override { return {0, 0, 0, 0}; }
  Vec2f texcoord(VertexHandle) const override { return {0, 0}; }
  Vec2f texcoord(HalfedgeHandle) const override { return {0, 0}; }
  StatusInfo status(VertexHandle) const override { return {}; }
  HalfedgeHandle getHeh(FaceHandle, VertexHandle) const override { return HalfedgeHandle(); }
  unsigned int get_face_texcoords(std::vector<Vec2f>& out) const override {
    out.clear();
    return 0;
  }
  Vec3uc color(FaceHandle) const override { return {0, 0, 0}; }
  Vec4uc colorA(FaceHandle) const override { return {0, 0, 0, 0}; }
  Vec3ui colori(FaceHandle) const override { return {0, 0, 0}; }
  Vec4ui colorAi(FaceHandle) const override { return {0, 0, 0, 0}; }
  Vec3f colorf(FaceHandle) const override { return {0, 0, 0}; }
  Vec4f colorAf(FaceHandle) const override { return {0, 0, 0, 0}; }
  StatusInfo status(FaceHandle) const override { return {}; }
  Vec3uc color(EdgeHandle) const override { return {0, 0, 0}; }
  Vec4uc colorA(EdgeHandle) const override { return {0, 0, 0, 0}; }
  Vec3ui colori(EdgeHandle) const override { return {0, 0, 0}; }
  Vec4ui colorAi(EdgeHandle) const override { return {0, 0, 0, 0}; }
  Vec3f colorf(EdgeHandle) const override { return {0, 0, 0}; }
  Vec4f colorAf(EdgeHandle) const override { return {0, 0, 0, 0}; }
  StatusInfo status(EdgeHandle) const override { return {}; }
  int get_halfedge_id(VertexHandle) override { return -1; }
  int get_halfedge_id(FaceHandle) override { return -1; }
  int get_next_halfedge_id(HalfedgeHandle) override { return -1; }
  int get_to_vertex_id(HalfedgeHandle) override { return -1; }
  int get_face_id(HalfedgeHandle) override { return -1; }
  StatusInfo status(HalfedgeHandle) const override { return {}; }

 private:
  glm::dvec3 vertex(VertexHandle vh) const { return mesh_.vertices[static_cast<std::size_t>(vh.idx())]; }
  const Mesh& mesh_;
  BaseKernel no_properties_;
};

const char* extension(Format format) {
  switch (format) {
    case Format::obj: return "obj";
    case Format::off: return "off";
    case Format::ply: return "ply";
    case Format::stl: return "stl";
  }
  return "";
}

bool read(const std::string& path, Polygons& out, std::string& reason) {
  const std::lock_guard lock(openmesh_mutex());
  silence_openmesh();
  out = Polygons{};
  try {
    Recorder recorder(out);
    IO::Options options;
    return IO::IOManager().read(path, recorder, options);
  } catch (const std::exception& e) {
    reason = std::string("OpenMesh failed reading it (") + e.what() + ")";
    return false;
  }
}

bool write(const Mesh& mesh, Format format, std::ostream& out, std::string& reason) {
  const std::lock_guard lock(openmesh_mutex());
  silence_openmesh();
  try {
    Feeder feeder(mesh);
    IO::Options options;
    if (format == Format::ply || format == Format::stl) options += IO::Options::Binary;
    // 17 digits print every float exactly (the writers convert positions to float).
    if (IO::IOManager().write(out, extension(format), feeder, options, 17)) return true;
    reason = "the OpenMesh writer failed";
  } catch (const std::exception& e) {
    reason = std::string("the OpenMesh writer failed (") + e.what() + ")";
  }
  return false;
}

constexpr OpenMeshModule kModule{read, write};

}  // namespace
}  // namespace marchcheck::meshes::detail

extern "C" const marchcheck::meshes::detail::OpenMeshModule* marchcheck_openmesh_module() {
  return &marchcheck::meshes::detail::kModule;
}
