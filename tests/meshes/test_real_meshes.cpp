// Third-party meshes from ../shared/meshes (not part of the repository): they load with the documented counts
// and topology. Skipped when the folder is absent.
#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/io.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <filesystem>
#include <string>

namespace marchcheck::meshes {
namespace {

struct RealMesh {
  const char* file;
  std::size_t vertices;  // 0: not documented
  std::size_t triangles;
  bool closed;
};

void PrintTo(const RealMesh& m, std::ostream* os) { *os << m.file; }

class RealMeshes : public ::testing::TestWithParam<RealMesh> {};

TEST_P(RealMeshes, LoadWithTheDocumentedTopology) {
  const std::string path = std::string(MARCHCHECK_SHARED_MESHES) + "/" + GetParam().file;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not available";
  const Mesh mesh = load_mesh(path);
  if (GetParam().vertices) {
    EXPECT_EQ(mesh.vertices.size(), GetParam().vertices);
  }
  EXPECT_EQ(mesh.triangles.size(), GetParam().triangles);
  const MeshReport r = inspect(mesh);
  EXPECT_EQ(r.closed, GetParam().closed);
  if (GetParam().closed) {
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.consistently_oriented);
    EXPECT_TRUE(r.outward) << "signed volume " << r.signed_volume;
    EXPECT_EQ(r.boundary_edges, 0);
  } else {
    EXPECT_GT(r.boundary_edges, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Shared, RealMeshes,
                         ::testing::Values(RealMesh{"bunny.off", 3485, 6966, true},
                                           RealMesh{"spot.obj", 2930, 5856, true},
                                           RealMesh{"fandisk.obj", 6475, 12946, true},
                                           RealMesh{"teapot.obj", 0, 6320, false},
                                           RealMesh{"unit_sphere.STL", 642, 1280, true}),
                         [](const auto& param_info) {
                           std::string name = param_info.param.file;
                           for (char& c : name)
                             if (c == '.') c = '_';
                           return name;
                         });

TEST(RealMeshes, UnitSphereStlHasRadiusOne) {
  const std::string path = std::string(MARCHCHECK_SHARED_MESHES) + "/unit_sphere.STL";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not available";
  const Mesh mesh = load_mesh(path);
  for (const glm::dvec3& v : mesh.vertices) EXPECT_NEAR(glm::length(v), 1, 1e-7);
  EXPECT_EQ(inspect(mesh).duplicate_vertices, 0);
}

}  // namespace
}  // namespace marchcheck::meshes
