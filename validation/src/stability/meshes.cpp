// Meshes: degenerate, duplicated, open, non-manifold, inverted and nearly touching ones, and a large one.
#include "battery.hpp"

#include "marchcheck/meshes/checks.hpp"
#include "marchcheck/meshes/procedural.hpp"
#include "marchcheck/validation/mesh_reference.hpp"
#include "marchcheck/validation/reference.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <utility>

namespace marchcheck::validation::stability {

namespace {

// ---- meshes ----

constexpr double kMeshSampleMargin = 0.05;  // points this close to the unit sphere are left out (chord error)

std::vector<dvec3> mesh_samples(int n, double half = 1.5) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-half, half);
  std::vector<dvec3> out;
  while (static_cast<int>(out.size()) < n) {
    const dvec3 p(u(rng), u(rng), u(rng));
    if (std::abs(glm::length(p) - 1) > kMeshSampleMargin) out.push_back(p);
  }
  return out;
}

// The naive sign: the side of the nearest vertex's normal (sum of its faces' normals); defined on any mesh,
// right or not.
double naive_sign(const meshes::Mesh& mesh, dvec3 p) {
  std::vector<dvec3> normals(mesh.vertices.size(), dvec3(0));
  for (const auto& t : mesh.triangles) {
    const dvec3 n = glm::cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    for (const auto i : t) normals[i] += n;
  }
  size_t best = 0;
  for (size_t i = 1; i < mesh.vertices.size(); ++i)
    if (glm::length(mesh.vertices[i] - p) < glm::length(mesh.vertices[best] - p)) best = i;
  return glm::dot(p - mesh.vertices[best], normals[best]) < 0 ? -1 : 1;
}

// Signs at the samples against the unit sphere's: every sample signed and on the right side (a closed mesh), or
// none signed (a mesh with no inside). naive: the nearest vertex normal's side; refused_sign: no sign at all;
// sign_flipped: the winding's sign taken without the orientation.
void sphere_signs(Run& r, const meshes::Mesh& mesh, bool expect_sign) {
  const MeshReference ref(mesh);
  int wrong = 0, signed_count = 0;
  for (const dvec3& p : mesh_samples(200)) {
    std::optional<double> s = r.naive() ? std::optional<double>(naive_sign(mesh, p)) : ref.signed_distance(p);
    if (r.as("refused_sign")) s.reset();
    if (r.as("sign_flipped") && s) s = -*s;
    if (!s) continue;
    ++signed_count;
    wrong += (*s < 0) != (glm::length(p) < 1);
  }
  r.m["samples.signed"] = signed_count;
  r.m["samples.wrong_sign"] = wrong;
  if (expect_sign) {
    r.require("every_sample_signed", signed_count == 200, std::to_string(200 - signed_count) + " of 200 samples left without a sign");
    r.require("sign_right", wrong == 0, std::to_string(wrong) + " of 200 samples got the wrong side");
  } else {
    r.require("no_sample_signed", signed_count == 0, std::to_string(signed_count) + " samples given a sign by a mesh with no inside");
  }
}

// The mesh checks' report, recorded among the case's numbers.
meshes::MeshReport inspected(Run& r, const meshes::Mesh& mesh) {
  const auto rep = meshes::inspect(mesh);
  r.m["report.closed"] = rep.closed;
  r.m["report.manifold"] = rep.manifold;
  r.m["report.boundary_edges"] = rep.boundary_edges;
  r.m["report.nonmanifold_edges"] = rep.nonmanifold_edges;
  r.m["report.degenerate_faces"] = rep.degenerate_faces;
  r.m["report.duplicate_vertices"] = rep.duplicate_vertices;
  r.m["report.outward"] = rep.outward;
  return rep;
}

meshes::Mesh unit_icosphere() { return meshes::icosphere(1, 3).mesh; }

void mesh_degenerate(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  const auto a = mesh.triangles[0][0], b = mesh.triangles[0][1];
  const dvec3 mid = (mesh.vertices[a] + mesh.vertices[b]) * 0.5;
  mesh.vertices.push_back(mid);                                                     // collinear with a and b
  mesh.vertices.push_back(mid + glm::normalize(glm::cross(mid, dvec3(0, 0, 1))) * 1e-14);  // a sliver's apex
  const auto m = static_cast<std::uint32_t>(mesh.vertices.size() - 2);
  mesh.triangles.push_back({a, a, b});      // repeated index
  mesh.triangles.push_back({a, m, b});      // zero area, exactly collinear up to rounding
  mesh.triangles.push_back({a, m + 1, b});  // area 1e-14 times an edge
  const auto rep = inspected(r, mesh);
  int naive_count = 0;  // naive: only repeated indices count as degenerate
  for (const auto& t : mesh.triangles) naive_count += t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
  const int counted = r.naive() ? naive_count : rep.degenerate_faces;
  // Distances and hits on the rest stay right: within the icosphere's chord error of the sphere.
  const MeshReference ref(mesh);
  const double err = meshes::icosphere(1, 3).max_error;
  const auto distance = [&](dvec3 p) {
    if (!r.as("vertex_distance")) return ref.unsigned_distance(p);
    double d = INFINITY;  // vertex_distance: the nearest vertex taken for the nearest point
    for (const dvec3& v : mesh.vertices) d = std::min(d, glm::length(p - v));
    return d;
  };
  int bad = 0;
  for (const dvec3& p : mesh_samples(100)) bad += !(std::abs(distance(p) - std::abs(glm::length(p) - 1)) <= err + 1e-12);
  for (const dvec3& p : mesh_samples(50)) {
    const ReferenceHit h = ref.first_hit(p * 3.0, -glm::normalize(p), 10);
    bad += !(h.hit && std::isfinite(h.t) && std::abs(glm::length(h.normal) - 1) < 1e-9);
  }
  r.m["degenerate_counted"] = counted;
  r.m["queries_wrong"] = bad;
  r.require("counted", counted == 3, "counted " + std::to_string(counted) + " degenerate faces of the 3 added");
  r.require("queries", bad == 0, std::to_string(bad) + " distance or ray queries wrong or non-finite");
}

void mesh_duplicates(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  for (int i = 0; i < 5; ++i) mesh.vertices.push_back(mesh.vertices[static_cast<size_t>(i)]);
  const auto rep = inspected(r, mesh);
  const int counted = r.naive() ? 0 : rep.duplicate_vertices;  // naive: vertices compared by index, never equal
  r.m["duplicates_counted"] = counted;
  r.require("counted", counted == 5, "counted " + std::to_string(counted) + " duplicate vertices of the 5 added");
  sphere_signs(r, mesh, true);
}

// The report's numbers a variant miscounts (each a one-line slip in the mesh checks), for the cases that judge them.
meshes::MeshReport miscounted(const Run& r, meshes::MeshReport rep) {
  if (r.as("boundary_counted_twice")) rep.boundary_edges *= 2;  // once per face beside the edge
  if (r.as("fin_manifold")) {  // an edge of three faces taken for manifold (only four or more counted)
    rep.nonmanifold_edges = 0;
    rep.manifold = true;
  }
  if (r.as("volume_unsigned")) {  // the volume's absolute value: the orientation lost
    rep.signed_volume = std::abs(rep.signed_volume);
    rep.outward = true;
  }
  if (r.as("components_nonmanifold")) rep.manifold = false;  // two components read as a pinch between them
  if (r.as("outward_inverted")) rep.outward = !rep.outward;  // the volume's sign read backwards
  return rep;
}

void mesh_open(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  mesh.triangles.pop_back();
  const auto rep = miscounted(r, inspected(r, mesh));
  r.require("reports_boundary", !rep.closed && rep.boundary_edges == 3, "the hole's 3 boundary edges not reported");
  sphere_signs(r, mesh, false);
}

void mesh_nonmanifold(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  const auto a = mesh.triangles[0][0], b = mesh.triangles[0][1];
  mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]) * 1.5);  // a fin on edge a-b
  mesh.triangles.push_back({a, b, static_cast<std::uint32_t>(mesh.vertices.size() - 1)});
  const auto rep = miscounted(r, inspected(r, mesh));
  r.require("reports_nonmanifold", !rep.manifold && rep.nonmanifold_edges == 1,
            "the fin's shared edge not reported non-manifold");
  sphere_signs(r, mesh, false);
}

void mesh_inverted(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh = unit_icosphere();
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  const auto rep = miscounted(r, inspected(r, mesh));
  r.m["report.signed_volume"] = rep.signed_volume;
  r.require("reports_inward", rep.closed && rep.consistently_oriented && !rep.outward && rep.signed_volume < 0,
            "the inward orientation not reported (closed, consistent, negative volume)");
  sphere_signs(r, mesh, true);
}

// Two closed spheres 0.1 apart: points in the gap are outside both. The naive sign is read off a grid of
// 0.25 (a level set coarser than the gap), as in the sign flips users reported against OpenVDB.
void mesh_sign_flip(Run& r, const StabilityOptions&) {
  meshes::Mesh mesh;
  for (const double x : {-1.05, 1.05}) {
    const meshes::Mesh s = unit_icosphere();
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (const dvec3& v : s.vertices) mesh.vertices.push_back(v + dvec3(x, 0, 0));
    for (auto t : s.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  const auto rep = miscounted(r, inspected(r, mesh));
  const MeshReference ref(mesh);
  const double h = 0.25;
  const auto sign_at = [&](dvec3 p) {
    if (!r.naive()) return ref.signed_distance(p);
    const dvec3 node = (glm::floor(p / h) + 0.5) * h;
    return ref.signed_distance(node);
  };
  int wrong = 0, gap_wrong = 0, samples = 0;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 300; ++i) {
    // Half the samples in the gap's slab |x| < 0.04 near the axis, half anywhere around both spheres.
    const bool gap = i % 2 == 0;
    const dvec3 p = gap ? dvec3(0.04 * u(rng), 0.3 * u(rng), 0.3 * u(rng)) : dvec3(2.2 * u(rng), 1.2 * u(rng), 1.2 * u(rng));
    const double exact = std::min(glm::length(p - dvec3(-1.05, 0, 0)), glm::length(p - dvec3(1.05, 0, 0))) - 1;
    if (std::abs(exact) < kMeshSampleMargin && !gap) continue;
    const auto s = sign_at(p);
    ++samples;
    const bool bad = !s || (*s < 0) != (exact < 0);
    wrong += bad;
    gap_wrong += bad && gap;
  }
  r.m["samples"] = samples;
  r.m["wrong_sign"] = wrong;
  r.m["gap.wrong_sign"] = gap_wrong;
  r.require("reports_closed_manifold", rep.closed && rep.manifold, "two closed spheres not reported closed and manifold");
  r.require("sign_right", wrong == 0,
            std::to_string(wrong) + " samples on the wrong side (" + std::to_string(gap_wrong) + " in the gap)");
}

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024;  // Linux reports KiB
}

// The 60 s and the memory below are the product's: AddressSanitizer's checked loads and stores make this case about
// 15 times slower (measured: 4 s optimised, 55 s sanitized before the self-intersection test), so a sanitized
// build, which is there to find memory errors, does not time it; and its redzones and its quarantine of freed
// blocks (256 MiB unless a binary turns it off) add to the peak, so there the memory limit is 4 times the stated
// one plus 256 MiB (measured: 134 MiB of growth for the 20480-triangle case with CGAL's crossing test, 84 stated).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

// A generated sphere mesh (1.3M triangles with --full): generation, checks (self-intersections included), tree and
// queries within the stated memory (1 KiB per triangle + 64 MiB of peak growth) and, in optimised full runs, 60 s.
void mesh_large(Run& r, const StabilityOptions& o) {
  const int subdivisions = o.full ? 8 : 5;
  const double rss0 = peak_rss_mib();
  const auto start = std::chrono::steady_clock::now();
  meshes::ProceduralMesh pm = meshes::icosphere(1, subdivisions);
  if (r.naive()) pm.mesh.triangles.pop_back();  // a truncated build
  const meshes::MeshReport inspected = meshes::inspect(pm.mesh);  // once: the crossing test is most of it
  const auto rep = miscounted(r, inspected);
  const MeshReference ref(pm.mesh, inspected);
  const double triangles = static_cast<double>(pm.mesh.triangles.size());
  const double limit = (triangles / 1024 + 64) * (kSanitized ? 4 : 1) + (kSanitized ? 256 : 0);
  std::vector<char> kept;  // scratch_kept: scratch memory kept past the limit, above anything used before
  if (r.as("scratch_kept")) kept.assign(static_cast<size_t>((rss0 + limit + 16) * 1024 * 1024), 1);
  int wrong = 0;
  for (const dvec3& p : mesh_samples(200)) {
    auto s = ref.signed_distance(p);
    if (r.as("sign_flipped") && s) s = -*s;
    wrong += !s || std::abs(*s - (glm::length(p) - 1)) > pm.max_error + 1e-12;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double growth = peak_rss_mib() - rss0;
  r.m["triangles"] = triangles;
  r.m["seconds"] = seconds;
  r.m["peak_rss_growth_mib"] = growth;
  r.m["memory_limit_mib"] = limit;
  r.m["max_error"] = pm.max_error;
  r.m["samples.wrong"] = wrong;
  r.require("closed_manifold_outward", rep.closed && rep.manifold && rep.outward,
            "the generated mesh is not closed, manifold and outward");
  r.require("chord_error", wrong == 0, std::to_string(wrong) + " of 200 signed distances off the sphere by more than the chord error");
  r.require("memory", growth <= limit, "peak memory grew " + num(growth) + " MiB, over " + num(limit));
  if (o.full && !kSanitized) r.require("seconds", seconds <= 60, "took " + num(seconds) + " s, over 60");
}

}  // namespace

void add_mesh_cases(Battery& b) {
  const Variants signs = {{"refused_sign", "every_sample_signed", "no sign given"},
                          {"sign_flipped", "sign_right", "the winding's sign taken without the orientation"}};
  b.add("mesh.degenerate_triangles", "an icosphere with a repeated-index, a collinear and a sliver triangle",
        "all 3 counted degenerate; distances and ray hits right and finite",
        {{"naive", "counted", "only repeated indices counted"},
         {"vertex_distance", "queries", "the nearest vertex taken for the nearest point"}},
        mesh_degenerate);
  b.add("mesh.duplicate_vertices", "an icosphere with 5 vertices repeated", "all 5 counted; signs right",
        plus({{"naive", "counted", "vertices compared by index"}}, signs), mesh_duplicates);
  b.add("mesh.open_boundary", "an icosphere missing a triangle", "3 boundary edges reported; no sample given a sign",
        {{"naive", "no_sample_signed", "sign from the nearest vertex normal"},
         {"boundary_counted_twice", "reports_boundary", "boundary edges counted once per face beside them"}},
        mesh_open);
  b.add("mesh.nonmanifold_edge",
        "an icosphere with a fin on one edge", "1 non-manifold edge reported; no sample given a sign",
        {{"naive", "no_sample_signed", "sign from the nearest vertex normal"},
         {"fin_manifold", "reports_nonmanifold", "an edge of three faces taken for manifold"}},
        mesh_nonmanifold);
  b.add("mesh.inverted_orientation", "an icosphere wound inward",
        "reported inward (negative volume); signs still right",
        plus({{"naive", "sign_right", "sign from the nearest vertex normal"},
              {"volume_unsigned", "reports_inward", "the volume's absolute value: the orientation lost"}},
             signs),
        mesh_inverted);
  b.add("mesh.sign_flip_gap_0p1", "two closed spheres 0.1 apart (the OpenVDB sign-flip report)",
        "every sample's sign right, in the gap too",
        {{"naive", "sign_right", "sign read off a 0.25 grid"},
         {"components_nonmanifold", "reports_closed_manifold", "two components read as a pinch between them"}},
        mesh_sign_flip);
  b.add("mesh.million_triangles", "a generated icosphere: 20480 triangles, 1.3M with --full (slow)",
        "closed, manifold, outward; signed distances within the chord error; memory within 1 KiB/triangle + 64 MiB; "
        "--full: 60 s",
        {{"naive", "", "a truncated build (one triangle short)"},
         {"outward_inverted", "closed_manifold_outward", "the volume's sign read backwards"},
         {"sign_flipped", "chord_error", "the winding's sign taken without the orientation"},
         {"scratch_kept", "memory", "scratch memory kept past the limit"}},
        mesh_large);
}

}  // namespace marchcheck::validation::stability
