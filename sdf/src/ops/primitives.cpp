// The 3D primitives (kernels: marchcheck/sdf/kernels/primitives.hpp).
#include "rules.hpp"

#include "marchcheck/meshes/io.hpp"
#include "marchcheck/sdf/glsl_field.hpp"
#include "marchcheck/sdf/mesh_distance.hpp"

#include <cmath>

namespace marchcheck::sdf::ops {

namespace {

using P = ParamSpec;
constexpr double kInf = 1e300;

FieldInfo exact(Box3 bounds) { return {Kind::exact, 1, bounds, "closed form"}; }

// The box around the solid dot(p, normalize(normal)) + offset <= 0: along an axis (the ground planes), the side
// past -offset; any other normal, everything.
Box3 half_space_box(glm::dvec3 normal, double offset) {
  Box3 box;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 axis = glm::dvec3(k == 0, k == 1, k == 2);
    if (normal == glm::length(normal) * axis) box.hi[k] = -offset;
    if (normal == -glm::length(normal) * axis) box.lo[k] = offset;
  }
  return box;
}

// A GLSL field is what its node declares, or, declared unknown, Lipschitz with the slope measured at load.
FieldInfo glsl_info(const GlslSpec& spec) {
  const std::string name = spec.code.empty() ? spec.source : "inline GLSL";
  if (spec.measured)
    return {Kind::lipschitz, spec.lipschitz, Box3{},
            name + ": kind not declared; Lipschitz constant " + std::to_string(spec.lipschitz) +
                " measured over [-4, 4]^3 by finite differences (a lower bound)"};
  return {spec.kind, spec.kind == Kind::lipschitz ? spec.lipschitz : 1.0, Box3{},
          name + ": declared " + std::string(to_string(spec.kind))};
}

// The solids with a closed form.
std::vector<OpRules> solid_rules() {
  return {
      {{Op::sphere, "sphere", 3, 0, 0, 0, {P{"radius", 1, {}, kPositive}}, "length(p) - r"},
       [](const Node& n, auto, double) { return exact(symmetric_box(glm::dvec3(n.scalar("radius")))); },
       compile_as_given<TapeOp::sphere>,
       {{"radius", {0.8}}}},
      {{Op::plane, "plane", 3, 0, 0, 0, {P{"normal", 3, {0, 1, 0}}, P{"offset", 1, {0}}},
        "dot(p, normalize(n)) + offset"},
       [](const Node& n, auto, double) { return exact(half_space_box(n.vec3("normal"), n.scalar("offset"))); },
       [](Compiler& c, const Node& n) {
         const glm::dvec3 u = glm::normalize(n.vec3("normal"));
         c.primitive(TapeOp::plane, c.constants({u.x, u.y, u.z, n.scalar("offset")}), n);
       },
       {{"normal", {0.2, 1, -0.3}}, {"offset", {0.1}}}},
      {{Op::box, "box", 3, 0, 0, 0, {P{"half_size", 3, {}, kPositive}}, "axis-aligned box"},
       [](const Node& n, auto, double) { return exact(symmetric_box(n.vec3("half_size"))); },
       compile_as_given<TapeOp::box>,
       {{"half_size", {0.9, 0.5, 0.3}}}},
      {{Op::round_box, "round_box", 3, 0, 0, 0, {P{"half_size", 3, {}, kPositive}, P{"radius", 1, {}, 0}},
        "box with rounded edges (half_size is the outer size)"},
       [](const Node& n, auto, double) { return exact(symmetric_box(n.vec3("half_size"))); },
       compile_as_given<TapeOp::round_box>,
       {{"half_size", {0.9, 0.5, 0.4}}, {"radius", {0.2}}}},
      {{Op::box_frame, "box_frame", 3, 0, 0, 0, {P{"half_size", 3, {}, kPositive}, P{"thickness", 1, {}, kPositive}},
        "the twelve edges of a box, as bars of the given thickness inside it"},
       [](const Node& n, auto, double) { return exact(symmetric_box(n.vec3("half_size"))); },
       compile_as_given<TapeOp::box_frame>,
       {{"half_size", {0.8, 0.6, 0.7}}, {"thickness", {0.15}}}},
      {{Op::torus, "torus", 3, 0, 0, 0, {P{"major", 1, {}, 0}, P{"minor", 1, {}, kPositive}}, "torus in the xz plane"},
       [](const Node& n, auto, double) {
         const double big = n.scalar("major") + n.scalar("minor");
         return exact(symmetric_box({big, n.scalar("minor"), big}));
       },
       compile_as_given<TapeOp::torus>,
       {{"major", {0.7}}, {"minor", {0.25}}}},
      {{Op::capped_torus, "capped_torus", 3, 0, 0, 0,
        {P{"angle_deg", 1, {}, 0, 180}, P{"major", 1, {}, 0}, P{"minor", 1, {}, kPositive}},
        "torus arc of half-angle angle_deg about +y"},
       [](const Node& n, auto, double) {
         return exact(symmetric_box(glm::dvec3(n.scalar("major") + n.scalar("minor"))));
       },
       [](Compiler& c, const Node& n) {
         const double angle = n.scalar("angle_deg") * kDegree;
         c.primitive(TapeOp::capped_torus,
                     c.constants({std::sin(angle), std::cos(angle), n.scalar("major"), n.scalar("minor")}), n);
       },
       {{"angle_deg", {120}}, {"major", {0.7}}, {"minor", {0.2}}}},
      {{Op::capsule, "capsule", 3, 0, 0, 0, {P{"a", 3, {}}, P{"b", 3, {}}, P{"radius", 1, {}, kPositive}},
        "segment a-b swept by a sphere"},
       [](const Node& n, auto, double) {
         const double r = n.scalar("radius");
         const glm::dvec3 a = n.vec3("a"), b = n.vec3("b");
         return exact(Box3{glm::min(a, b) - r, glm::max(a, b) + r});
       },
       [](Compiler& c, const Node& n) {
         const glm::dvec3 a = n.vec3("a"), ba = n.vec3("b") - a;
         const double len2 = glm::dot(ba, ba);
         c.primitive(TapeOp::capsule,
                     c.constants({a.x, a.y, a.z, ba.x, ba.y, ba.z, len2 > 0 ? 1 / len2 : 0, n.scalar("radius")}), n);
       },
       {{"a", {-0.5, -0.3, 0.1}}, {"b", {0.6, 0.4, -0.2}}, {"radius", {0.3}}}},
      {{Op::capped_cylinder, "capped_cylinder", 3, 0, 0, 0,
        {P{"half_height", 1, {}, kPositive}, P{"radius", 1, {}, kPositive}}, "cylinder along y"},
       [](const Node& n, auto, double) {
         const double r = n.scalar("radius");
         return exact(symmetric_box({r, n.scalar("half_height"), r}));
       },
       compile_as_given<TapeOp::capped_cylinder>,
       {{"half_height", {0.6}}, {"radius", {0.4}}}},
      {{Op::cone, "cone", 3, 0, 0, 0, {P{"angle_deg", 1, {}, 1e-6, 90 - 1e-6}, P{"height", 1, {}, kPositive}},
        "cone with apex at the origin opening down -y"},
       [](const Node& n, auto, double) {
         const double h = n.scalar("height"), r = h * std::tan(n.scalar("angle_deg") * kDegree);
         return exact(Box3{{-r, -h, -r}, {r, 0, r}});
       },
       [](Compiler& c, const Node& n) {
         const double h = n.scalar("height");
         c.primitive(TapeOp::cone, c.constants({h * std::tan(n.scalar("angle_deg") * kDegree), -h}), n);
       },
       {{"angle_deg", {30}}, {"height", {1.2}}}},
      {{Op::ellipsoid, "ellipsoid", 3, 0, 0, 0, {P{"radii", 3, {}, kPositive}}, "ellipsoid (a bound)"},
       [](const Node& n, auto, double) {
         return FieldInfo{Kind::bound, 1, symmetric_box(n.vec3("radii")),
                          "k0 (k0 - 1) / k1 outside, (k0 - 1) min(r) inside: a bound, not exact"};
       },
       compile_as_given<TapeOp::ellipsoid>,
       {{"radii", {0.9, 0.5, 0.3}}}},
      {{Op::octahedron, "octahedron", 3, 0, 0, 0, {P{"size", 1, {}, kPositive}}, "exact octahedron"},
       [](const Node& n, auto, double) { return exact(symmetric_box(glm::dvec3(n.scalar("size")))); },
       compile_as_given<TapeOp::octahedron>,
       {{"size", {0.9}}}},
      {{Op::octahedron_bound, "octahedron_bound", 3, 0, 0, 0, {P{"size", 1, {}, kPositive}},
        "octahedron, cheap bound form"},
       [](const Node& n, auto, double) {
         return FieldInfo{Kind::bound, 1, symmetric_box(glm::dvec3(n.scalar("size"))),
                          "plane distance scaled by 1/sqrt(3)"};
       },
       compile_as_given<TapeOp::octahedron_bound>,
       {{"size", {0.9}}}},
  };
}

// The primitives that are fields rather than solids with a closed form: a height field, a fractal, a mesh.
std::vector<OpRules> field_rules() {
  return {
      {{Op::heightfield, "heightfield", 3, 0, 0, 0, {P{"hash", 1, {0}, 0, 1}, P{"octaves", 0, {}, -kInf, kInf}},
        "p.y - sum(amplitude * value_noise(frequency * p.xz)) over [amplitude, frequency] pairs; hash 0: splitmix64 "
        "(the same in every precision), 1: the lee seed's fract(sin(dot(c, (12.9898, 54.233))) * 43758.5453123) in "
        "the march's arithmetic"},
       [](const Node& n, auto, double) {
         // Smoothstep-interpolated bilinear noise in [0,1]: each partial derivative is at most 1.5 * frequency.
         double slope = 0, top = 0, band = 0;
         const auto octaves = n.param("octaves");
         for (size_t i = 0; i + 1 < octaves.size(); i += 2) {
           slope += 1.5 * std::sqrt(2.0) * std::abs(octaves[i]) * std::abs(octaves[i + 1]);
           top += std::max(octaves[i], 0.0);
           band += std::abs(octaves[i]);
         }
         FieldInfo out{Kind::lipschitz, std::sqrt(1 + slope * slope),
                       Box3{{-INFINITY, -INFINITY, -INFINITY}, {INFINITY, top, INFINITY}},
                       "height field: vertical distance, overestimates by up to sqrt(1 + slope^2)"};
         // p.y (1-Lipschitz) less a height within [sum of negative amplitudes, top]: a band sum |amplitude| wide.
         out.perturbation = Perturbation{1, band};
         if (slope == 0) out = {Kind::exact, 1, out.bounds, "flat height field: a plane"};
         return out;
       },
       [](Compiler& c, const Node& n) {
         const auto octaves = n.param("octaves");
         const auto offset = c.constants({static_cast<double>(octaves.size() / 2), n.scalar("hash")});
         c.constants(octaves);
         c.primitive(TapeOp::heightfield, offset, n);
       },
       {{"octaves", {0.4, 1.1, 0.1, 3}}},
       [](const Node& n) {
         if (n.param("octaves").empty()) return std::string("/octaves: needs at least one pair");
         const double hash = n.scalar("hash");
         return hash == 0 || hash == 1 ? std::string() : std::string("/hash: 0 (splitmix64) or 1 (the seed's sin hash)");
       }},
      {{Op::mandelbulb, "mandelbulb", 3, 0, 0, 0,
        {P{"power", 1, {8}, 2, 16}, P{"iterations", 1, {8}, 1, 64}, P{"bailout", 1, {2}, 1.0001, 1e3}},
        "power-N Mandelbulb distance estimator"},
       [](const Node&, auto, double) {
         return FieldInfo{Kind::estimate, 2, symmetric_box(glm::dvec3(1.25)),
                          "escape-time distance estimate 0.5 log(r) r / dr: no bound and no Lipschitz constant (it "
                          "jumps where the escape iteration changes); stepped at half"};
       },
       compile_as_given<TapeOp::mandelbulb>,
       {}},
      {{Op::mesh, "mesh", 3, 0, 0, 0, {P{"weld", 1, {0}, 0, 1e6}},
        "closed, consistently oriented triangle mesh (\"mesh\": a file, or procedural:NAME(ARGS)): exact signed "
        "distance; \"weld\": a distance within which vertices are merged first (0: off)"},
       [](const Node& n, auto, double) {
         return FieldInfo{Kind::exact, 1, n.mesh ? n.mesh->bounds() : Box3{},
                          "closed, consistently oriented mesh: distance to the closest triangle, sign by "
                          "angle-weighted pseudonormals"};
       },
       [](Compiler& c, const Node& n) { c.primitive(TapeOp::mesh, c.mesh(n.mesh), n); },
       {},
       [](const Node& n) {
         return n.mesh ? std::string()
                       : "/mesh: '" + n.source + "' is not loaded (scenes with meshes need a mesh loader)";
       },
       [](Node& n) {
         n.source = "procedural:torus(0.7,0.25,48,24)";
         n.mesh = std::make_shared<const MeshDistance>(meshes::load_mesh_source(n.source));
       }},
      {{Op::glsl, "glsl", 3, 0, 0, 0, {},
        "a field written in GLSL (\"source\": a file, or \"code\"; \"function\": its name, map by default; "
        "\"uniforms\"; \"kind\": exact, bound, lipschitz with \"lipschitz\": L, or unknown: measured)"},
       [](const Node& n, auto, double) { return n.glsl ? glsl_info(n.glsl->spec()) : FieldInfo{}; },
       [](Compiler& c, const Node& n) { c.primitive(TapeOp::glsl, c.glsl(n.glsl), n); },
       {},
       [](const Node& n) { return n.glsl ? std::string() : std::string("/source: the GLSL field is not compiled"); },
       [](Node& n) {
         GlslSpec spec;
         spec.code =
             "float sdTorus(vec3 p, vec2 t) { vec2 q = vec2(length(p.xz) - t.x, p.y); return length(q) - t.y; }\n"
             "float map(vec3 p) { p.xy *= mat2(0.8, 0.6, -0.6, 0.8); return sdTorus(p, vec2(0.7, 0.25)); }\n";
         spec.kind = Kind::exact;
         spec.measured = false;
         n.glsl = std::make_shared<const GlslField>(spec, spec.code, "example.glsl");
       }},
  };
}

}  // namespace

std::vector<OpRules> primitive_rules() {
  std::vector<OpRules> rules = solid_rules();
  for (auto& row : field_rules()) rules.push_back(std::move(row));
  return rules;
}

}  // namespace marchcheck::sdf::ops
