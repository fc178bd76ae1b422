// Meshes of analytic surfaces with a known error bound: closed, manifold, outward (counter-clockwise from outside).
#pragma once

#include "marchcheck/meshes/mesh.hpp"

#include <glm/vec3.hpp>

#include <string>

namespace marchcheck::meshes {

// max_error bounds the distance from any point of the analytic surface to the mesh, and from any point of the
// mesh to the analytic surface (the Hausdorff distance), computed from the triangles actually built.
struct ProceduralMesh {
  Mesh mesh;
  double max_error = 0;
};

// Sphere of the given radius about the origin; every vertex lies on it. 20·4^subdivisions triangles
// (subdivisions 0..9). The error roughly quarters with each subdivision.
ProceduralMesh icosphere(double radius, int subdivisions);

// Latitude/longitude sphere about the origin, poles on the y axis: stacks >= 2 bands, slices >= 3 segments.
ProceduralMesh uv_sphere(double radius, int stacks, int slices);

// The SDF torus: centre circle of radius major in the xz plane, tube radius minor (0 < minor < major); rings
// segments around the y axis (>= 3), sides segments around the tube (>= 3).
ProceduralMesh torus(double major, double minor, int rings, int sides);

// Axis-aligned box about the origin, 12 triangles, exact (max_error = 0).
ProceduralMesh box(glm::dvec3 half_size);

// The same box with its +x +y +z octant cut away: sharp convex and concave edges, and vertices where coplanar
// triangles meet at many angles. 48 triangles, exact (max_error = 0).
ProceduralMesh notched_box(glm::dvec3 half_size);

// A generator by name and arguments: "icosphere(R,N)", "uv_sphere(R,STACKS,SLICES)", "torus(MAJOR,MINOR,RINGS,SIDES)",
// "box(HX,HY,HZ)", "notched_box(HX,HY,HZ)". Throws MeshError naming the spec and the problem.
ProceduralMesh procedural_mesh(const std::string& spec);

}  // namespace marchcheck::meshes
