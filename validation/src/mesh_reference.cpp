// CGAL lives in this file alone: it is slow to compile and adds -frounding-math to whatever links it.
#include "marchcheck/validation/mesh_reference.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <map>

namespace marchcheck::validation {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;
using Triangles = std::vector<K::Triangle_3>;
// A triangle soup: distances and ray hits work for any mesh, open or non-manifold.
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
using Inside = CGAL::Side_of_triangle_mesh<SurfaceMesh, K>;

K::Point_3 point(glm::dvec3 p) { return {p.x, p.y, p.z}; }
glm::dvec3 vec(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }

// Closed and manifold: every edge has exactly two faces, traversed once in each direction.
bool is_closed(const meshes::Mesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) ++directed[{t[static_cast<size_t>(i)], t[static_cast<size_t>((i + 1) % 3)]}];
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    auto twin = directed.find({edge.second, edge.first});
    if (twin == directed.end() || twin->second != 1) return false;
  }
  return !mesh.triangles.empty();
}

}  // namespace

struct MeshReference::Impl {
  Triangles triangles;
  std::unique_ptr<Tree> tree;
  SurfaceMesh surface;  // closed meshes only, for the inside test
  std::unique_ptr<Inside> inside;
};

MeshReference::MeshReference(const meshes::Mesh& mesh) : impl_(std::make_unique<Impl>()) {
  for (const auto& t : mesh.triangles)
    impl_->triangles.emplace_back(point(mesh.vertices[t[0]]), point(mesh.vertices[t[1]]), point(mesh.vertices[t[2]]));
  impl_->tree = std::make_unique<Tree>(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree->accelerate_distance_queries();
  if (is_closed(mesh)) {
    std::vector<SurfaceMesh::Vertex_index> ids;
    for (const auto& v : mesh.vertices) ids.push_back(impl_->surface.add_vertex(point(v)));
    for (const auto& t : mesh.triangles) impl_->surface.add_face(ids[t[0]], ids[t[1]], ids[t[2]]);
    impl_->inside = std::make_unique<Inside>(impl_->surface);
    // The inside test builds its own tree on first use: build it now, while no other thread can call it.
    (*impl_->inside)(point(mesh.vertices[0] + glm::dvec3(1e-3)));
  }
}

MeshReference::~MeshReference() = default;

bool MeshReference::closed() const { return impl_->inside != nullptr; }

double MeshReference::unsigned_distance(glm::dvec3 p) const {
  return std::sqrt(impl_->tree->squared_distance(point(p)));
}

glm::dvec3 MeshReference::closest_point(glm::dvec3 p) const { return vec(impl_->tree->closest_point(point(p))); }

std::optional<double> MeshReference::signed_distance(glm::dvec3 p) const {
  if (!impl_->inside) return std::nullopt;
  const double d = unsigned_distance(p);
  return (*impl_->inside)(point(p)) == CGAL::ON_BOUNDED_SIDE ? -d : d;
}

ReferenceHit MeshReference::first_hit(glm::dvec3 o, glm::dvec3 d, double t_max) const {
  ReferenceHit out;
  const K::Ray_3 ray(point(o), K::Vector_3(d.x, d.y, d.z));
  const auto hit = impl_->tree->first_intersection(ray);
  if (!hit) return out;
  const K::Point_3* at = boost::get<K::Point_3>(&hit->first);
  if (!at) return out;  // the ray runs along a face: no single first point
  const double t = glm::dot(vec(*at) - o, d);
  if (t > t_max) return out;
  if (impl_->inside && (*impl_->inside)(point(o)) == CGAL::ON_BOUNDED_SIDE) {
    out.inside = true;
    return out;
  }
  out.hit = true;
  out.t = t;
  // Counter-clockwise seen from outside: the cross product of the edges faces out.
  const K::Vector_3 n = CGAL::cross_product(hit->second->vertex(1) - hit->second->vertex(0),
                                            hit->second->vertex(2) - hit->second->vertex(0));
  out.normal = glm::normalize(glm::dvec3(n.x(), n.y(), n.z()));
  return out;
}

bool MeshReference::visible(glm::dvec3 a, glm::dvec3 b) const {
  return !impl_->tree->do_intersect(K::Segment_3(point(a), point(b)));
}

}  // namespace marchcheck::validation
