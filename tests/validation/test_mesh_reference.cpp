// CGAL mesh references against closed forms, across file formats, and the user-facing test helpers.
#include "marchcheck/march/marcher.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/meshes/io.hpp"
#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/validation/gtest_helpers.hpp"
#include "../meshes/mesh_test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

namespace marchcheck::validation {
namespace {

using glm::dvec3;

TEST(MeshReference, IcosphereDistancesMatchTheSphereWithinTheChordError) {
  const auto sphere = meshes::icosphere(1.0, 4);
  const MeshReference ref(sphere.mesh);
  ASSERT_TRUE(ref.closed());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  for (int i = 0; i < 500; ++i) {
    const dvec3 p(u(rng), u(rng), u(rng));
    const auto d = ref.signed_distance(p);
    ASSERT_TRUE(d.has_value());
    // The mesh lies between radius 1 - max_error and 1: distances differ by at most the chord error.
    EXPECT_NEAR(*d, glm::length(p) - 1, sphere.max_error + 1e-12);
  }
  // A wrong radius is caught: the check can fail.
  EXPECT_GT(std::abs(*ref.signed_distance({1.5, 0, 0}) - (1.5 - 1.1)), sphere.max_error);
}

TEST(MeshReference, RayHitsMatchTheSphereWithinTheChordError) {
  const auto sphere = meshes::icosphere(1.0, 5);
  const MeshReference ref(sphere.mesh);
  for (double b : {0.0, 0.3, 0.6}) {
    const auto hit = ref.first_hit({0, b, -5}, {0, 0, 1}, 100);
    ASSERT_TRUE(hit.hit);
    const double exact = 5 - std::sqrt(1 - b * b), cos_i = std::sqrt(1 - b * b);
    EXPECT_NEAR(hit.t, exact, sphere.max_error / cos_i + 1e-9) << b;
    EXPECT_GT(glm::dot(hit.normal, dvec3(0, b, -cos_i)), 0.99);
  }
  EXPECT_FALSE(ref.first_hit({0, 1.5, -5}, {0, 0, 1}, 100).hit);
  EXPECT_TRUE(ref.first_hit({0, 0, 0}, {0, 0, 1}, 100).inside);
  EXPECT_FALSE(ref.visible({0, 0, -3}, {0, 0, 3}));
  EXPECT_TRUE(ref.visible({0, 2, -3}, {0, 2, 3}));
}

TEST(MeshReference, EveryFileFormatGivesTheSameDistances) {
  const auto sphere = meshes::icosphere(1.0, 3);
  const auto dir = std::filesystem::temp_directory_path() / ("marchcheck_formats_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const MeshReference original(sphere.mesh);
  for (const char* ext : {".obj", ".off", ".ply", ".stl"}) {
    const std::string path = (dir / (std::string("sphere") + ext)).string();
    meshes::save_mesh(sphere.mesh, path);
    const MeshReference loaded(meshes::load_mesh(path));
    EXPECT_TRUE(loaded.closed()) << ext;
    for (const dvec3 p : {dvec3(1.7, 0.2, -0.4), dvec3(0.1, 0.3, 0.2), dvec3(-3, 2, 1)})
      // Formats that store float coordinates move vertices by up to 6e-8 relative.
      EXPECT_NEAR(*loaded.signed_distance(p), *original.signed_distance(p), 1e-6) << ext;
  }
  std::filesystem::remove_all(dir);
}

// A pinched vertex: the reference gives no sign (it once built its inside test from the faces CGAL's add_face
// took, dropped those around the pinch, and was wrong at 2% of points near it), while its distances and ray hits
// use every face. Broken variants: the inside test built anyway; a face left out of the soup.
TEST(MeshReference, APinchedMeshGetsNoSignAndKeepsEveryFace) {
  const meshes::Mesh cone = meshes::test::pinched_double_cone();
  const meshes::MeshReport report = meshes::inspect(cone);
  ASSERT_TRUE(report.closed && report.consistently_oriented);
  ASSERT_EQ(report.nonmanifold_vertices, 1);
  const MeshReference ref(cone);
  EXPECT_FALSE(ref.closed());
  int checked = 0;
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  for (int i = 0; i < 400; ++i) {
    const dvec3 p(u(rng), u(rng), u(rng));
    EXPECT_FALSE(ref.signed_distance(p).has_value());
    // Brute force over every face (mesh_test_support) to double rounding at unit scale.
    EXPECT_NEAR(ref.unsigned_distance(p), meshes::test::mesh_distance(cone, p), 1e-12) << p.x << " " << p.y << " " << p.z;
    ++checked;
  }
  EXPECT_EQ(checked, 400);
  // Straight down the axis from above: the upper base at y = 1, whichever faces CGAL would have kept.
  const ReferenceHit down = ref.first_hit({0.01, 3, 0.02}, {0, -1, 0}, 10);
  ASSERT_TRUE(down.hit);
  EXPECT_NEAR(down.t, 2, 1e-12);
  // From below, through the lower cone's base at y = -1 (the part a dropped fan would lose).
  const ReferenceHit up = ref.first_hit({0.01, -3, 0.02}, {0, 1, 0}, 10);
  ASSERT_TRUE(up.hit);
  EXPECT_NEAR(up.t, 2, 1e-12);
}

TEST(MeshReference, OpenMeshesGiveUnsignedDistancesOnly) {
  auto open = meshes::icosphere(1.0, 2).mesh;
  open.triangles.pop_back();
  const MeshReference ref(open);
  EXPECT_FALSE(ref.closed());
  EXPECT_FALSE(ref.signed_distance({0, 0, 0}).has_value());
  EXPECT_NEAR(ref.unsigned_distance({0, 3, 0}), 2.0, 0.1);
}

TEST(Helpers, BoundOfMeshPassesForTheSphereSdfAndFailsForAnOverestimate) {
  const auto sphere = meshes::icosphere(1.0, 4);
  const dvec3 lo(-2), hi(2);
  // The exact sphere SDF scaled by 0.9 is a bound (within the chord error of the mesh).
  EXPECT_TRUE(IsBoundOfMesh([](dvec3 p) { return 0.9 * (glm::length(p) - 1); }, sphere.mesh, {lo, hi}, sphere.max_error));
  EXPECT_FALSE(IsBoundOfMesh([](dvec3 p) { return 2 * (glm::length(p) - 1); }, sphere.mesh, {lo, hi}, sphere.max_error));
  EXPECT_FALSE(IsBoundOfMesh([](dvec3 p) { return 1 - glm::length(p); }, sphere.mesh, {lo, hi}, sphere.max_error))
      << "flipped sign";
}

TEST(Helpers, LipschitzAtMostCatchesASteepField) {
  EXPECT_TRUE(LipschitzAtMost([](dvec3 p) { return glm::length(p) - 1; }, 1.0, {dvec3(-2), dvec3(2)}));
  EXPECT_FALSE(LipschitzAtMost([](dvec3 p) { return 1.5 * (glm::length(p) - 1); }, 1.0, {dvec3(-2), dvec3(2)}));
}

TEST(Helpers, MarcherMatchesReferenceOnAMesh) {
  const auto sphere = meshes::icosphere(1.0, 5);
  const MeshReference ref(sphere.mesh);
  std::vector<TestRay> rays;
  for (double b : {-0.5, 0.0, 0.4, 1.4}) rays.push_back({{b, 0.1, -4}, {0, 0, 1}});
  const sdf::Tape tape = sdf::compile(sdf::sphere(1));
  march::MarchSettings s;
  s.hit_eps = 1e-6;
  auto marcher = [&](const TestRay& r) -> std::optional<double> {
    const auto rec = march::march<double>(march::TapeField{&tape}, r.origin, r.direction, s, {});
    if (rec.outcome != march::Outcome::hit) return std::nullopt;
    return rec.t;
  };
  // Tolerance: the mesh's chord error over the steepest incidence here (cos >= 0.86), plus hit_eps.
  EXPECT_TRUE(MarcherMatchesReference(marcher, ref, rays, sphere.max_error / 0.86 + 1e-6));
  // A marcher that stops early by 0.1 is caught.
  auto early = [&](const TestRay& r) -> std::optional<double> {
    auto t = marcher(r);
    return t ? std::optional<double>(*t - 0.1) : std::nullopt;
  };
  EXPECT_FALSE(MarcherMatchesReference(early, ref, rays, sphere.max_error / 0.86 + 1e-6));
}

}  // namespace
}  // namespace marchcheck::validation
