#include "marchcheck/meshes/procedural.hpp"

#include "marchcheck/meshes/closest_point.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <unordered_map>

namespace marchcheck::meshes {
namespace {

using glm::dvec3;
using Triangle = std::array<std::uint32_t, 3>;
constexpr double pi = std::numbers::pi;

void require(bool ok, const std::string& what) {
  if (!ok) throw MeshError(what);
}

bool positive(double x) { return std::isfinite(x) && x > 0; }

// Points of a triangle inside the ball lie at most r - |closest point to the centre| inside the sphere, and the
// ray from the centre through any sphere point crosses some triangle no nearer: so this is the Hausdorff distance
// (plus the rounding of vertex positions off the sphere).
double sphere_error(const Mesh& mesh, double radius) {
  double error = 0;
  for (const dvec3& v : mesh.vertices) error = std::max(error, std::fabs(glm::length(v) - radius));
  for (const Triangle& t : mesh.triangles) {
    TriangleFeature unused;
    const dvec3 q = closest_on_triangle(dvec3(0), {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]}, unused);
    error = std::max(error, radius - glm::length(q));
  }
  return error;
}

double angle_between(glm::dvec2 a, glm::dvec2 b) { return std::atan2(std::fabs(a.x * b.y - a.y * b.x), glm::dot(a, b)); }

}  // namespace

ProceduralMesh icosphere(double radius, int subdivisions) {
  require(positive(radius), "icosphere: radius must be positive and finite, got " + std::to_string(radius));
  require(subdivisions >= 0 && subdivisions <= 9,
          "icosphere: subdivisions must be 0..9, got " + std::to_string(subdivisions));
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<dvec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (dvec3& v : unit) v = glm::normalize(v);
  std::vector<Triangle> triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                     {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                     {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                     {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      const auto [it, inserted] = midpoints.try_emplace(key, static_cast<std::uint32_t>(unit.size()));
      if (inserted) unit.push_back(glm::normalize(unit[a] + unit[b]));
      return it->second;
    };
    std::vector<Triangle> finer;
    finer.reserve(triangles.size() * 4);
    for (const Triangle& tri : triangles) {
      const std::uint32_t ab = midpoint(tri[0], tri[1]), bc = midpoint(tri[1], tri[2]), ca = midpoint(tri[2], tri[0]);
      finer.push_back({tri[0], ab, ca});
      finer.push_back({tri[1], bc, ab});
      finer.push_back({tri[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    triangles = std::move(finer);
  }
  ProceduralMesh result;
  for (const dvec3& v : unit) result.mesh.vertices.push_back(v * radius);
  result.mesh.triangles = std::move(triangles);
  result.max_error = sphere_error(result.mesh, radius);
  return result;
}

ProceduralMesh uv_sphere(double radius, int stacks, int slices) {
  require(positive(radius), "uv_sphere: radius must be positive and finite, got " + std::to_string(radius));
  require(stacks >= 2 && slices >= 3 && static_cast<double>(stacks) * slices <= 1e8,
          "uv_sphere: need stacks >= 2, slices >= 3 and stacks·slices <= 1e8, got " + std::to_string(stacks) +
              " and " + std::to_string(slices));
  Mesh mesh;
  const auto n = static_cast<std::uint32_t>(slices);
  mesh.vertices.emplace_back(0, radius, 0);
  for (int k = 1; k < stacks; ++k) {
    const double theta = pi * k / stacks;
    for (int s = 0; s < slices; ++s) {
      const double phi = 2 * pi * s / slices;
      mesh.vertices.emplace_back(radius * std::sin(theta) * std::cos(phi), radius * std::cos(theta),
                                 radius * std::sin(theta) * std::sin(phi));
    }
  }
  mesh.vertices.emplace_back(0, -radius, 0);
  const auto south = static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  // Ring k (1-based) slice s; counter-clockwise from outside means the slice angle advances first, then the stack.
  const auto at = [n](int k, std::uint32_t s) { return 1 + static_cast<std::uint32_t>(k - 1) * n + s % n; };
  for (std::uint32_t s = 0; s < n; ++s) {
    mesh.triangles.push_back({0, at(1, s + 1), at(1, s)});
    for (int k = 1; k + 1 < stacks; ++k) {
      mesh.triangles.push_back({at(k, s), at(k, s + 1), at(k + 1, s + 1)});
      mesh.triangles.push_back({at(k, s), at(k + 1, s + 1), at(k + 1, s)});
    }
    mesh.triangles.push_back({south, at(stacks - 1, s), at(stacks - 1, s + 1)});
  }
  ProceduralMesh result{std::move(mesh), 0};
  result.max_error = sphere_error(result.mesh, radius);
  return result;
}

ProceduralMesh torus(double major, double minor, int rings, int sides) {
  require(positive(major) && positive(minor) && minor < major,
          "torus: need 0 < minor < major, got major " + std::to_string(major) + ", minor " + std::to_string(minor));
  require(rings >= 3 && sides >= 3 && static_cast<double>(rings) * sides <= 1e8,
          "torus: need rings >= 3, sides >= 3 and rings·sides <= 1e8, got " + std::to_string(rings) + " and " +
              std::to_string(sides));
  Mesh mesh;
  for (int i = 0; i < rings; ++i) {
    const double u = 2 * pi * i / rings;
    for (int j = 0; j < sides; ++j) {
      const double v = 2 * pi * j / sides;
      const double rho = major + minor * std::cos(v);
      mesh.vertices.emplace_back(rho * std::cos(u), minor * std::sin(v), rho * std::sin(u));
    }
  }
  const auto r = static_cast<std::uint32_t>(rings), s = static_cast<std::uint32_t>(sides);
  const auto at = [r, s](std::uint32_t i, std::uint32_t j) { return (i % r) * s + j % s; };
  // Counter-clockwise from outside: around the tube first, then around the axis.
  for (std::uint32_t i = 0; i < r; ++i)
    for (std::uint32_t j = 0; j < s; ++j) {
      mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }

  // Each patch of the surface between grid angles u_i..u_i+1 and v_j..v_j+1 maps onto its planar quad (the two
  // triangles) by bilinear interpolation of the corners, and the interpolation error is at most
  // du²/8·max|S_uu| + dv²/8·max|S_vv| = du²/8·rho_max + dv²/8·minor (linear interpolation error, once per
  // direction). That bounds both directions of the Hausdorff distance. du, dv, rho_max and the tube radius are
  // measured on the actual corners; the vertices' own rounding off the surface is added on top.
  const auto rho = [](dvec3 p) { return std::hypot(p.x, p.z); };
  const auto tube = [&](dvec3 p) { return glm::dvec2(rho(p) - major, p.y); };
  double error = 0, off_surface = 0;
  for (const dvec3& p : mesh.vertices) off_surface = std::max(off_surface, std::fabs(glm::length(tube(p)) - minor));
  for (std::uint32_t i = 0; i < r; ++i)
    for (std::uint32_t j = 0; j < s; ++j) {
      const dvec3 c00 = mesh.vertices[at(i, j)], c10 = mesh.vertices[at(i + 1, j)];
      const dvec3 c01 = mesh.vertices[at(i, j + 1)], c11 = mesh.vertices[at(i + 1, j + 1)];
      const double du = std::max(angle_between({c00.x, c00.z}, {c10.x, c10.z}),
                                 angle_between({c01.x, c01.z}, {c11.x, c11.z}));
      const double dv = std::max(angle_between(tube(c00), tube(c01)), angle_between(tube(c10), tube(c11)));
      const double rho_max = std::max({rho(c00), rho(c10), rho(c01), rho(c11)});
      const double tube_max = std::max({glm::length(tube(c00)), glm::length(tube(c10)), glm::length(tube(c01)),
                                        glm::length(tube(c11))});
      error = std::max(error, du * du / 8 * rho_max + dv * dv / 8 * tube_max);
    }
  return {std::move(mesh), error + off_surface};
}

ProceduralMesh box(glm::dvec3 half_size) {
  require(positive(half_size.x) && positive(half_size.y) && positive(half_size.z),
          "box: half sizes must be positive and finite");
  Mesh mesh;
  // Vertex i has +x if bit 0 is set, +y for bit 1, +z for bit 2.
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back((i & 1) ? half_size.x : -half_size.x, (i & 2) ? half_size.y : -half_size.y,
                               (i & 4) ? half_size.z : -half_size.z);
  // Two counter-clockwise triangles per face seen from outside: -z, +z, -y, +y, -x, +x.
  mesh.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return {std::move(mesh), 0};
}

ProceduralMesh notched_box(glm::dvec3 half_size) {
  require(positive(half_size.x) && positive(half_size.y) && positive(half_size.z),
          "notched_box: half sizes must be positive and finite");
  // Seven of the eight half-size cells of the box; a square face of a cell is on the surface where the
  // neighbouring cell is empty or outside, split into two triangles.
  auto filled = [](glm::ivec3 c) {
    return c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < 2 && c.y < 2 && c.z < 2 && !(c.x == 1 && c.y == 1 && c.z == 1);
  };
  Mesh mesh;
  std::unordered_map<int, std::uint32_t> index;  // grid point (x + 3y + 9z) -> vertex
  auto vertex = [&](glm::ivec3 g) {
    auto [it, added] = index.emplace(g.x + 3 * g.y + 9 * g.z, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (added) mesh.vertices.push_back(-half_size + dvec3(g) * half_size);
    return it->second;
  };
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) {
        const glm::ivec3 c(x, y, z);
        if (!filled(c)) continue;
        for (int axis = 0; axis < 3; ++axis)
          for (int side : {-1, 1}) {
            glm::ivec3 n = c;
            n[axis] += side;
            if (filled(n)) continue;
            // Corners in the order (u0 v0), (u1 v0), (u1 v1), (u0 v1) run counter-clockwise about +axis, since
            // e_u x e_v = e_axis for the cyclic u, v.
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            std::uint32_t q[4];
            for (int k = 0; k < 4; ++k) {
              glm::ivec3 g = c;
              g[axis] += side > 0 ? 1 : 0;
              g[u] += (k == 1 || k == 2) ? 1 : 0;
              g[v] += (k >= 2) ? 1 : 0;
              q[k] = vertex(g);
            }
            if (side < 0) std::swap(q[1], q[3]);
            mesh.triangles.push_back({q[0], q[1], q[2]});
            mesh.triangles.push_back({q[0], q[2], q[3]});
          }
      }
  return {std::move(mesh), 0};
}

ProceduralMesh procedural_mesh(const std::string& spec) {
  const auto open = spec.find('('), close = spec.rfind(')');
  if (open == std::string::npos || close != spec.size() - 1)
    throw MeshError(spec + ": expected NAME(ARGUMENTS), e.g. icosphere(1,4)");
  const std::string name = spec.substr(0, open);
  std::vector<double> a;
  std::istringstream args(spec.substr(open + 1, close - open - 1));
  for (std::string item; std::getline(args, item, ',');) {
    char* end = nullptr;
    a.push_back(std::strtod(item.c_str(), &end));
    if (end == item.c_str() || *end != 0) throw MeshError(spec + ": '" + item + "' is not a number");
  }
  auto need = [&](size_t n) {
    if (a.size() != n) throw MeshError(name + " takes " + std::to_string(n) + " arguments");
  };
  auto whole = [&](double x) {
    if (x != std::floor(x) || std::abs(x) > 1e6) throw MeshError(std::to_string(x) + " is not a count");
    return static_cast<int>(x);
  };
  try {
    if (name == "icosphere") {
      need(2);
      return icosphere(a[0], whole(a[1]));
    }
    if (name == "uv_sphere") {
      need(3);
      return uv_sphere(a[0], whole(a[1]), whole(a[2]));
    }
    if (name == "torus") {
      need(4);
      return torus(a[0], a[1], whole(a[2]), whole(a[3]));
    }
    if (name == "box") {
      need(3);
      return box({a[0], a[1], a[2]});
    }
    if (name == "notched_box") {
      need(3);
      return notched_box({a[0], a[1], a[2]});
    }
  } catch (const MeshError& e) {
    throw MeshError(spec + ": " + e.what());
  }
  throw MeshError(spec + ": unknown generator '" + name + "' (icosphere, uv_sphere, torus, box, notched_box)");
}

}  // namespace marchcheck::meshes
