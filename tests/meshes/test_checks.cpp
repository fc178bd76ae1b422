// inspect(): a clean mesh passes, and each broken variant trips exactly the check meant for it.
#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/meshes/weld.hpp"
#include "mesh_test_support.hpp"

#include <gtest/gtest.h>

#include <array>

#include <algorithm>
#include <string>

namespace marchcheck::meshes {
namespace {

using glm::dvec3;
using Triangle = std::array<std::uint32_t, 3>;

Mesh sphere() { return icosphere(1, 2).mesh; }

using test::expect_clean;

TEST(Inspect, CleanMeshPasses) {
  const MeshReport r = inspect(sphere());
  expect_clean(r);
  EXPECT_GT(r.signed_volume, 3.5);
  EXPECT_LT(r.signed_volume, 4.0 / 3 * 3.14159266);
}

TEST(Inspect, RemovedTriangleLeavesThreeBoundaryEdges) {
  Mesh m = sphere();
  m.triangles.erase(m.triangles.begin() + 7);
  const MeshReport r = inspect(m);
  EXPECT_FALSE(r.closed);
  EXPECT_EQ(r.boundary_edges, 3);
  EXPECT_TRUE(r.manifold);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_FALSE(r.outward);  // an open mesh has no inside
}

TEST(Inspect, FlippedTriangleIsInconsistent) {
  Mesh m = sphere();
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  const MeshReport r = inspect(m);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_FALSE(r.consistently_oriented);
  EXPECT_FALSE(r.outward);
}

TEST(Inspect, InsideOutMeshIsNotOutward) {
  Mesh m = sphere();
  for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  const MeshReport r = inspect(m);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_LT(r.signed_volume, 0);
  EXPECT_FALSE(r.outward);
}

// A vertex at the midpoint of edge ab splits both faces beside it; the zero-area sliver (m, a, b) keeps the
// mesh closed and consistently oriented.
TEST(Inspect, ZeroAreaSliverIsDegenerate) {
  Mesh m = sphere();
  const Triangle abc = m.triangles[0];
  const std::uint32_t a = abc[0], b = abc[1], c = abc[2];
  const std::uint32_t mid = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.push_back((m.vertices[a] + m.vertices[b]) / 2.0);
  m.triangles[0] = {a, mid, c};
  m.triangles.push_back({mid, b, c});
  m.triangles.push_back({mid, a, b});
  const MeshReport r = inspect(m);
  EXPECT_EQ(r.degenerate_faces, 1);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_TRUE(r.manifold);
}

TEST(Inspect, RepeatedIndexIsDegenerate) {
  Mesh m = sphere();
  m.triangles.push_back({0, 0, 1});
  EXPECT_EQ(inspect(m).degenerate_faces, 1);
  m = sphere();
  m.vertices.push_back(m.vertices[0]);  // same position, different index: zero area all the same
  m.triangles.push_back({0, static_cast<std::uint32_t>(m.vertices.size() - 1), 1});
  EXPECT_EQ(inspect(m).degenerate_faces, 1);
}

// Whichever two corners repeat, the face is degenerate and takes no part in the topology: the sphere stays closed,
// manifold and consistently oriented. Broken variant: (a, b, a) counted as a face with proper edges.
TEST(Inspect, ARepeatedIndexAnywhereLeavesTheTopologyAlone) {
  for (const std::array<std::uint32_t, 3> face : {std::array<std::uint32_t, 3>{0, 0, 1}, {1, 2, 2}, {1, 2, 1}}) {
    Mesh m = sphere();
    m.triangles.push_back(face);
    const MeshReport r = inspect(m);
    EXPECT_EQ(r.degenerate_faces, 1) << face[0] << face[1] << face[2];
    EXPECT_TRUE(r.closed && r.manifold && r.consistently_oriented) << face[0] << face[1] << face[2];
    EXPECT_EQ(r.boundary_edges + r.nonmanifold_edges + r.nonmanifold_vertices, 0) << face[0] << face[1] << face[2];
  }
}

TEST(Inspect, ThinButRealTriangleIsNotDegenerate) {
  const Mesh m{{{0, 0, 0}, {1, 0, 0}, {2, 1e-7, 0}}, {{0, 1, 2}}};
  EXPECT_EQ(inspect(m).degenerate_faces, 0);
}

TEST(Inspect, ThreeFacesOnAnEdgeAreNonManifold) {
  Mesh m = sphere();
  const Triangle t = m.triangles[0];
  m.vertices.push_back(dvec3(2, 2, 2));
  m.triangles.push_back({t[0], t[1], static_cast<std::uint32_t>(m.vertices.size() - 1)});
  const MeshReport r = inspect(m);
  EXPECT_EQ(r.nonmanifold_edges, 1);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(r.boundary_edges, 2);
  EXPECT_FALSE(r.closed);
  EXPECT_FALSE(r.consistently_oriented);  // three faces cannot pair up their directions
}

TEST(Inspect, TwoClosedPiecesTouchingAtAVertexArePinched) {
  const Mesh single = box({1, 1, 1}).mesh;
  Mesh m = single;
  // A second box sharing vertex 7 (+1, +1, +1) of the first: box corner 0 of the copy moves onto it.
  const std::uint32_t offset = static_cast<std::uint32_t>(m.vertices.size());
  for (const dvec3& v : single.vertices) m.vertices.push_back(v + dvec3(2, 2, 2));
  for (Triangle t : single.triangles) {
    for (auto& i : t) i = i == 0 ? 7 : i + offset;
    m.triangles.push_back(t);
  }
  const MeshReport r = inspect(m);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.nonmanifold_edges, 0);
  EXPECT_EQ(r.nonmanifold_vertices, 1);
  EXPECT_FALSE(r.manifold);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_DOUBLE_EQ(r.signed_volume, 16);
}

// A closed, manifold, consistently oriented box with its corner 7 (+1, +1, +1) pushed down through the bottom: the
// six triangles around it pass through the bottom face (triangles 4 and 5, y = -1) and nowhere else.
Mesh folded_box() {
  Mesh m = box({1, 1, 1}).mesh;
  m.vertices[7] = dvec3(0.5, -3, 0.5);
  return m;
}

// Broken variants: no crossing test (the fold is taken for a solid); faces that share an edge or a vertex counted
// as crossing (every solid would be refused).
TEST(Inspect, AFoldedBoxPassesThroughItself) {
  const Mesh m = folded_box();
  const MeshReport r = inspect(m);
  ASSERT_TRUE(r.closed && r.manifold && r.consistently_oriented && r.degenerate_faces == 0);
  ASSERT_FALSE(r.crossing_triangles.empty());
  for (const auto& [a, b] : r.crossing_triangles) {
    const auto uses_corner = [&](std::size_t t) { return std::ranges::count(m.triangles[t], 7u) == 1; };
    EXPECT_LT(a, b);
    EXPECT_TRUE((uses_corner(a) && (b == 4 || b == 5)) || (uses_corner(b) && (a == 4 || a == 5))) << a << " " << b;
  }
  const std::string problem = solid_problem(r, m);
  EXPECT_EQ(problem.rfind("self-intersecting: " + std::to_string(r.crossing_triangles.size()) + " pairs", 0), 0u)
      << problem;
  // Counted from 1 where no file numbers the faces.
  EXPECT_NE(problem.find("no sign: faces " + std::to_string(r.crossing_triangles[0][0] + 1) + " and " +
                         std::to_string(r.crossing_triangles[0][1] + 1)),
            std::string::npos)
      << problem;
}

TEST(Inspect, SolidsWhoseFacesMeetOnlyAtSharedEdgesDoNotCross) {
  for (const Mesh& m : {sphere(), box({1, 2, 3}).mesh, notched_box({1, 0.7, 0.6}).mesh, torus(1, 0.3, 24, 12).mesh}) {
    const MeshReport r = inspect(m);
    EXPECT_TRUE(r.crossing_triangles.empty()) << r.crossing_triangles.size();
    EXPECT_EQ(solid_problem(r, m), "");
  }
}

// The crossing test runs on solid topology only: an open fold reports its boundary, not crossings.
TEST(Inspect, CrossingsAreNotTestedWhereTheTopologyIsAlreadyNoSolids) {
  Mesh m = folded_box();
  m.triangles.pop_back();
  const MeshReport r = inspect(m);
  EXPECT_FALSE(r.closed);
  EXPECT_TRUE(r.crossing_triangles.empty());
  EXPECT_EQ(solid_problem(r, m).rfind("open: ", 0), 0u);
}

// Every problem is reported with its count and where its first few lie, not only the first one found. A box with a
// triangle removed (a hole: 3 edges in 1 loop), a fin on another edge (1 edge of three faces, its 2 free edges in a
// second loop) and a face like (a, b, a): all three named, the hole's edges at the removed face's corners.
// Broken variants: only the first problem said; loops counted per edge; examples from the wrong list.
TEST(Inspect, EveryProblemIsCountedWithWhereItLies) {
  Mesh m = box({1, 1, 1}).mesh;
  const Triangle removed = m.triangles[11];  // {1, 7, 5}: the +x face's second half
  m.triangles.erase(m.triangles.begin() + 11);
  const auto fin = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.push_back({-1, -3, 0});
  m.triangles.push_back({0, 4, fin});  // a third face on the edge 0-4 of the -x face
  m.triangles.push_back({0, 1, 0});    // triangle 13 in the file's numbering
  const MeshReport r = inspect(m);
  EXPECT_EQ(r.boundary_edges, 5);
  EXPECT_EQ(r.boundary_loops, 2);
  EXPECT_EQ(r.nonmanifold_edges, 1);
  EXPECT_EQ(r.degenerate_faces, 1);
  ASSERT_EQ(r.boundary_edges_at.size(), kReportExamples);
  const std::string problem = solid_problem(r, m);
  for (const std::string part : {"1 degenerate faces", "rounding): face 13", "open: 5 boundary edges in 2 loops: (",
                                  "non-manifold: 1 edges with three or more faces: (-1, -1, -1)-(-1, -1, 1)", "; "})
    EXPECT_NE(problem.find(part), std::string::npos) << part << "\n" << problem;
  EXPECT_NE(problem.find(", ...;"), std::string::npos) << "5 boundary edges, 3 shown: " << problem;
  // Each shown boundary edge is one of the hole's or the fin's free edges.
  for (const auto& [a, b] : r.boundary_edges_at) {
    const auto corner = [&](std::uint32_t v) { return std::ranges::count(removed, v) == 1; };
    const bool hole = corner(a) && corner(b);
    const bool fin_edge = a == fin || b == fin;
    EXPECT_TRUE(hole || fin_edge) << a << "-" << b;
  }
}

// A mesh split along a seam (as STL files and exporters write them): open, and the message points at the seam and
// at the weld that closes it, for copies at the same position and for near-coincident ones alike.
// Broken variants: equal positions only (the copy 2.2e-16 away unseen); boundary vertices of one edge end only.
TEST(Inspect, ASplitSeamIsPointedOutWithTheWeldThatClosesIt) {
  for (const double gap : {0.0, 0x1p-52}) {  // a copy at the same position, or one unit in the last place away
    Mesh m = box({1, 1, 1}).mesh;
    m.vertices.push_back(m.vertices[7] + dvec3(gap, 0, 0));
    m.triangles[11][1] = 8;  // {1, 7, 5} now uses the copy of vertex 7
    const MeshReport r = inspect(m);
    EXPECT_EQ(r.seam_vertices, 2) << gap;  // vertex 7 and its copy, each the other's partner
    EXPECT_EQ(r.seam_gap, gap);
    const std::string problem = solid_problem(r, m);
    EXPECT_EQ(problem.rfind("open: ", 0), 0u) << problem;
    const std::string where = gap == 0 ? "at the position of" : "within 2.22e-16 of";
    EXPECT_NE(problem.find("2 boundary vertices lie " + where + " another boundary vertex: a seam split there (a "
                           "mesh node's \"weld\": 1e-13 merges them"),
              std::string::npos)
        << problem;
    // The weld it names closes it.
    EXPECT_EQ(weld(m, 1e-13).merged_vertices, 1);
    EXPECT_EQ(solid_problem(inspect(m), m), "");
  }
  // Boundary vertices farther apart than 1e-6 of the boundary's size are no seam: a plain hole says nothing of one.
  Mesh hole = sphere();
  hole.triangles.erase(hole.triangles.begin() + 7);
  EXPECT_EQ(inspect(hole).seam_vertices, 0);
  EXPECT_EQ(solid_problem(inspect(hole), hole).find("seam"), std::string::npos);
}

// A small mesh far out (a box 1.2e14 from the origin, as fuzz_mesh_stl found): its seam is found and welded as at
// the origin, the grid counting cells from the mesh's own corner (from the origin, its cells would pass 2^48 and
// inspect threw). Broken variant: cells counted from the origin (meshes-grid-cells-from-origin).
TEST(Inspect, ASeamFarFromTheOriginIsFoundAtTheResolutionThere) {
  Mesh m = box({1, 1, 1}).mesh;
  for (dvec3& v : m.vertices) v += dvec3(1.22e14, 0, 0);
  m.vertices.push_back(m.vertices[7]);
  m.triangles[11][1] = 8;
  const MeshReport r = inspect(m);
  EXPECT_EQ(r.seam_vertices, 2);
  const std::string problem = solid_problem(r, m);
  EXPECT_NE(problem.find("a seam split there (a mesh node's \"weld\": 1e-13 merges them"), std::string::npos) << problem;
  EXPECT_EQ(weld(m, 1e-13).merged_vertices, 1);
  EXPECT_EQ(solid_problem(inspect(m), m), "");
}

TEST(Inspect, DuplicateVerticesAreCounted) {
  Mesh m = sphere();
  m.vertices.push_back(m.vertices[3]);
  m.vertices.push_back(m.vertices[3]);
  m.vertices.push_back(-m.vertices[3] * 0.0);  // -0 and +0 count as the same position
  m.vertices.push_back(dvec3(0));
  EXPECT_EQ(inspect(m).duplicate_vertices, 3);

  // A triangle soup (as STL stores it) is all duplicates and all boundary.
  const Mesh shared = box({1, 1, 1}).mesh;
  Mesh soup;
  for (const Triangle& t : shared.triangles) {
    const auto base = static_cast<std::uint32_t>(soup.vertices.size());
    for (const auto i : t) soup.vertices.push_back(shared.vertices[i]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  const MeshReport r = inspect(soup);
  EXPECT_EQ(r.duplicate_vertices, 36 - 8);
  EXPECT_EQ(r.boundary_edges, 36);
  EXPECT_FALSE(r.closed);
}

TEST(Inspect, VolumeFarFromTheOrigin) {
  Mesh m = box({1, 2, 3}).mesh;
  for (dvec3& v : m.vertices) v += dvec3(1e6, -2e6, 3e6);
  EXPECT_NEAR(inspect(m).signed_volume, 48, 1e-6);
}

TEST(Inspect, EmptyMeshIsNotClosed) {
  const MeshReport r = inspect(Mesh{});
  EXPECT_FALSE(r.closed);
  EXPECT_FALSE(r.outward);
  EXPECT_EQ(r.signed_volume, 0);
}

TEST(Inspect, IndexPastTheVerticesThrows) {
  Mesh m = sphere();
  m.triangles.push_back({0, 1, static_cast<std::uint32_t>(m.vertices.size())});
  EXPECT_THROW(inspect(m), MeshError);
}

// A box whose corner 7 is split into two copies 2.7e-16 apart (an exporter's seam), with 200 zero-area slivers
// along the split edge, (7, copy, 3), as such files carry: open and degenerate as read; welded at 1e-12, one vertex
// merges, the 200 slivers (now (7, 7, 3)) go, and the box is a solid again. Broken variants: merging beyond the
// tolerance, faces left with a repeated index, a merge missed across a cell boundary.
Mesh split_seam_box() {
  Mesh m = box({1, 1, 1}).mesh;
  const auto copy = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.push_back(m.vertices[7] + dvec3(2.7e-16, 0, 0));
  m.triangles[11][1] = copy;  // {1, 7, 5} -> {1, copy, 5}
  for (int i = 0; i < 200; ++i) m.triangles.push_back({7, copy, 3});
  return m;
}

TEST(Weld, ClosesASplitSeamAndRemovesTheSliversItCollapses) {
  Mesh m = split_seam_box();
  // Numbered as an OBJ would number them, the slivers first (faces 1-200): the numbers stay with what is kept.
  std::rotate(m.triangles.begin(), m.triangles.begin() + 12, m.triangles.end());
  for (std::uint32_t v = 0; v < m.vertices.size(); ++v) m.vertex_numbers.push_back(v + 1);
  for (std::uint32_t t = 0; t < m.triangles.size(); ++t) m.face_numbers.push_back(t + 1);
  const Mesh before = m;
  EXPECT_NE(solid_problem(inspect(m), m), "");
  const WeldResult r = weld(m, 1e-12);
  EXPECT_EQ(r.merged_vertices, 1);
  EXPECT_EQ(r.removed_faces, 200);
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.triangles.size(), 12u);
  const MeshReport report = inspect(m);
  EXPECT_EQ(solid_problem(report, m), "");
  EXPECT_TRUE(report.outward);
  EXPECT_EQ(describe(r, 1e-12), "welded at 1e-12: 1 vertices merged, 200 faces with a repeated index removed");
  ASSERT_EQ(m.vertex_numbers.size(), 8u);
  for (std::size_t v = 0; v < 8; ++v) EXPECT_EQ(m.vertices[v], before.vertices[m.vertex_numbers[v] - 1]) << v;
  ASSERT_EQ(m.face_numbers.size(), 12u);
  for (std::size_t t = 0; t < 12; ++t) {
    EXPECT_EQ(m.face_numbers[t], t + 201);
    for (int k = 0; k < 3; ++k)  // the copy (vertex 9) became vertex 8
      EXPECT_EQ(m.vertices[m.triangles[t][k]], before.vertices[std::min(before.triangles[t + 200][k], 7u)]);
  }
}

// Broken variants: a merge past the tolerance (a 3x looser distance test, 0.7e-9 apart at 5e-10); a tolerance
// below double's resolution at the coordinates taken (its cells, rounded, no longer neighbour: the 2.7e-16 seam at
// 1 was missed at 1e-16).
TEST(Weld, MergesOnlyWithinTheTolerance) {
  Mesh apart = box({1, 1, 1}).mesh;
  apart.vertices.push_back(apart.vertices[7] + dvec3(0, 0.7e-9, 0));  // within reach of the 5e-10 grid
  apart.triangles[11][1] = 8;
  const WeldResult none = weld(apart, 0.5e-9);
  EXPECT_EQ(none.merged_vertices, 0);
  EXPECT_EQ(none.removed_faces, 0);
  EXPECT_EQ(describe(none, 0.5e-9), "welded at 5e-10: nothing to weld");
  EXPECT_EQ(weld(apart, 2e-9).merged_vertices, 1);
  Mesh seam = split_seam_box();
  EXPECT_THROW(weld(seam, 1e-16), MeshError);
  // A pair straddling a cell boundary (cells are the tolerance wide) still merges; 0 merges equal positions only.
  Mesh straddle{{{0.999e-3, 0, 0}, {1.001e-3, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 3}, {1, 2, 3}}};
  EXPECT_EQ(weld(straddle, 1e-5).merged_vertices, 1);
  Mesh equal{{{1, 2, 3}, {1, 2, 3}, {1, 2, 3 + 1e-15}, {0, 1, 0}}, {{0, 2, 3}, {1, 2, 3}}};
  EXPECT_EQ(weld(equal, 0).merged_vertices, 1);
  EXPECT_THROW(weld(equal, -1), MeshError);
  EXPECT_THROW(weld(equal, 1e-300), MeshError);
}

}  // namespace
}  // namespace marchcheck::meshes
