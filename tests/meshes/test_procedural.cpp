// Procedural meshes: clean topology, outward orientation, and an error bound that holds and is tight, measured
// both ways (mesh samples against the analytic surface, surface samples against the mesh).
#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/io.hpp"
#include "marchcheck/meshes/procedural.hpp"
#include "mesh_test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>

namespace marchcheck::meshes {
namespace {

using glm::dvec3;
using namespace test;
constexpr double pi = std::numbers::pi;

struct Case {
  std::string name;
  std::function<ProceduralMesh()> make;
  std::function<double(dvec3)> distance;             // to the analytic surface
  std::function<dvec3(double, double)> surface;      // (s, t) in [0, 1)² onto the analytic surface
  double volume, area;                                // of the analytic solid and surface
};

dvec3 on_sphere(double radius, double s, double t) {
  const double theta = std::acos(1 - 2 * s), phi = 2 * pi * t;  // area-uniform in s
  return radius * dvec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
}

Case sphere_case(std::string name, double radius, std::function<ProceduralMesh()> make) {
  return {std::move(name), std::move(make), [radius](dvec3 p) { return sphere_distance(p, radius); },
          [radius](double s, double t) { return on_sphere(radius, s, t); }, 4.0 / 3 * pi * radius * radius * radius,
          4 * pi * radius * radius};
}

Case torus_case(std::string name, double major, double minor, int rings, int sides) {
  return {std::move(name), [=] { return torus(major, minor, rings, sides); },
          [=](dvec3 p) { return torus_distance(p, major, minor); },
          [=](double s, double t) {
            const double u = 2 * pi * s, v = 2 * pi * t, rho = major + minor * std::cos(v);
            return dvec3(rho * std::cos(u), minor * std::sin(v), rho * std::sin(u));
          },
          2 * pi * pi * major * minor * minor, 4 * pi * pi * major * minor};
}

Case box_case(std::string name, dvec3 half) {
  return {std::move(name), [=] { return box(half); }, [=](dvec3 p) { return box_distance(p, half); },
          [=](double s, double t) {
            // Six faces side by side along s.
            const int face = std::min(5, static_cast<int>(s * 6));
            const double a = 2 * (s * 6 - face) - 1, b = 2 * t - 1, sign = face % 2 ? 1 : -1;
            const int axis = face / 2;
            dvec3 p;
            p[axis] = sign * half[axis];
            p[(axis + 1) % 3] = a * half[(axis + 1) % 3];
            p[(axis + 2) % 3] = b * half[(axis + 2) % 3];
            return p;
          },
          8 * half.x * half.y * half.z, 8 * (half.x * half.y + half.y * half.z + half.z * half.x)};
}

// The largest distance found each way; grids fine enough to land near every face's worst point.
struct Measured {
  double mesh_to_surface = 0, surface_to_mesh = 0;
};

Measured measure(const Mesh& mesh, const Case& c, int surface_grid = 40) {
  Measured m;
  for_each_face_sample(mesh, 12, [&](dvec3 p) { m.mesh_to_surface = std::max(m.mesh_to_surface, c.distance(p)); });
  for (int i = 0; i < surface_grid; ++i)
    for (int j = 0; j < surface_grid; ++j) {
      const dvec3 p = c.surface((i + 0.5) / surface_grid, (j + 0.37) / surface_grid);
      m.surface_to_mesh = std::max(m.surface_to_mesh, mesh_distance(mesh, p));
    }
  return m;
}

// Fails when a sample lies beyond the bound, or when the bound is loose (no sample reaches half of it).
::testing::AssertionResult BoundHoldsAndIsTight(const Measured& m, double max_error) {
  std::ostringstream out;
  out << "max_error " << max_error << ", measured mesh->surface " << m.mesh_to_surface << ", surface->mesh "
      << m.surface_to_mesh;
  if (m.mesh_to_surface > max_error + 1e-12 || m.surface_to_mesh > max_error + 1e-12)
    return ::testing::AssertionFailure() << "bound exceeded: " << out.str();
  if (std::max(m.mesh_to_surface, m.surface_to_mesh) < 0.5 * max_error)
    return ::testing::AssertionFailure() << "bound loose: " << out.str();
  return ::testing::AssertionSuccess() << out.str();
}

class Procedural : public ::testing::TestWithParam<Case> {};

TEST_P(Procedural, IsClosedManifoldOutwardAndClean) {
  const ProceduralMesh p = GetParam().make();
  const MeshReport r = inspect(p.mesh);
  test::expect_clean(r);
  // The solids differ only within max_error of the surface: about area · max_error of volume (doubled for slack).
  EXPECT_NEAR(r.signed_volume, GetParam().volume, 2 * GetParam().area * p.max_error + 1e-12 * GetParam().volume);
}

TEST_P(Procedural, ErrorBoundHoldsBothWaysAndIsTight) {
  const ProceduralMesh p = GetParam().make();
  const Measured m = measure(p.mesh, GetParam());
  if (p.max_error == 0) {  // exact up to the rounding of the samples
    EXPECT_LE(m.mesh_to_surface, 1e-15 * GetParam().area);
    EXPECT_LE(m.surface_to_mesh, 1e-15 * GetParam().area);
  } else {
    EXPECT_TRUE(BoundHoldsAndIsTight(m, p.max_error));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, Procedural,
    ::testing::Values(sphere_case("icosphere_r1_s0", 1, [] { return icosphere(1, 0); }),
                      sphere_case("icosphere_r1_s1", 1, [] { return icosphere(1, 1); }),
                      sphere_case("icosphere_r2p5_s3", 2.5, [] { return icosphere(2.5, 3); }),
                      sphere_case("icosphere_r0p01_s4", 0.01, [] { return icosphere(0.01, 4); }),
                      sphere_case("uv_r1_2x3", 1, [] { return uv_sphere(1, 2, 3); }),
                      sphere_case("uv_r1_7x5", 1, [] { return uv_sphere(1, 7, 5); }),
                      sphere_case("uv_r1p5_16x32", 1.5, [] { return uv_sphere(1.5, 16, 32); }),
                      torus_case("torus_1_0p25_24x12", 1, 0.25, 24, 12),
                      torus_case("torus_2_0p5_6x4", 2, 0.5, 6, 4),
                      torus_case("torus_1_0p9_40x7", 1, 0.9, 40, 7),
                      torus_case("torus_3_0p1_64x5", 3, 0.1, 64, 5), box_case("box_1_2_0p5", {1, 2, 0.5}),
                      box_case("box_thin", {1e-3, 10, 1})),
    [](const auto& param_info) { return param_info.param.name; });

TEST(Procedural, CountsMatchTheConstruction) {
  for (int s = 0; s <= 4; ++s) {
    const Mesh m = icosphere(1, s).mesh;
    EXPECT_EQ(m.triangles.size(), 20u << (2 * s));
    EXPECT_EQ(m.vertices.size(), 10u * (1u << (2 * s)) + 2);
  }
  EXPECT_EQ(uv_sphere(1, 6, 9).mesh.triangles.size(), 2u * 9 * 5);
  EXPECT_EQ(uv_sphere(1, 6, 9).mesh.vertices.size(), 5u * 9 + 2);
  EXPECT_EQ(torus(1, 0.3, 10, 7).mesh.triangles.size(), 2u * 10 * 7);
  EXPECT_EQ(box({1, 1, 1}).mesh.triangles.size(), 12u);
}

TEST(Procedural, IcosphereVerticesLieOnTheSphere) {
  const ProceduralMesh p = icosphere(3, 4);
  for (const dvec3& v : p.mesh.vertices) EXPECT_NEAR(glm::length(v), 3, 1e-14);
}

TEST(Procedural, BoxIsExact) {
  const ProceduralMesh p = box({1, 2, 3});
  EXPECT_EQ(p.max_error, 0);
  for (const dvec3& v : p.mesh.vertices) {
    EXPECT_EQ(std::fabs(v.x), 1);
    EXPECT_EQ(std::fabs(v.y), 2);
    EXPECT_EQ(std::fabs(v.z), 3);
  }
  EXPECT_EQ(inspect(p.mesh).signed_volume, 48);
}

TEST(Procedural, NotchedBoxIsAClosedOutwardBoxLessOneOctant) {
  const ProceduralMesh p = notched_box({1, 2, 3});
  EXPECT_EQ(p.max_error, 0);
  EXPECT_EQ(p.mesh.triangles.size(), 48u);  // 24 cell faces on the surface, two triangles each
  const MeshReport r = inspect(p.mesh);
  EXPECT_TRUE(r.closed && r.manifold && r.consistently_oriented && r.outward);
  EXPECT_EQ(r.degenerate_faces, 0);
  EXPECT_EQ(r.signed_volume, 48 * 7.0 / 8);  // exact in double: sums of products of small integers
}

TEST(Procedural, SpecsNameTheGeneratorAndSourcesPickFileOrGenerator) {
  EXPECT_EQ(procedural_mesh("icosphere(2,3)").mesh.vertices, icosphere(2, 3).mesh.vertices);
  EXPECT_EQ(procedural_mesh("torus(1,0.25,12,6)").mesh.triangles, torus(1, 0.25, 12, 6).mesh.triangles);
  EXPECT_EQ(procedural_mesh("notched_box(1,2,3)").mesh.vertices, notched_box({1, 2, 3}).mesh.vertices);
  EXPECT_EQ(load_mesh_source("procedural:box(1,2,3)").vertices, box({1, 2, 3}).mesh.vertices);
  auto message = [](const std::string& source) {
    try {
      load_mesh_source(source);
    } catch (const MeshError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message("procedural:cube(1)"), "procedural:cube(1): unknown generator 'cube' (icosphere, uv_sphere, torus, box, notched_box)");
  EXPECT_EQ(message("procedural:icosphere(1)"), "procedural:icosphere(1): icosphere takes 2 arguments");
  EXPECT_EQ(message("procedural:icosphere(1,x)"), "procedural:icosphere(1,x): 'x' is not a number");
  EXPECT_EQ(message("procedural:icosphere(1,2.5)"), "procedural:icosphere(1,2.5): 2.500000 is not a count");
  EXPECT_EQ(message("procedural:icosphere"), "procedural:icosphere: expected NAME(ARGUMENTS), e.g. icosphere(1,4)");
  EXPECT_EQ(message("/no/such/mesh.obj").rfind("/no/such/mesh.obj: ", 0), 0u);
}

TEST(Procedural, IcosphereErrorQuartersPerSubdivision) {
  double previous = icosphere(1, 0).max_error;
  for (int s = 1; s <= 6; ++s) {
    const double error = icosphere(1, s).max_error;
    const double ratio = previous / error;
    EXPECT_GT(ratio, s == 1 ? 3.0 : 3.5) << "subdivision " << s;
    EXPECT_LT(ratio, 4.5) << "subdivision " << s;
    previous = error;
  }
  // Sagitta of the longest edge at subdivision 6 is about L²/8 with L ≈ 1.1/64.
  EXPECT_LT(previous, 1e-4);
}

TEST(Procedural, ErrorScalesWithRadius) {
  EXPECT_NEAR(icosphere(5, 3).max_error, 5 * icosphere(1, 3).max_error, 1e-14);
  EXPECT_NEAR(torus(2, 0.5, 30, 20).max_error, 2 * torus(1, 0.25, 30, 20).max_error, 1e-14);
}

// The bound check must be able to fail: a dented sphere exceeds the bound, an inflated bound is loose.
TEST(Procedural, BoundCheckCatchesADentAndALooseBound) {
  const Case c = sphere_case("icosphere", 1, [] { return icosphere(1, 3); });
  ProceduralMesh p = c.make();
  EXPECT_TRUE(BoundHoldsAndIsTight(measure(p.mesh, c), p.max_error));
  EXPECT_FALSE(BoundHoldsAndIsTight(measure(p.mesh, c), 3 * p.max_error));
  p.mesh.vertices[17] *= 1 - 3 * p.max_error;
  EXPECT_FALSE(BoundHoldsAndIsTight(measure(p.mesh, c), p.max_error));

  const Case t = torus_case("torus", 1, 0.25, 24, 12);
  ProceduralMesh q = t.make();
  q.mesh.vertices[5] += dvec3(0, 3 * q.max_error, 0);  // lifts a vertex off the tube
  EXPECT_FALSE(BoundHoldsAndIsTight(measure(q.mesh, t), q.max_error));
}

TEST(Procedural, BadParametersThrowMeshError) {
  const double nan = std::nan("");
  EXPECT_THROW(icosphere(-1, 2), MeshError);
  EXPECT_THROW(icosphere(nan, 2), MeshError);
  EXPECT_THROW(icosphere(1, -1), MeshError);
  EXPECT_THROW(icosphere(1, 10), MeshError);
  EXPECT_THROW(uv_sphere(0, 4, 8), MeshError);
  EXPECT_THROW(uv_sphere(1, 1, 8), MeshError);
  EXPECT_THROW(uv_sphere(1, 4, 2), MeshError);
  EXPECT_THROW(torus(1, 1, 8, 8), MeshError);
  EXPECT_THROW(torus(1, 0, 8, 8), MeshError);
  EXPECT_THROW(torus(1, 0.5, 2, 8), MeshError);
  EXPECT_THROW(torus(1, 0.5, 8, 2), MeshError);
  EXPECT_THROW(box({0, 1, 1}), MeshError);
  EXPECT_THROW(box({1, nan, 1}), MeshError);
  try {
    icosphere(1, 12);
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("subdivisions"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace marchcheck::meshes
