// CGAL lives in this file alone within meshes/: it is slow to compile and adds -frounding-math to what links it.
#include "marchcheck/meshes/cgal_surface.hpp"

#include "../src/self_intersections.hpp"

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <algorithm>
#include <iterator>
#include <string>
#include <utility>

namespace marchcheck::meshes {

namespace PMP = CGAL::Polygon_mesh_processing;

cgal::SurfaceMesh cgal::surface_mesh(const Mesh& mesh) {
  std::vector<Kernel::Point_3> points;
  points.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) points.emplace_back(v.x, v.y, v.z);
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) faces.push_back({t[0], t[1], t[2]});
  // Adding faces one by one (add_face) fails for some orders even on a manifold and says nothing; the soup
  // conversion takes them all at once, in order (face i is triangle i), where the soup is a surface at all.
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces))
    throw MeshError("the triangles form no oriented manifold surface for CGAL");
  SurfaceMesh surface;
  PMP::polygon_soup_to_polygon_mesh(points, faces, surface);
  if (surface.number_of_faces() != mesh.triangles.size())
    throw MeshError("CGAL took " + std::to_string(surface.number_of_faces()) + " of the " +
                    std::to_string(mesh.triangles.size()) + " triangles");
  return surface;
}

std::vector<std::array<std::size_t, 2>> crossing_triangles(const Mesh& mesh) {
  const cgal::SurfaceMesh surface = cgal::surface_mesh(mesh);
  std::vector<std::pair<cgal::SurfaceMesh::Face_index, cgal::SurfaceMesh::Face_index>> pairs;
  PMP::self_intersections(surface, std::back_inserter(pairs));
  std::vector<std::array<std::size_t, 2>> crossings;
  crossings.reserve(pairs.size());
  for (const auto& [a, b] : pairs) crossings.push_back({std::min<std::size_t>(a, b), std::max<std::size_t>(a, b)});
  std::sort(crossings.begin(), crossings.end());
  return crossings;
}

}  // namespace marchcheck::meshes
