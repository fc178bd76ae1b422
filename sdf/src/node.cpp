#include "marchcheck/sdf/node.hpp"

#include "marchcheck/sdf/mesh_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

namespace marchcheck::sdf {

std::string_view to_string(Kind kind) {
  switch (kind) {
    case Kind::exact: return "exact";
    case Kind::bound: return "bound";
    case Kind::lipschitz: return "lipschitz";
    case Kind::estimate: return "estimate";
  }
  return "?";
}

namespace {

constexpr double kPositive = 1e-12;
constexpr double kInf = 1e300;

std::vector<OpInfo> build_table() {
  using P = ParamSpec;
  std::vector<OpInfo> t = {
      {Op::sphere, "sphere", 3, 0, 0, 0, {P{"radius", 1, {}, kPositive}}, "length(p) - r"},
      {Op::plane, "plane", 3, 0, 0, 0, {P{"normal", 3, {0, 1, 0}}, P{"offset", 1, {0}}},
       "dot(p, normalize(n)) + offset"},
      {Op::box, "box", 3, 0, 0, 0, {P{"half_size", 3, {}, kPositive}}, "axis-aligned box"},
      {Op::round_box, "round_box", 3, 0, 0, 0, {P{"half_size", 3, {}, kPositive}, P{"radius", 1, {}, 0}},
       "box with rounded edges (half_size is the outer size)"},
      {Op::box_frame, "box_frame", 3, 0, 0, 0, {P{"half_size", 3, {}, kPositive}, P{"thickness", 1, {}, kPositive}},
       "the twelve edges of a box, as bars of the given thickness inside it"},
      {Op::torus, "torus", 3, 0, 0, 0, {P{"major", 1, {}, 0}, P{"minor", 1, {}, kPositive}}, "torus in the xz plane"},
      {Op::capped_torus, "capped_torus", 3, 0, 0, 0,
       {P{"angle_deg", 1, {}, 0, 180}, P{"major", 1, {}, 0}, P{"minor", 1, {}, kPositive}},
       "torus arc of half-angle angle_deg about +y"},
      {Op::capsule, "capsule", 3, 0, 0, 0, {P{"a", 3, {}}, P{"b", 3, {}}, P{"radius", 1, {}, kPositive}},
       "segment a-b swept by a sphere"},
      {Op::capped_cylinder, "capped_cylinder", 3, 0, 0, 0,
       {P{"half_height", 1, {}, kPositive}, P{"radius", 1, {}, kPositive}}, "cylinder along y"},
      {Op::cone, "cone", 3, 0, 0, 0, {P{"angle_deg", 1, {}, 1e-6, 90 - 1e-6}, P{"height", 1, {}, kPositive}},
       "cone with apex at the origin opening down -y"},
      {Op::ellipsoid, "ellipsoid", 3, 0, 0, 0, {P{"radii", 3, {}, kPositive}}, "ellipsoid (a bound)"},
      {Op::octahedron, "octahedron", 3, 0, 0, 0, {P{"size", 1, {}, kPositive}}, "exact octahedron"},
      {Op::octahedron_bound, "octahedron_bound", 3, 0, 0, 0, {P{"size", 1, {}, kPositive}},
       "octahedron, cheap bound form"},
      {Op::heightfield, "heightfield", 3, 0, 0, 0, {P{"octaves", 0, {}, -kInf, kInf}},
       "p.y - sum(amplitude * value_noise(frequency * p.xz)) over [amplitude, frequency] pairs"},
      {Op::mandelbulb, "mandelbulb", 3, 0, 0, 0,
       {P{"power", 1, {8}, 2, 16}, P{"iterations", 1, {8}, 1, 64}, P{"bailout", 1, {2}, 1.0001, 1e3}},
       "power-N Mandelbulb distance estimator"},
      {Op::mesh, "mesh", 3, 0, 0, 0, {},
       "closed, consistently oriented triangle mesh (\"mesh\": a file, or procedural:NAME(ARGS)): exact signed "
       "distance"},
      {Op::circle, "circle", 2, 0, 0, 0, {P{"center", 2, {0, 0}}, P{"radius", 1, {}, kPositive}}, "2D disc"},
      {Op::rect, "rect", 2, 0, 0, 0, {P{"center", 2, {0, 0}}, P{"half_size", 2, {}, kPositive}}, "2D rectangle"},
      {Op::segment, "segment", 2, 0, 0, 0, {P{"a", 2, {}}, P{"b", 2, {}}, P{"radius", 1, {0}, 0}},
       "2D segment, thickened by radius"},
      {Op::revolve, "revolve", 3, 1, 1, 2, {P{"offset", 1, {0}, 0}},
       "a 2D shape (x: distance from the y axis minus offset, y: height) revolved about y"},
      {Op::extrude, "extrude", 3, 1, 1, 2, {P{"half_depth", 1, {}, kPositive}},
       "a 2D shape in xy extruded along z"},
      {Op::union_, "union", 3, 1, -1, 3, {}, "min of the children"},
      {Op::intersection, "intersection", 3, 2, -1, 3, {}, "max of the children"},
      {Op::subtraction, "subtraction", 3, 2, 2, 3, {}, "first child minus the second: max(a, -b)"},
      {Op::smooth_union, "smooth_union", 3, 1, -1, 3, {P{"k", 1, {}, kPositive}}, "polynomial smooth min"},
      {Op::smooth_intersection, "smooth_intersection", 3, 2, -1, 3, {P{"k", 1, {}, kPositive}},
       "polynomial smooth max"},
      {Op::smooth_subtraction, "smooth_subtraction", 3, 2, 2, 3, {P{"k", 1, {}, kPositive}},
       "polynomial smooth max(a, -b)"},
      {Op::round, "round", 3, 1, 1, 3, {P{"radius", 1, {}, 0}}, "d - radius"},
      {Op::onion, "onion", 3, 1, 1, 3, {P{"thickness", 1, {}, kPositive}}, "|d| - thickness (a shell)"},
      {Op::displace, "displace", 3, 1, 1, 3, {P{"amplitude", 1, {}}, P{"frequency", 1, {}, 0}},
       "d + amplitude * sin(f x) sin(f y) sin(f z)"},
      {Op::grid, "grid", 3, 1, 1, 3, {P{"resolution", 1, {64}, 2, 256}, P{"padding", 1, {0.1}, 0}},
       "the child sampled on a regular grid (resolution samples along the longest side of its bounds grown by "
       "padding) and interpolated trilinearly; outside the grid, the value at the nearest grid point plus the "
       "distance to it"},
      {Op::translate, "translate", 3, 1, 1, 3, {P{"offset", 3, {}}}, "moves the child by offset"},
      {Op::rotate, "rotate", 3, 1, 1, 3, {P{"axis", 3, {}}, P{"angle_deg", 1, {}}},
       "rotates the child about axis (through the origin)"},
      {Op::scale, "scale", 3, 1, 1, 3, {P{"factor", 1, {}, kPositive}}, "uniform scale: f(p / s) * s"},
      {Op::affine, "affine", 3, 1, 1, 3, {P{"model", 12, {}}},
       "child evaluated at inverse(model) * p; model is a row-major 3x4 matrix [A | t]"},
      {Op::animate, "animate", 3, 1, 1, 3,
       {P{"translate_sin", 3, {0, 0, 0}}, P{"spin_axis", 3, {0, 0, 1}}, P{"spin_deg_per_s", 1, {0}}},
       "model = translate(translate_sin * sin(time)) * rotate(spin_axis, spin_deg_per_s * time)"},
      {Op::repeat, "repeat", 3, 1, 1, 3, {P{"period", 3, {}, 0}},
       "infinite repetition, cells centred on the origin (period 0: that axis is not repeated)"},
      {Op::repeat_limited, "repeat_limited", 3, 1, 1, 3, {P{"period", 3, {}, 0}, P{"count", 3, {}, 0, 1e6}},
       "repetition over cells -count..count on each axis"},
      {Op::mirror, "mirror", 3, 1, 1, 3, {P{"axes", 3, {1, 0, 0}, 0, 1}},
       "mirror symmetry: p = abs(p) on the flagged axes"},
      {Op::twist, "twist", 3, 1, 1, 3, {P{"rate", 1, {}}}, "rotates xz by rate * y"},
      {Op::warp, "warp", 3, 1, 1, 3,
       {P{"amplitude", 1, {0.2}}, P{"frequency", 1, {20}}, P{"rates", 4, {2, 5, 2.7, 3}}, P{"offset_z", 1, {2}}},
       "child at p - w(p, time), w = (sin(f p.y sin(r0 t)) a sin(r1 t), sin(f p.x sin(r2 t)) a sin(r3 t), "
       "offset_z)"},
  };
  std::sort(t.begin(), t.end(), [](const OpInfo& a, const OpInfo& b) { return a.op < b.op; });
  return t;
}

const std::vector<OpInfo>& table() {
  static const std::vector<OpInfo> t = build_table();
  return t;
}

}  // namespace

const OpInfo& op_info(Op op) { return table()[static_cast<size_t>(op)]; }

const OpInfo* find_op(std::string_view name) {
  for (const auto& info : table())
    if (info.name == name) return &info;
  return nullptr;
}

std::span<const OpInfo> all_ops() { return table(); }

std::span<const double> Node::param(std::string_view name) const {
  size_t offset = 0;
  const auto& info = op_info(op);
  for (const auto& spec : info.params) {
    const size_t size = spec.size == 0 ? params.size() - offset : static_cast<size_t>(spec.size);
    if (spec.name == name) return std::span<const double>(params).subspan(offset, size);
    offset += size;
  }
  std::fprintf(stderr, "marchcheck: operator %s has no parameter %.*s\n", info.name.data(),
               static_cast<int>(name.size()), name.data());
  std::abort();
}

glm::dvec3 Node::vec3(std::string_view name) const {
  const auto v = param(name);
  return {v[0], v[1], v[2]};
}

Node make(Op op, std::vector<std::pair<std::string_view, std::vector<double>>> values,
          std::vector<Node> children, int material) {
  Node node;
  node.op = op;
  node.children = std::move(children);
  node.material = material;
  for (const auto& spec : op_info(op).params) {
    auto given = std::find_if(values.begin(), values.end(), [&](const auto& v) { return v.first == spec.name; });
    const auto& chosen = given != values.end() ? given->second : spec.fallback;
    node.params.insert(node.params.end(), chosen.begin(), chosen.end());
  }
  return node;
}

Node sphere(double radius, int material) { return make(Op::sphere, {{"radius", {radius}}}, {}, material); }
Node plane(glm::dvec3 normal, double offset, int material) {
  return make(Op::plane, {{"normal", {normal.x, normal.y, normal.z}}, {"offset", {offset}}}, {}, material);
}
Node box(glm::dvec3 half_size, int material) {
  return make(Op::box, {{"half_size", {half_size.x, half_size.y, half_size.z}}}, {}, material);
}
Node torus(double major, double minor, int material) {
  return make(Op::torus, {{"major", {major}}, {"minor", {minor}}}, {}, material);
}
Node translate(glm::dvec3 offset, Node child) {
  return make(Op::translate, {{"offset", {offset.x, offset.y, offset.z}}}, {std::move(child)});
}
Node unite(std::vector<Node> children) { return make(Op::union_, {}, std::move(children)); }
Node intersect(Node a, Node b) { return make(Op::intersection, {}, {std::move(a), std::move(b)}); }
Node subtract(Node a, Node b) { return make(Op::subtraction, {}, {std::move(a), std::move(b)}); }
Node smooth_union(double k, std::vector<Node> children) {
  return make(Op::smooth_union, {{"k", {k}}}, std::move(children));
}
Node mesh(std::string source, int material) {
  Node n = make(Op::mesh, {}, {}, material);
  n.source = std::move(source);
  return n;
}

bool Box3::is_finite() const {
  return std::isfinite(lo.x) && std::isfinite(lo.y) && std::isfinite(lo.z) && std::isfinite(hi.x) &&
         std::isfinite(hi.y) && std::isfinite(hi.z);
}

namespace {

Box3 sym(glm::dvec3 h) { return {-h, h}; }
Box3 expand(Box3 b, double r) { return {b.lo - r, b.hi + r}; }
Box3 hull(const Box3& a, const Box3& b) { return {glm::min(a.lo, b.lo), glm::max(a.hi, b.hi)}; }
Box3 overlap(const Box3& a, const Box3& b) { return {glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)}; }

// Box of the image of b under x -> A x + t.
Box3 transform_box(const Box3& b, const glm::dmat3& a, glm::dvec3 t) {
  if (!b.is_finite()) return Box3{};
  Box3 out{glm::dvec3(INFINITY), glm::dvec3(-INFINITY)};
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 c{(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z};
    const glm::dvec3 q = a * c + t;
    out.lo = glm::min(out.lo, q);
    out.hi = glm::max(out.hi, q);
  }
  return out;
}

// Largest singular value of a 3x3 matrix: power iteration on A^T A, which converges for any start
// not orthogonal to the top singular vector; three starts make that impossible in practice.
double spectral_norm(const glm::dmat3& a) {
  const glm::dmat3 ata = glm::transpose(a) * a;
  double best = 0;
  for (glm::dvec3 v : {glm::dvec3(1, 0.3, 0.1), glm::dvec3(0.1, 1, 0.3), glm::dvec3(0.3, 0.1, 1)}) {
    for (int i = 0; i < 100; ++i) v = glm::normalize(ata * v);
    best = std::max(best, std::sqrt(glm::length(ata * v)));
  }
  return best;
}

Kind weaker(Kind a, Kind b) { return std::max(a, b); }

// Combining children: min/max-like operators keep 1-Lipschitz fields 1-Lipschitz with the combined zero
// set, so exact and bound children give a bound; a child with only a Lipschitz bound gives only that.
FieldInfo combine(const std::vector<FieldInfo>& cs, const std::string& what) {
  FieldInfo out;
  out.kind = Kind::bound;
  out.lipschitz = 0;
  for (const auto& c : cs) {
    out.kind = weaker(out.kind, c.kind);
    out.lipschitz = std::max(out.lipschitz, c.lipschitz);
  }
  out.reason = out.kind >= Kind::lipschitz
                   ? what + " of an " + std::string(to_string(out.kind)) + " field"
                   : what + " of exact/bound fields: a bound (exact only on parts of the surface)";
  return out;
}

}  // namespace

glm::dmat3 rotation_matrix(glm::dvec3 axis, double angle_rad) {
  const glm::dvec3 u = glm::normalize(axis);
  const double c = std::cos(angle_rad), s = std::sin(angle_rad), k = 1 - c;
  // Column-major: m[col][row].
  return glm::dmat3(c + u.x * u.x * k, u.y * u.x * k + u.z * s, u.z * u.x * k - u.y * s,  //
                    u.x * u.y * k - u.z * s, c + u.y * u.y * k, u.z * u.y * k + u.x * s,  //
                    u.x * u.z * k + u.y * s, u.y * u.z * k - u.x * s, c + u.z * u.z * k);
}

ModelTransform model_transform(const Node& node, double time) {
  if (node.op == Op::affine) {
    const auto m = node.param("model");
    return {glm::transpose(glm::dmat3(m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10])), {m[3], m[7], m[11]}};
  }
  return {rotation_matrix(node.vec3("spin_axis"), node.scalar("spin_deg_per_s") * time * std::numbers::pi / 180),
          node.vec3("translate_sin") * std::sin(time)};
}

GridLayout grid_layout(const Node& grid, const Box3& child_bounds) {
  const double pad = grid.scalar("padding");
  const glm::dvec3 extent = child_bounds.size() + 2 * pad;
  const double cell = std::max({extent.x, extent.y, extent.z}) / (grid.scalar("resolution") - 1);
  GridLayout g;
  g.cell = cell;
  for (int i = 0; i < 3; ++i) g.count[i] = std::max(2, static_cast<int>(std::ceil(extent[i] / cell - 1e-9)) + 1);
  g.lo = child_bounds.center() - glm::dvec3(g.count - 1) * (cell / 2);
  return g;
}

FieldInfo derive_info(const Node& node, double time) {
  std::vector<FieldInfo> cs;
  for (const auto& child : node.children) cs.push_back(derive_info(child, time));
  const FieldInfo child = cs.empty() ? FieldInfo{} : cs.front();
  auto same_as_child = [&](Box3 bounds, const char* reason) {
    FieldInfo out = child;
    out.bounds = bounds;
    out.reason = reason;
    return out;
  };
  switch (node.op) {
    case Op::sphere: return {Kind::exact, 1, sym(glm::dvec3(node.scalar("radius"))), "closed form"};
    case Op::plane: return {Kind::exact, 1, Box3{}, "closed form"};
    case Op::box: return {Kind::exact, 1, sym(node.vec3("half_size")), "closed form"};
    case Op::round_box: return {Kind::exact, 1, sym(node.vec3("half_size")), "closed form"};
    case Op::box_frame: return {Kind::exact, 1, sym(node.vec3("half_size")), "closed form"};
    case Op::torus: {
      const double big = node.scalar("major") + node.scalar("minor");
      return {Kind::exact, 1, sym({big, node.scalar("minor"), big}), "closed form"};
    }
    case Op::capped_torus: {
      const double big = node.scalar("major") + node.scalar("minor");
      return {Kind::exact, 1, sym(glm::dvec3(big)), "closed form"};
    }
    case Op::capsule: {
      const double r = node.scalar("radius");
      const glm::dvec3 a = node.vec3("a"), b = node.vec3("b");
      return {Kind::exact, 1, Box3{glm::min(a, b) - r, glm::max(a, b) + r}, "closed form"};
    }
    case Op::capped_cylinder: {
      const double r = node.scalar("radius");
      return {Kind::exact, 1, sym({r, node.scalar("half_height"), r}), "closed form"};
    }
    case Op::cone: {
      const double h = node.scalar("height"), r = h * std::tan(node.scalar("angle_deg") * std::numbers::pi / 180);
      return {Kind::exact, 1, Box3{{-r, -h, -r}, {r, 0, r}}, "closed form"};
    }
    case Op::ellipsoid:
      return {Kind::bound, 1, sym(node.vec3("radii")), "k0 (k0 - 1) / k1 outside, (k0 - 1) min(r) inside: a bound, not exact"};
    case Op::octahedron: return {Kind::exact, 1, sym(glm::dvec3(node.scalar("size"))), "closed form"};
    case Op::octahedron_bound:
      return {Kind::bound, 1, sym(glm::dvec3(node.scalar("size"))), "plane distance scaled by 1/sqrt(3)"};
    case Op::heightfield: {
      // Smoothstep-interpolated bilinear noise in [0,1]: each partial derivative is at most 1.5 * frequency.
      double slope = 0, top = 0;
      const auto oct = node.param("octaves");
      for (size_t i = 0; i + 1 < oct.size(); i += 2) {
        slope += 1.5 * std::sqrt(2.0) * std::abs(oct[i]) * std::abs(oct[i + 1]);
        top += std::max(oct[i], 0.0);
      }
      FieldInfo out{Kind::lipschitz, std::sqrt(1 + slope * slope),
                    Box3{{-INFINITY, -INFINITY, -INFINITY}, {INFINITY, top, INFINITY}},
                    "height field: vertical distance, overestimates by up to sqrt(1 + slope^2)"};
      if (slope == 0) out = {Kind::exact, 1, out.bounds, "flat height field: a plane"};
      return out;
    }
    case Op::mandelbulb:
      return {Kind::estimate, 2, sym(glm::dvec3(1.25)),
              "escape-time distance estimate 0.5 log(r) r / dr: no bound and no Lipschitz constant (it jumps "
              "where the escape iteration changes); stepped at half"};
    case Op::mesh:
      return {Kind::exact, 1, node.mesh ? node.mesh->bounds() : Box3{},
              "closed, consistently oriented mesh: distance to the closest triangle, sign by angle-weighted "
              "pseudonormals"};
    case Op::circle: {
      const double r = node.scalar("radius");
      const auto c = node.param("center");
      return {Kind::exact, 1, Box3{{c[0] - r, c[1] - r, 0}, {c[0] + r, c[1] + r, 0}}, "closed form"};
    }
    case Op::rect: {
      const auto c = node.param("center"), h = node.param("half_size");
      return {Kind::exact, 1, Box3{{c[0] - h[0], c[1] - h[1], 0}, {c[0] + h[0], c[1] + h[1], 0}}, "closed form"};
    }
    case Op::segment: {
      const auto a = node.param("a"), b = node.param("b");
      const double r = node.scalar("radius");
      return {Kind::exact, 1,
              Box3{{std::min(a[0], b[0]) - r, std::min(a[1], b[1]) - r, 0},
                   {std::max(a[0], b[0]) + r, std::max(a[1], b[1]) + r, 0}},
              "closed form"};
    }
    case Op::revolve: {
      const double reach = node.scalar("offset") + std::max(std::abs(child.bounds.lo.x), std::abs(child.bounds.hi.x));
      return same_as_child(Box3{{-reach, child.bounds.lo.y, -reach}, {reach, child.bounds.hi.y, reach}},
                           "revolution keeps the 2D shape's kind");
    }
    case Op::extrude: {
      const double h = node.scalar("half_depth");
      return same_as_child(Box3{{child.bounds.lo.x, child.bounds.lo.y, -h}, {child.bounds.hi.x, child.bounds.hi.y, h}},
                           "extrusion keeps the 2D shape's kind");
    }
    case Op::union_:
    case Op::smooth_union:
    case Op::intersection:
    case Op::smooth_intersection:
    case Op::subtraction:
    case Op::smooth_subtraction: {
      if (node.op == Op::union_ && cs.size() == 1) return child;
      // Smooth variants: smin = w a + (1 - w) b with w in [0,1] along the blend, still max(L)-Lipschitz.
      FieldInfo out = combine(cs, std::string(op_info(node.op).name));
      const bool unites = node.op == Op::union_ || node.op == Op::smooth_union;
      const bool intersects = node.op == Op::intersection || node.op == Op::smooth_intersection;
      out.bounds = cs.front().bounds;
      for (const auto& c : cs) {
        if (unites) out.bounds = hull(out.bounds, c.bounds);
        if (intersects) out.bounds = overlap(out.bounds, c.bounds);
      }
      // The smooth union adds up to k/4 of material between its children.
      if (node.op == Op::smooth_union) out.bounds = expand(out.bounds, node.scalar("k") / 4);
      return out;
    }
    case Op::round: {
      FieldInfo out = same_as_child(expand(child.bounds, node.scalar("radius") * child.lipschitz),
                                    "offset surface: exact outside the original, a bound elsewhere");
      if (out.kind == Kind::exact && node.scalar("radius") > 0) out.kind = Kind::bound;
      return out;
    }
    case Op::onion: {
      FieldInfo out = same_as_child(expand(child.bounds, node.scalar("thickness") * child.lipschitz),
                                    "shell |d| - t: a bound");
      if (out.kind == Kind::exact) out.kind = Kind::bound;
      return out;
    }
    case Op::displace: {
      // |grad(a sin x sin y sin z)|^2 = a^2 w^2 (c1^2 s2^2 s3^2 + ...) <= a^2 w^2.
      const double a = std::abs(node.scalar("amplitude")), w = node.scalar("frequency");
      return {weaker(child.kind, Kind::lipschitz), child.lipschitz + a * w, expand(child.bounds, a),
              "displacement adds amplitude * frequency to the Lipschitz bound"};
    }
    case Op::grid: {
      // Along each axis the interpolant's slope is a weighted mean of sample differences over one cell, each at
      // most the child's L; outside the grid the added distance has slope 1. So |grad| <= sqrt(3) max(L, 1).
      // Interpolation is no bound: between samples it can exceed the distance (by up to sqrt(3)/2 of a cell
      // for an exact child).
      return {weaker(child.kind, Kind::lipschitz), std::sqrt(3.0) * std::max(child.lipschitz, 1.0),
              grid_layout(node, child.bounds).box(),
              "trilinear interpolation of samples: each axis's slope at most the child's L, so |grad| <= sqrt(3) L"};
    }
    case Op::translate: {
      const glm::dvec3 o = node.vec3("offset");
      return same_as_child(Box3{child.bounds.lo + o, child.bounds.hi + o}, "translation keeps the kind");
    }
    case Op::rotate: {
      const auto r = rotation_matrix(node.vec3("axis"), node.scalar("angle_deg") * std::numbers::pi / 180);
      return same_as_child(transform_box(child.bounds, r, {}), "rotation keeps the kind");
    }
    case Op::scale: {
      const double s = node.scalar("factor");
      return same_as_child(Box3{child.bounds.lo * s, child.bounds.hi * s}, "uniform scale f(p/s) s keeps the kind");
    }
    case Op::affine:
    case Op::animate: {
      const auto [a, t] = model_transform(node, time);
      const double stretch = spectral_norm(glm::inverse(a));  // how much p -> A^-1 (p - t) stretches distances
      FieldInfo out = same_as_child(transform_box(child.bounds, a, t), "rigid motion keeps the kind");
      if (std::abs(stretch - 1) > 1e-9 || std::abs(spectral_norm(a) - 1) > 1e-9) {
        out.lipschitz = child.lipschitz * stretch;
        if (stretch <= 1 && child.kind <= Kind::bound) {
          out.kind = Kind::bound;
          out.reason = "affine map that does not stretch: a bound";
        } else {
          out.kind = weaker(child.kind, Kind::lipschitz);
          out.reason = "affine map stretches distances by its inverse's spectral norm";
        }
      }
      return out;
    }
    case Op::repeat:
    case Op::repeat_limited: {
      const glm::dvec3 c = node.vec3("period");
      bool inside_cell = true;
      for (int i = 0; i < 3; ++i)
        if (c[i] > 0)
          inside_cell = inside_cell && child.bounds.lo[i] >= -c[i] / 2 - 1e-12 && child.bounds.hi[i] <= c[i] / 2 + 1e-12;
      FieldInfo out = child;
      if (inside_cell) {
        out.kind = weaker(child.kind, Kind::bound);
        out.reason = "repetition of a shape inside its cell: a bound when the shape is symmetric in its cell";
      } else {
        out.kind = weaker(child.kind, Kind::lipschitz);
        out.reason = "repetition of a shape that crosses its cell: the field jumps at cell faces";
      }
      Box3 b;
      if (node.op == Op::repeat_limited) {
        const glm::dvec3 n = node.vec3("count");
        b = Box3{child.bounds.lo - c * n, child.bounds.hi + c * n};
      }
      for (int i = 0; i < 3; ++i)
        if (c[i] <= 0) {
          b.lo[i] = child.bounds.lo[i];
          b.hi[i] = child.bounds.hi[i];
        }
      out.bounds = b;
      return out;
    }
    case Op::mirror: {
      const glm::dvec3 axes = node.vec3("axes");
      FieldInfo out = child;
      bool in_half = true;
      Box3 b = child.bounds;
      for (int i = 0; i < 3; ++i)
        if (axes[i] > 0.5) {
          in_half = in_half && child.bounds.lo[i] >= 0;
          const double reach = std::max(std::abs(child.bounds.lo[i]), std::abs(child.bounds.hi[i]));
          b.lo[i] = -reach;
          b.hi[i] = reach;
        }
      out.bounds = b;
      out.reason = "mirror of a shape in the kept half-space keeps the kind";
      if (!in_half && out.kind == Kind::exact) {
        out.kind = Kind::bound;
        out.reason = "mirror of a shape crossing its mirror plane: 1-Lipschitz, a bound";
      }
      return out;
    }
    case Op::twist: {
      const Box3& cb = child.bounds;
      const double r = std::sqrt(std::max(cb.lo.x * cb.lo.x, cb.hi.x * cb.hi.x) +
                                 std::max(cb.lo.z * cb.lo.z, cb.hi.z * cb.hi.z));
      return {weaker(child.kind, Kind::lipschitz), child.lipschitz * (1 + std::abs(node.scalar("rate")) * r),
              Box3{{-r, cb.lo.y, -r}, {r, cb.hi.y, r}},
              "twist stretches by 1 + rate * radius (within the child's bounding cylinder)"};
    }
    case Op::warp: {
      const double amp = node.scalar("amplitude"), f = node.scalar("frequency");
      const auto r = node.param("rates");
      const double ax = std::abs(amp * std::sin(r[1] * time)), ay = std::abs(amp * std::sin(r[3] * time));
      const double gx = ax * std::abs(f * std::sin(r[0] * time)), gy = ay * std::abs(f * std::sin(r[2] * time));
      const glm::dvec3 shift{0, 0, node.scalar("offset_z")};
      return {weaker(child.kind, Kind::lipschitz), child.lipschitz * (1 + std::max(gx, gy)),
              Box3{child.bounds.lo + shift - glm::dvec3(ax, ay, 0), child.bounds.hi + shift + glm::dvec3(ax, ay, 0)},
              "sinusoidal warp: Lipschitz 1 + largest warp slope"};
    }
    case Op::count_: break;
  }
  return {};
}

namespace {

void validate_into(const Node& node, const std::string& path, std::string& error) {
  if (!error.empty()) return;
  if (static_cast<size_t>(node.op) >= static_cast<size_t>(Op::count_)) {
    error = path + ": unknown operator";
    return;
  }
  const auto& info = op_info(node.op);
  const int n = static_cast<int>(node.children.size());
  if (n < info.min_children || (info.max_children >= 0 && n > info.max_children)) {
    error = path + ": " + std::string(info.name) + " takes " +
            (info.max_children == 0 ? "no children"
             : info.max_children < 0 ? "at least " + std::to_string(info.min_children) + " children"
             : info.min_children == info.max_children ? std::to_string(info.min_children) + " child(ren)"
                                                       : "between " + std::to_string(info.min_children) + " and " +
                                                             std::to_string(info.max_children) + " children") +
            ", got " + std::to_string(n);
    return;
  }
  size_t expected = 0;
  for (const auto& spec : info.params) expected += spec.size > 0 ? static_cast<size_t>(spec.size) : 0;
  const bool variable = std::any_of(info.params.begin(), info.params.end(), [](auto& s) { return s.size == 0; });
  if (variable ? (node.params.size() < expected || (node.params.size() - expected) % 2 != 0)
               : node.params.size() != expected) {
    error = path + ": " + std::string(info.name) + " has the wrong number of parameter values";
    return;
  }
  size_t offset = 0;
  for (const auto& spec : info.params) {
    const size_t size = spec.size == 0 ? node.params.size() - offset : static_cast<size_t>(spec.size);
    for (size_t i = 0; i < size; ++i) {
      const double v = node.params[offset + i];
      if (!std::isfinite(v) || v < spec.min || v > spec.max) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "%s/%.*s: value %g is out of range [%g, %g]", path.c_str(),
                      static_cast<int>(spec.name.size()), spec.name.data(), v, spec.min, spec.max);
        error = buf;
        return;
      }
    }
    offset += size;
  }
  if (node.op == Op::heightfield && node.params.empty()) error = path + "/octaves: needs at least one pair";
  if (node.op == Op::mesh && !node.mesh)
    error = path + "/mesh: '" + node.source + "' is not loaded (scenes with meshes need a mesh loader)";

  for (int i = 0; i < n && error.empty(); ++i) {
    const auto& c = node.children[static_cast<size_t>(i)];
    const std::string child_path = path + (info.max_children == 1 ? "/child" : "/children/" + std::to_string(i));
    if (static_cast<size_t>(c.op) < static_cast<size_t>(Op::count_) && op_info(c.op).dimension != info.child_dimension) {
      error = child_path + ": " + std::string(info.name) + " needs a " + std::to_string(info.child_dimension) +
              "D child, " + std::string(op_info(c.op).name) + " is " + std::to_string(op_info(c.op).dimension) + "D";
      return;
    }
    validate_into(c, child_path, error);
  }
  if (node.op == Op::grid && error.empty() && !derive_info(node.children[0]).bounds.is_finite())
    error = path + "/child: a grid needs a child with finite bounds";
}

}  // namespace

std::string validate_tree(const Node& node) {
  std::string error;
  validate_into(node, "", error);
  if (error.empty() && op_info(node.op).dimension != 3)
    error = ": the scene root must be a 3D shape, " + std::string(op_info(node.op).name) + " is 2D";
  return error;
}

}  // namespace marchcheck::sdf
