// The mesh node against CGAL: its own closest-point search and pseudonormal sign give the exact signed distance
// CGAL's AABB tree and side-of-mesh test give; a face-normal sign and broken meshes are caught.
#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/sdf/mesh_distance.hpp"
#include "marchcheck/sdf/tape.hpp"
#include "marchcheck/validation/mesh_reference.hpp"
#include "../meshes/mesh_test_support.hpp"

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>

namespace marchcheck::sdf {
namespace {

using glm::dvec3;

struct Case {
  const char* name;
  meshes::ProceduralMesh mesh;
};

std::vector<Case> cases() {
  return {{"icosphere", meshes::icosphere(1, 3)},
          {"torus", meshes::torus(1, 0.35, 32, 16)},
          // A tube of triangular section: edges whose faces' normals are 120 degrees apart.
          {"triangular_torus", meshes::torus(1, 0.35, 8, 3)},
          {"notched_box", meshes::notched_box({1, 0.7, 0.6})}};
}

// Uniform points in the mesh's bounds grown by half their size, and points within 0.02 of its vertices, where
// edges and vertices are the closest features.
std::vector<dvec3> samples(const MeshDistance& md, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), near(-0.02, 0.02);
  const Box3 b = md.bounds();
  const dvec3 lo = b.lo - b.size() * 0.5, size = b.size() * 2.0;
  std::vector<dvec3> out;
  for (int i = 0; i < count; ++i) out.push_back(lo + size * dvec3(u(rng), u(rng), u(rng)));
  const auto& vs = md.mesh().vertices;
  for (int i = 0; i < count; ++i)
    out.push_back(vs[static_cast<size_t>(i) % vs.size()] + dvec3(near(rng), near(rng), near(rng)));
  return out;
}

TEST(MeshNode, SignedDistanceMatchesCgalInDoubleAndFloat) {
  for (const auto& c : cases()) {
    const MeshDistance md(c.mesh.mesh);
    const validation::MeshReference ref(c.mesh.mesh);
    ASSERT_TRUE(ref.closed()) << c.name;
    const double scale = glm::length(md.bounds().size());
    // Double: both sides compute one closest point in double; a few hundred ulps at the mesh scale.
    const double tol_double = 256 * DBL_EPSILON * scale;
    // Float: vertices and query rounded to float (2^-24 relative each) and the closest-point arithmetic on
    // top; 16 float epsilons at the scale of the sampled region.
    const double tol_float = 16 * FLT_EPSILON * 2 * scale;
    double worst_double = 0, worst_float = 0;
    int wrong_sign = 0;
    for (const dvec3& p : samples(md, 1500, 7)) {
      const double expected = *ref.signed_distance(p);
      const double d = md.signed_distance(p);
      const float f = md.signed_distance(glm::vec3(p));
      worst_double = std::max(worst_double, std::abs(d - expected));
      worst_float = std::max(worst_float, std::abs(static_cast<double>(f) - expected));
      if (std::abs(expected) > tol_float && (f < 0) != (expected < 0)) ++wrong_sign;
    }
    EXPECT_LE(worst_double, tol_double) << c.name;
    EXPECT_LE(worst_float, tol_float) << c.name;
    EXPECT_EQ(wrong_sign, 0) << c.name;
  }
}

TEST(MeshNode, SignByTheClosestFaceNormalIsCaughtAtSharpEdges) {
  // The broken variant: sign(dot(p - closest, normal of the closest face)). Where the closest point is a vertex
  // or edge, the one face normal chosen need not lie on p's side (Baerentzen & Aanaes 2005).
  for (const auto& c : cases()) {
    const MeshDistance md(c.mesh.mesh);
    const validation::MeshReference ref(c.mesh.mesh);
    int wrong_pseudo = 0, wrong_face = 0;
    for (const dvec3& p : samples(md, 3000, 11)) {
      const double expected = *ref.signed_distance(p);
      if (std::abs(expected) < 1e-9) continue;
      const auto closest = md.closest(p);
      const bool face_inside = glm::dot(p - closest.point, closest.face_normal) < 0;
      wrong_face += face_inside != (expected < 0);
      wrong_pseudo += (md.signed_distance(p) < 0) != (expected < 0);
    }
    EXPECT_EQ(wrong_pseudo, 0) << c.name;
    // Only edges whose faces' normals are more than 90 degrees apart catch it (outside, near the edge, p - closest
    // can make an obtuse angle with one of them); where faces meet at right or flatter angles the closest face's
    // normal happens to give the right sign.
    if (std::string(c.name) == "triangular_torus") {
      EXPECT_GT(wrong_face, 0) << c.name;
    }
    std::printf("%s: face-normal sign wrong at %d of 6000 points, pseudonormal sign at %d\n", c.name, wrong_face,
                wrong_pseudo);
  }
}

// Where the closest feature is a vertex, its pseudonormal is the sum of the incident faces' normals, each weighted
// by the face's angle at that vertex (Baerentzen & Aanaes), computed here from the mesh alone. The notched box's
// right triangles meet its corners at 45 and 90 degrees, so any other weighting turns the normal. Broken variant:
// each face weighted by its angle at another corner.
TEST(MeshNode, VertexPseudonormalsAreAngleWeighted) {
  for (const auto& c : cases()) {
    const meshes::Mesh& mesh = c.mesh.mesh;
    const MeshDistance md(mesh);
    std::vector<dvec3> expected(mesh.vertices.size(), dvec3(0));
    for (const auto& t : mesh.triangles)
      for (int i = 0; i < 3; ++i) {
        const dvec3 a = mesh.vertices[t[i]], b = mesh.vertices[t[(i + 1) % 3]], cc = mesh.vertices[t[(i + 2) % 3]];
        const double angle = std::acos(std::clamp(glm::dot(glm::normalize(b - a), glm::normalize(cc - a)), -1.0, 1.0));
        expected[t[i]] += angle * glm::normalize(glm::cross(b - a, cc - a));
      }
    int vertex_hits = 0;
    for (const dvec3& p : samples(md, 1500, 5)) {
      const auto closest = md.closest(p);
      if (closest.feature > meshes::vertex2) continue;
      const std::uint32_t v = mesh.triangles[closest.triangle][closest.feature];
      ++vertex_hits;
      EXPECT_NEAR(glm::length(glm::normalize(closest.pseudonormal) - glm::normalize(expected[v])), 0, 1e-9)
          << c.name << ", vertex " << v;
    }
    EXPECT_GT(vertex_hits, 100) << c.name << ": the samples near vertices must reach vertex features";
  }
}

// The closest triangle over all of them, in the order given, by the same point-triangle routine.
template <class S>
MeshDistance::Closest<S> brute_force_closest(const MeshDistance& md, glm::vec<3, S> p) {
  MeshDistance::Closest<S> best{};
  best.distance2 = std::numeric_limits<S>::infinity();
  const meshes::Mesh& m = md.mesh();
  for (std::uint32_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    const std::array<glm::vec<3, S>, 3> corners{glm::vec<3, S>(m.vertices[t[0]]), glm::vec<3, S>(m.vertices[t[1]]),
                                                glm::vec<3, S>(m.vertices[t[2]])};
    MeshDistance::Feature feature;
    const glm::vec<3, S> q = meshes::closest_on_triangle(p, corners, feature);
    const S d2 = glm::dot(p - q, p - q);
    if (d2 < best.distance2) best = {q, d2, f, feature, {}, {}};
  }
  return best;
}

// Whether the search found a closest triangle exactly as the brute force would: the same distance2 to the bit,
// and the triangle it names at that distance2, with the feature and point the routine gives for it (on exact
// ties several triangles share the closest point, e.g. all around a closest vertex).
template <class S>
bool same_as_brute_force(const MeshDistance& md, glm::vec<3, S> p, const MeshDistance::Closest<S>& got) {
  const auto all = brute_force_closest(md, p);
  const meshes::Mesh& m = md.mesh();
  const auto& t = m.triangles[got.triangle];
  const std::array<glm::vec<3, S>, 3> corners{glm::vec<3, S>(m.vertices[t[0]]), glm::vec<3, S>(m.vertices[t[1]]),
                                              glm::vec<3, S>(m.vertices[t[2]])};
  MeshDistance::Feature feature;
  const glm::vec<3, S> q = meshes::closest_on_triangle(p, corners, feature);
  return got.distance2 == all.distance2 && glm::dot(p - q, p - q) == all.distance2 && got.feature == feature &&
         got.point == q;
}
template <class S>
bool same_as_brute_force(const MeshDistance& md, glm::vec<3, S> p) {
  return same_as_brute_force(md, p, md.closest(p));
}

TEST(MeshNode, SearchFindsExactlyTheBruteForceClosestTriangle) {
  // The search prunes boxes by their distance: a box pruned wrongly, or searched in an order that leaves a
  // closer triangle behind, shows here as a distance2 differing from the minimum over all triangles. Broken
  // variants: a double leaf's second row of 8 lanes reading the first row's corner a.z
  // (sdf-leaf-row-offset-dropped), or computing the first row's triangles again (sdf-leaf-rows-all-first); a leaf's
  // least folded down to pairs only (sdf-mesh-least-fold-short), paired with its lane 0's triangle
  // (sdf-mesh-least-lane-zero), or a later row's tie taken, the bipyramid's unused lane past its six triangles
  // (sdf-mesh-least-lane-later-row).
  auto all_cases = cases();
  all_cases.push_back({"icosphere(1,4)", meshes::icosphere(1, 4)});  // the mesh-icosphere scene's
  all_cases.push_back({"bipyramid", meshes::uv_sphere(1, 2, 3)});     // six triangles: a single leaf
  for (const auto& c : all_cases) {
    const MeshDistance md(c.mesh.mesh);
    std::vector<dvec3> points = samples(md, 1000, 5);
    const auto& m = md.mesh();
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0, 1), tiny(-1e-6, 1e-6);
    std::normal_distribution<double> g;
    const double size = glm::length(md.bounds().size());
    for (int i = 0; i < 300; ++i) {
      const auto& t = m.triangles[static_cast<size_t>(i) % m.triangles.size()];
      const dvec3 a = m.vertices[t[0]], b = m.vertices[t[1]];
      // On and just off an edge and a vertex, where neighbouring triangles tie or nearly tie.
      const dvec3 on_edge = a + (b - a) * u(rng);
      points.push_back(on_edge);
      points.push_back(on_edge + dvec3(tiny(rng), tiny(rng), tiny(rng)));
      points.push_back(a);
      points.push_back(a + dvec3(tiny(rng), tiny(rng), tiny(rng)));
      // Far away, where many triangles lie at nearly the same distance.
      const dvec3 dir = glm::normalize(dvec3(g(rng), g(rng), g(rng)));
      points.push_back(md.bounds().center() + dir * (size * (2 + 50 * u(rng))));
    }
    // The sign against CGAL's side-of-mesh test, away from the surface by the float tolerance of
    // SignedDistanceMatchesCgalInDoubleAndFloat (on exact ties the triangles share the closest point's feature and
    // so its pseudonormal).
    const validation::MeshReference ref(c.mesh.mesh);
    const double tol_float = 16 * FLT_EPSILON * 2 * size;
    int wrong_double = 0, wrong_float = 0, wrong_sign = 0;
    for (const dvec3& p : points) {
      wrong_double += !same_as_brute_force(md, p);
      wrong_float += !same_as_brute_force(md, glm::vec3(p));
      const double expected = *ref.signed_distance(p);
      if (std::abs(expected) > tol_float)
        wrong_sign += (md.signed_distance(p) < 0) != (expected < 0) ||
                      (md.signed_distance(glm::vec3(p)) < 0) != (expected < 0);
    }
    EXPECT_EQ(wrong_double, 0) << c.name << " of " << points.size();
    EXPECT_EQ(wrong_float, 0) << c.name << " of " << points.size();
    EXPECT_EQ(wrong_sign, 0) << c.name << " of " << points.size();
  }
}

// The search's cost, counted in leaves read (16 triangles each), at 2000 random points in 1.2x the box of a finely
// tessellated torus and icosphere (21,600 and 20,480 triangles): on a curved surface many leaves' axis-aligned
// boxes come nearer a point than its closest triangle, the oriented boxes about the patches' planes far fewer.
// A search starts from the start grid's leaf, near its answer. Measured: torus 4.76, icosphere 4.35 leaves a point
// (5.17 and 5.16 from the root of a four-wide tree). Broken variants: the axis-aligned boxes alone
// (sdf-mesh-oriented-boxes-unused); no start grid (sdf-mesh-start-grid-unused); the children searched farthest
// first (sdf-mesh-children-farthest-first). Limits: 3% above the measured counts, which are deterministic (a fixed
// seed, IEEE arithmetic without contraction, nothing timed).
TEST(MeshNode, OrientedBoxesKeepTheSearchToAFewLeaves) {
  struct Expected {
    const char* name;
    meshes::ProceduralMesh mesh;
    double leaves;
  };
  for (const auto& [name, mesh, measured] : {Expected{"torus", meshes::torus(1, 0.35, 120, 90), 4.76},
                                             Expected{"icosphere", meshes::icosphere(1, 5), 4.35}}) {
    const MeshDistance md(mesh.mesh);
    std::mt19937 rng(16);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    const Box3 b = md.bounds();
    double leaves = 0;
    constexpr int kPoints = 2000;
    for (int i = 0; i < kPoints; ++i)
      leaves += md.leaves_searched(glm::vec3(b.center() + b.size() * dvec3(u(rng), u(rng), u(rng))));
    EXPECT_LE(leaves / kPoints, 1.03 * measured) << name;
  }
}

// The order a node's children are searched in: a sorting network on keys of a value's bits and its lane. Random
// values with exact ties, zeros, +inf and NaN (a child a NaN point cannot be near), in float and double: the
// order is a permutation, the values never decrease (NaN last), and equal values keep their lanes' order. Broken
// variant: the larger of each pair kept low (sdf-mesh-sort-descending).
template <class S>
void check_nearest_first() {
  std::mt19937 rng(21);
  std::uniform_int_distribution<int> pick(0, 9);
  constexpr std::size_t kN = 8;
  for (int trial = 0; trial < 2000; ++trial) {
    S values[kN];
    for (S& v : values) {
      const int k = pick(rng);
      v = k == 0 ? S(0) : k == 1 ? std::numeric_limits<S>::infinity() : k == 2 ? std::numeric_limits<S>::quiet_NaN()
                                                                        : static_cast<S>(k % 4);  // ties
    }
    std::uint32_t order[kN];
    detail::nearest_first<kN>(values, order);
    std::vector<std::uint32_t> lanes(order, order + kN);
    std::sort(lanes.begin(), lanes.end());
    for (std::uint32_t i = 0; i < kN; ++i) ASSERT_EQ(lanes[i], i) << "not a permutation";
    for (std::size_t i = 1; i < kN; ++i) {
      const S a = values[order[i - 1]], b = values[order[i]];
      if (std::isnan(a)) {
        EXPECT_TRUE(std::isnan(b)) << "NaN before a number at " << i;
      } else if (!std::isnan(b)) {
        EXPECT_LE(a, b) << "at " << i;
      }
      if (a == b || (std::isnan(a) && std::isnan(b))) {
        EXPECT_LT(order[i - 1], order[i]) << "a tie out of lane order";
      }
    }
  }
}

TEST(MeshNode, ChildrenAreSearchedNearestFirstTiesInLaneOrder) {
  check_nearest_first<float>();
  check_nearest_first<double>();
}

// bounds_distance2's oriented box is computed in float, yet must never come out above the distance to the box
// (a search would then skip the closest triangle): points just outside a face of boxes 100 from the origin, where
// float rounding of (p - centre) . axis (6e-6 there) dwarfs the distance (1e-7 .. 1e-5). The box's axis-aligned
// bounds are left unbounded, so the oriented one decides. The distance compared against is to the box point
// nearest p along the axes (p's coordinates clamped), at least the distance to the box, in long double.
// Broken variant: the rounding slack left out (sdf-mesh-oriented-box-no-slack).
TEST(MeshNode, OrientedBoxBoundAllowsForFloatRounding) {
  struct Node {
    std::array<float, 4> lo[3], hi[3], centre[3], axes[3][3], half[3];
  };
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1), offset(1e-7, 1e-5);
  std::normal_distribution<double> g;
  int above = 0, trials = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Node node{};
    glm::dvec4 q(g(rng), g(rng), g(rng), g(rng));
    const glm::dmat3 rotation = glm::mat3_cast(glm::normalize(glm::dquat(q.w, q.x, q.y, q.z)));
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 3; ++i) {
        node.lo[i][k] = -INFINITY;
        node.hi[i][k] = INFINITY;
        node.centre[i][k] = static_cast<float>(100 * u(rng));
        node.half[i][k] = static_cast<float>(0.01 + std::abs(u(rng)));
        for (int r = 0; r < 3; ++r) node.axes[r][i][k] = static_cast<float>(rotation[r][i]);
      }
    // Child 0's box: p just outside face `face`, anywhere across it.
    const int face = trial % 3;
    glm::dvec3 t;
    for (int r = 0; r < 3; ++r) t[r] = node.half[r][0] * u(rng);
    t[face] = (u(rng) < 0 ? -1 : 1) * (node.half[face][0] + offset(rng));
    using LD = long double;
    LD p[3], x[3];
    for (int i = 0; i < 3; ++i) {
      p[i] = node.centre[i][0];
      for (int r = 0; r < 3; ++r) p[i] += LD(t[r]) * node.axes[r][i][0];
    }
    const glm::vec3 pf(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
    // pf's coordinates along the (float) axes, solved in long double by Cramer's rule, clamped to the box.
    LD a[3][3], w[3], coords[3];
    for (int i = 0; i < 3; ++i) {
      w[i] = LD(pf[i]) - node.centre[i][0];
      for (int r = 0; r < 3; ++r) a[i][r] = node.axes[r][i][0];
    }
    const auto det = [](const LD m[3][3]) {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    for (int r = 0; r < 3; ++r) {
      LD m[3][3];
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) m[i][c] = c == r ? w[i] : a[i][c];
      coords[r] = std::clamp(det(m) / det(a), LD(-node.half[r][0]), LD(node.half[r][0]));
    }
    LD distance2 = 0;
    for (int i = 0; i < 3; ++i) {
      x[i] = node.centre[i][0];
      for (int r = 0; r < 3; ++r) x[i] += coords[r] * a[i][r];
      distance2 += (LD(pf[i]) - x[i]) * (LD(pf[i]) - x[i]);
    }
    float bound[4];
    detail::bounds_distance2(pf, node, bound);
    ++trials;
    above += LD(bound[0]) > distance2;
  }
  EXPECT_EQ(above, 0) << "of " << trials;
}

// Coherent points, as a packet's lanes and a ray's steps are: rays from far outside toward each vertex and edge
// midpoint, each step halving the distance left (so each point lies within the previous one's distance and its
// search starts from that one's leaf), ending on the vertex or edge, where triangles tie. The batched search
// finds the brute force's distance2 at every point with a triangle at that distance, the single search's triangle
// (wherever each started, among tied ones the first in BVH order), and signed_distances gives the single
// signed_distance bit for bit (tied triangles compute the closest point each in its own way, so the sign of a point
// within rounding of the surface). Broken variants: the start leaf skipped in the tree but never searched
// (sdf-mesh-start-leaf-skipped); a NaN point at distance 0 from every box, searching forever (sdf-mesh-nan-box-zero);
// or given +inf when no triangle was found (sdf-mesh-nothing-found-infinite); the first tie found kept
// (sdf-mesh-tie-first-found: 24 of the torus's float distances differ in sign); a child whose box ties the best
// pruned (sdf-mesh-tied-box-pruned).
TEST(MeshNode, BatchedSearchFromANeighboursLeafGivesTheSingleSearchesAnswers) {
  for (const auto& c : cases()) {
    const MeshDistance md(c.mesh.mesh);
    const auto& m = md.mesh();
    std::vector<dvec3> targets(m.vertices.begin(), m.vertices.end());
    for (const auto& t : m.triangles) targets.push_back((m.vertices[t[0]] + m.vertices[t[1]]) * 0.5);
    const dvec3 centre = md.bounds().center();
    const double size = glm::length(md.bounds().size());
    std::vector<dvec3> points;
    for (const dvec3& target : targets) {
      const dvec3 from = target + glm::normalize(target - centre) * size;
      for (int k = 0; k < 40; ++k) points.push_back(target + (from - target) * std::ldexp(1.0, -k));
      points.push_back(target);
    }
    for (const dvec3 nan_first : {dvec3(NAN, 0, 0), dvec3(0, 0, NAN)}) points.push_back(nan_first);
    const auto check = [&](auto zero) {
      using S = decltype(zero);
      std::vector<glm::vec<3, S>> ps(points.begin(), points.end());
      std::vector<MeshDistance::Closest<S>> batched(ps.size());
      md.closest(ps.data(), batched.data(), static_cast<int>(ps.size()));
      std::vector<S> x, y, z, distances(ps.size());
      for (const auto& p : ps) {
        x.push_back(p.x);
        y.push_back(p.y);
        z.push_back(p.z);
      }
      md.signed_distances(x.data(), y.data(), z.data(), distances.data(), static_cast<int>(ps.size()));
      int wrong = 0, wrong_distance = 0, wrong_triangle = 0;
      for (size_t i = 0; i < ps.size(); ++i) {
        const S single = md.signed_distance(ps[i]);
        wrong_triangle += md.closest(ps[i]).triangle != batched[i].triangle;
        if (std::isnan(ps[i].x + ps[i].z)) {  // no closest triangle: NaN, not a number from triangle 0
          EXPECT_TRUE(std::isnan(single) && std::isnan(distances[i])) << c.name;
          continue;
        }
        wrong += !same_as_brute_force(md, ps[i], batched[i]);
        wrong_distance += std::memcmp(&single, &distances[i], sizeof single) != 0;
      }
      EXPECT_EQ(wrong, 0) << c.name << " of " << ps.size();
      EXPECT_EQ(wrong_distance, 0) << c.name << " of " << ps.size();
      EXPECT_EQ(wrong_triangle, 0) << c.name << " of " << ps.size();
    };
    check(0.0);
    check(0.0f);
  }
}

// Float distances beside the needles of a plate 100-400 from the origin (aspect ~300): once 8.7x the exact value,
// from the barycentric face point's cancellation (closest_point.hpp). Now within the rounding of the float point
// and corners: half an ulp each of coordinates up to 400 (FLT_EPSILON / 2 x 400 = 2.4e-5), four of them.
// Broken variants: the barycentric face point in the leaf or in closest_on_triangle; the normal across the tip.
TEST(MeshNode, FloatDistanceBesideSliversIsWithinRounding) {
  const meshes::Mesh plate = meshes::test::sliver_plate();
  const meshes::MeshReport report = meshes::inspect(plate);
  ASSERT_TRUE(report.closed && report.manifold && report.outward && report.crossing_triangles.empty());
  const MeshDistance md(plate);
  std::mt19937 rng(300);
  std::uniform_real_distribution<double> x(105, 395), across(0.02, 0.98), height(0.01, 0.05);
  const double tolerance = 4 * (FLT_EPSILON / 2 * 400);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    // Above the top face, over the needles' part of it (below the fan's last, fat triangle at y = 100 + 2 (x-100)/3).
    const double px = x(rng), py = 100 + across(rng) * (200 * (px - 100) / 300), h = height(rng);
    const dvec3 p(px, py, 103 + h);
    ASSERT_NEAR(md.signed_distance(p), h, 1e-12);
    worst = std::max(worst, std::abs(static_cast<double>(md.signed_distance(glm::vec3(p))) - h));
  }
  EXPECT_LE(worst, tolerance);
}

TEST(MeshNode, RefusesMeshesWithoutAnInside) {
  auto throws_with = [](const meshes::Mesh& m, const std::string& what) {
    try {
      MeshDistance md(m);
      ADD_FAILURE() << "accepted a mesh that is " << what;
    } catch (const MeshShapeError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  meshes::Mesh flipped = meshes::box({1, 1, 1}).mesh;
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  throws_with(flipped, "inside out");
  meshes::Mesh open = meshes::box({1, 1, 1}).mesh;
  open.triangles.pop_back();
  throws_with(open, "open: ");
  meshes::Mesh one_face_flipped = meshes::box({1, 1, 1}).mesh;
  std::swap(one_face_flipped.triangles[0][1], one_face_flipped.triangles[0][2]);
  throws_with(one_face_flipped, "inconsistently oriented");
  throws_with({}, "no triangles");
  // The rules the distance field once checked on its own and missed (meshes::solid_problem is the one rule now):
  // two boxes sharing only a corner (every edge has two faces; the corner is pinched, and the sign beside it
  // was wrong), and a closed box with a face like (a, b, a) added.
  meshes::Mesh pinched = meshes::box({1, 1, 1}).mesh;
  const meshes::Mesh other = meshes::box({1, 1, 1}).mesh;
  const auto base = static_cast<std::uint32_t>(pinched.vertices.size() - 1);
  for (size_t i = 1; i < other.vertices.size(); ++i) pinched.vertices.push_back(other.vertices[i] + glm::dvec3(2));
  for (auto t : other.triangles) {  // its vertex 0, at (1, 1, 1), is the first box's vertex 7
    for (auto& v : t) v = v == 0 ? 7 : v + base;
    pinched.triangles.push_back(t);
  }
  throws_with(pinched, "pinched");
  throws_with(meshes::test::pinched_double_cone(), "pinched");
  meshes::Mesh repeated = meshes::box({1, 1, 1}).mesh;
  repeated.triangles.push_back({0, 1, 0});
  throws_with(repeated, "degenerate");
  // Closed, manifold and consistently oriented, but corner 7 pushed through the bottom: no single inside.
  meshes::Mesh folded = meshes::box({1, 1, 1}).mesh;
  folded.vertices[7] = glm::dvec3(0.5, -3, 0.5);
  throws_with(folded, "self-intersecting");
}

TEST(MeshNode, DualGradientIsTheUnitDirectionOfSteepestAscent) {
  // A 1-Lipschitz field changing at slope 1 along a unit vector has it as its gradient. On the segment from p
  // to its closest point the closest point stays put, so there the slope is 1 up to rounding.
  const MeshDistance md(meshes::notched_box({1, 0.7, 0.6}).mesh);
  using D = Dual<double>;
  int checked = 0;
  for (const dvec3& p : samples(md, 500, 3)) {
    const glm::vec<3, D> q(D(p.x, {1, 0, 0}), D(p.y, {0, 1, 0}), D(p.z, {0, 0, 1}));
    const D d = md.signed_distance(q);
    EXPECT_EQ(d.v, md.signed_distance(p));
    if (std::abs(d.v) < 1e-3) continue;  // the step below must stay on one side of the surface
    ++checked;
    const double h = 1e-4, s = d.v > 0 ? 1 : -1;
    const double slope = (d.v - md.signed_distance(p - d.d * (s * h))) / (s * h);  // a step towards the surface
    EXPECT_NEAR(glm::length(d.d), 1, 1e-12);
    // Difference quotient in double of values near 1: rounding of about eps / h.
    EXPECT_NEAR(slope, 1, 1e-9) << p.x << " " << p.y << " " << p.z;
  }
  EXPECT_GT(checked, 500);
}

TEST(MeshNode, TapeEvaluatesItUnderTransformsInFloatDoubleAndDual) {
  Node m = mesh("procedural:icosphere(1,2)");
  m.mesh = std::make_shared<const MeshDistance>(meshes::icosphere(1, 2).mesh);
  const MeshDistance& md = *m.mesh;
  const Tape tape = compile(translate({1, 2, 3}, m));
  EXPECT_EQ(derive_info(m).kind, Kind::exact);
  for (const dvec3 p : {dvec3(1, 2, 3), dvec3(3, 2, 1), dvec3(1, 2.5, 3.2)}) {
    EXPECT_EQ(evaluate(tape, p), md.signed_distance(p - dvec3(1, 2, 3)));
    EXPECT_EQ(evaluate(tape, glm::vec3(p)), md.signed_distance(glm::vec3(p) - glm::vec3(1, 2, 3)));
    using D = Dual<double>;
    const D d = evaluate(tape, glm::vec<3, D>(D(p.x, {1, 0, 0}), D(p.y, {0, 1, 0}), D(p.z, {0, 0, 1})));
    const dvec3 q = p - dvec3(1, 2, 3);
    EXPECT_EQ(d.d, md.signed_distance(glm::vec<3, D>(D(q.x, {1, 0, 0}), D(q.y, {0, 1, 0}), D(q.z, {0, 0, 1}))).d);
  }
  Node unloaded = mesh("m.obj");
  EXPECT_THROW(compile(unloaded), CompileError);
}

}  // namespace
}  // namespace marchcheck::sdf
