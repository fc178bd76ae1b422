// CGAL lives in this file alone: it is slow to compile and adds -frounding-math to whatever links it.
#include "marchcheck/validation/mesh_reference.hpp"

#include "marchcheck/meshes/cgal_surface.hpp"
#include "marchcheck/meshes/checks.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Side_of_triangle_mesh.h>

#include <algorithm>
#include <iterator>
#include <map>

namespace marchcheck::validation {

namespace {

using K = meshes::cgal::Kernel;
using SurfaceMesh = meshes::cgal::SurfaceMesh;
using Triangles = std::vector<K::Triangle_3>;
// A triangle soup: distances and ray hits work for any mesh, open or non-manifold.
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
using Inside = CGAL::Side_of_triangle_mesh<SurfaceMesh, K>;

K::Point_3 point(glm::dvec3 p) { return {p.x, p.y, p.z}; }
glm::dvec3 vec(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

struct MeshReference::Impl {
  Triangles triangles;
  std::unique_ptr<Tree> tree;
  SurfaceMesh surface;  // closed meshes only, for the inside test
  std::unique_ptr<Inside> inside;
};

MeshReference::MeshReference(const meshes::Mesh& mesh) : MeshReference(mesh, meshes::inspect(mesh)) {}

MeshReference::MeshReference(const meshes::Mesh& mesh, const meshes::MeshReport& report)
    : impl_(std::make_unique<Impl>()) {
  for (const auto& t : mesh.triangles)
    impl_->triangles.emplace_back(point(mesh.vertices[t[0]]), point(mesh.vertices[t[1]]), point(mesh.vertices[t[2]]));
  impl_->tree = std::make_unique<Tree>(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree->accelerate_distance_queries();
  // Only a solid has an inside; its surface holds every face or surface_mesh throws (a reference that dropped the
  // faces around a pinch once answered wrongly beside it).
  if (meshes::solid_problem(report, mesh).empty()) {
    impl_->surface = meshes::cgal::surface_mesh(mesh);
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

Spans MeshReference::spans(glm::dvec3 o, glm::dvec3 d) const {
  if (!impl_->inside) return {};
  const K::Line_3 line(point(o), K::Vector_3(d.x, d.y, d.z));
  std::vector<Tree::Intersection_and_primitive_id<K::Line_3>::Type> hits;
  impl_->tree->all_intersections(line, std::back_inserter(hits));
  struct Crossing {
    double t;
    glm::dvec3 n;
  };
  std::vector<Crossing> crossings;
  const double dd = glm::dot(d, d);
  for (const auto& h : hits) {
    const K::Point_3* at = boost::get<K::Point_3>(&h.first);
    if (!at) continue;  // the line lies in the face's plane: the faces around it bound the solid
    const K::Vector_3 n = CGAL::cross_product(h.second->vertex(1) - h.second->vertex(0),
                                              h.second->vertex(2) - h.second->vertex(0));
    crossings.push_back({glm::dot(vec(*at) - o, d) / dd, glm::normalize(glm::dvec3(n.x(), n.y(), n.z()))});
  }
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) { return a.t < b.t; });
  // Crossings at one point (an edge or vertex shared by several faces) form a group; between groups the line is
  // wholly inside or outside. When every group is one face crossed inside, the line alternates out, in, out;
  // otherwise (an edge or vertex crossed, counted once per face, or only touched) the exact side test at the
  // middle of each gap decides.
  struct Group {
    double t;
    glm::dvec3 entry, exit;  // the face normals most against and most along the line
    int faces;
  };
  std::vector<Group> groups;
  double most_against = 0, most_along = 0;
  for (const auto& c : crossings) {
    const double along = glm::dot(c.n, d);
    if (groups.empty() || c.t > groups.back().t + 1e-12 * (1 + std::abs(groups.back().t))) {
      groups.push_back({c.t, c.n, c.n, 0});
      most_against = most_along = along;
    }
    ++groups.back().faces;
    if (along < most_against) {
      groups.back().entry = c.n;
      most_against = along;
    }
    if (along > most_along) {
      groups.back().exit = c.n;
      most_along = along;
    }
  }
  const bool alternating = groups.size() % 2 == 0 &&
                           std::all_of(groups.begin(), groups.end(), [](const Group& g) { return g.faces == 1; });
  Spans out;
  for (size_t k = 0; k + 1 < groups.size(); ++k) {
    const glm::dvec3 middle = o + d * (0.5 * (groups[k].t + groups[k + 1].t));
    if (alternating ? k % 2 == 1 : (*impl_->inside)(point(middle)) != CGAL::ON_BOUNDED_SIDE) continue;
    if (!out.empty() && out.back().t1 == groups[k].t) {
      out.back().t1 = groups[k + 1].t;  // inside on both sides of a touching point
      out.back().n1 = groups[k + 1].exit;
    } else {
      out.push_back({groups[k].t, groups[k + 1].t, groups[k].entry, groups[k + 1].exit});
    }
  }
  return out;
}

bool MeshReference::visible(glm::dvec3 a, glm::dvec3 b) const {
  return !impl_->tree->do_intersect(K::Segment_3(point(a), point(b)));
}

}  // namespace marchcheck::validation
