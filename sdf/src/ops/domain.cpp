// Domain operators: the child evaluated at a moved, repeated, mirrored or deformed point (kernels:
// marchcheck/sdf/kernels/domain.hpp).
#include "rules.hpp"

#include <cmath>

namespace marchcheck::sdf::ops {

namespace {

using P = ParamSpec;

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

ModelTransform placement(const Node& n, double time) {
  if (n.op == Op::rotate) return {rotation_matrix(n.vec3("axis"), n.scalar("angle_deg") * kDegree), {}};
  return model_transform(n, time);
}

FieldInfo derive_placed(const Node& n, std::span<const FieldInfo> cs, double time) {
  const auto [a, t] = placement(n, time);
  if (n.op == Op::rotate) return like_child(cs[0], transform_box(cs[0].bounds, a, {}), "rotation keeps the kind");
  const double stretch = spectral_norm(glm::inverse(a));  // how much p -> A^-1 (p - t) stretches distances
  FieldInfo out = like_child(cs[0], transform_box(cs[0].bounds, a, t), "rigid motion keeps the kind");
  if (std::abs(stretch - 1) > 1e-9 || std::abs(spectral_norm(a) - 1) > 1e-9) {
    out.lipschitz = cs[0].lipschitz * stretch;
    if (out.perturbation) out.perturbation->lipschitz *= stretch;
    if (stretch <= 1 && cs[0].kind <= Kind::bound) {
      out.kind = Kind::bound;
      out.reason = "affine map that does not stretch: a bound";
    } else {
      out.kind = weaker(cs[0].kind, Kind::lipschitz);
      out.reason = "affine map stretches distances by its inverse's spectral norm";
    }
  }
  return out;
}

// The child at inverse(model) * p, as one row-major 3x4 matrix.
void compile_placed(Compiler& c, const Node& n) {
  const ModelTransform m = placement(n, c.time());
  const glm::dmat3 inv = glm::inverse(m.a);
  const glm::dvec3 it = -(inv * m.t);
  // glm is column-major: inv[col][row]; the tape stores rows.
  c.point_op(TapeOp::p_affine,
             c.constants({inv[0][0], inv[1][0], inv[2][0], it.x, inv[0][1], inv[1][1], inv[2][1], it.y, inv[0][2],
                          inv[1][2], inv[2][2], it.z}),
             n.children[0]);
}

FieldInfo derive_repeated(const Node& n, std::span<const FieldInfo> cs, double) {
  const FieldInfo& child = cs[0];
  const glm::dvec3 c = n.vec3("period");
  // Only a shape centred in its cell meets its neighbours' copies in the middle: the copy beyond a face is the
  // mirror image of the own one (for a shape symmetric in its cell), so the own copy is the nearest. Off centre,
  // the field jumps at the faces even when the shape stays inside.
  bool centred_in_cell = true;
  for (int i = 0; i < 3; ++i)
    if (c[i] > 0)
      centred_in_cell = centred_in_cell && child.bounds.lo[i] >= -c[i] / 2 - 1e-12 &&
                        child.bounds.hi[i] <= c[i] / 2 + 1e-12 &&
                        std::abs(child.bounds.lo[i] + child.bounds.hi[i]) <= 1e-12 * c[i];
  FieldInfo out = child;
  out.perturbation.reset();  // a copy in the next cell is no perturbation of the own one
  if (centred_in_cell) {
    out.kind = weaker(child.kind, Kind::bound);
    out.reason = "repetition of a shape centred in its cell: a bound when the shape is symmetric in its cell";
  } else {
    out.kind = weaker(child.kind, Kind::lipschitz);
    out.reason = "repetition of a shape off centre in its cell or crossing it: the field jumps at cell faces";
  }
  Box3 b;
  if (n.op == Op::repeat_limited) {
    const glm::dvec3 count = n.vec3("count");
    b = Box3{child.bounds.lo - c * count, child.bounds.hi + c * count};
  }
  for (int i = 0; i < 3; ++i)
    if (c[i] <= 0) {
      b.lo[i] = child.bounds.lo[i];
      b.hi[i] = child.bounds.hi[i];
    }
  out.bounds = b;
  return out;
}

// A repetition's example shape sits where its declaration holds: centred in its cell.
std::vector<Node> centred_children() { return {box({0.5, 0.4, 0.3})}; }

template <TapeOp Instruction>
void compile_point_as_given(Compiler& c, const Node& n) {
  c.point_op(Instruction, c.constants(n.params), n.children[0]);
}

}  // namespace

std::vector<OpRules> domain_rules() {
  return {
      {{Op::translate, "translate", 3, 1, 1, 3, {P{"offset", 3, {}}}, "moves the child by offset"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         const glm::dvec3 o = n.vec3("offset");
         return like_child(cs[0], Box3{cs[0].bounds.lo + o, cs[0].bounds.hi + o}, "translation keeps the kind");
       },
       compile_point_as_given<TapeOp::p_translate>,
       {{"offset", {0.3, -0.2, 0.1}}}},
      {{Op::rotate, "rotate", 3, 1, 1, 3, {P{"axis", 3, {}}, P{"angle_deg", 1, {}}},
        "rotates the child about axis (through the origin)"},
       derive_placed,
       compile_placed,
       {{"axis", {1, 2, 3}}, {"angle_deg", {40}}}},
      {{Op::scale, "scale", 3, 1, 1, 3, {P{"factor", 1, {}, kPositive}}, "uniform scale: f(p / s) * s"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         const double s = n.scalar("factor");
         FieldInfo out = like_child(cs[0], Box3{cs[0].bounds.lo * s, cs[0].bounds.hi * s},
                                    "uniform scale f(p/s) s keeps the kind");
         if (out.perturbation) out.perturbation->width *= s;  // values scale by s, slopes stay
         return out;
       },
       [](Compiler& c, const Node& n) {
         const double s = n.scalar("factor");
         c.point_op(TapeOp::p_scale, c.constants({1 / s}), n.children[0]);
         c.emit(TapeOp::scale_value, c.constants({s}));
       },
       {{"factor", {1.7}}}},
      {{Op::affine, "affine", 3, 1, 1, 3, {P{"model", 12, {}}},
        "child evaluated at inverse(model) * p; model is a row-major 3x4 matrix [A | t]"},
       derive_placed,
       compile_placed,
       {{"model", {1.2, 0.1, 0, 0.2, 0, 0.9, 0.2, -0.1, 0.1, 0, 1.1, 0.3}}}},
      {{Op::animate, "animate", 3, 1, 1, 3,
        {P{"translate_sin", 3, {0, 0, 0}}, P{"spin_axis", 3, {0, 0, 1}}, P{"spin_deg_per_s", 1, {0}}},
        "model = translate(translate_sin * sin(time)) * rotate(spin_axis, spin_deg_per_s * time)"},
       derive_placed,
       compile_placed,
       {{"translate_sin", {0.3, 0, 0}}, {"spin_axis", {0, 1, 1}}, {"spin_deg_per_s", {30}}}},
      {{Op::repeat, "repeat", 3, 1, 1, 3, {P{"period", 3, {}, 0}},
        "infinite repetition, cells centred on the origin (period 0: that axis is not repeated)"},
       derive_repeated,
       compile_point_as_given<TapeOp::p_repeat>,
       {{"period", {2.5, 0, 2.5}}},
       nullptr,
       {},
       centred_children},
      {{Op::repeat_limited, "repeat_limited", 3, 1, 1, 3, {P{"period", 3, {}, 0}, P{"count", 3, {}, 0, 1e6}},
        "repetition over cells -count..count on each axis"},
       derive_repeated,
       compile_point_as_given<TapeOp::p_repeat_limited>,
       {{"period", {2.5, 0, 0}}, {"count", {1, 0, 0}}},
       nullptr,
       {},
       centred_children},
      {{Op::mirror, "mirror", 3, 1, 1, 3, {P{"axes", 3, {1, 0, 0}, 0, 1}},
        "mirror symmetry: p = abs(p) on the flagged axes"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         const glm::dvec3 axes = n.vec3("axes");
         FieldInfo out = cs[0];
         bool in_half = true;
         for (int i = 0; i < 3; ++i)
           if (axes[i] > 0.5) {
             in_half = in_half && cs[0].bounds.lo[i] >= 0;
             const double reach = std::max(std::abs(cs[0].bounds.lo[i]), std::abs(cs[0].bounds.hi[i]));
             out.bounds.lo[i] = -reach;
             out.bounds.hi[i] = reach;
           }
         out.reason = "mirror of a shape in the kept half-space keeps the kind";
         if (!in_half && out.kind == Kind::exact) {
           out.kind = Kind::bound;
           out.reason = "mirror of a shape crossing its mirror plane: 1-Lipschitz, a bound";
         }
         return out;
       },
       compile_point_as_given<TapeOp::p_mirror>,
       {}},
      {{Op::twist, "twist", 3, 1, 1, 3, {P{"rate", 1, {}}}, "rotates xz by rate * y"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         const Box3& cb = cs[0].bounds;
         const double r = std::sqrt(std::max(cb.lo.x * cb.lo.x, cb.hi.x * cb.hi.x) +
                                    std::max(cb.lo.z * cb.lo.z, cb.hi.z * cb.hi.z));
         return FieldInfo{weaker(cs[0].kind, Kind::lipschitz), cs[0].lipschitz * (1 + std::abs(n.scalar("rate")) * r),
                          Box3{{-r, cb.lo.y, -r}, {r, cb.hi.y, r}},
                          "twist stretches by 1 + rate * radius (within the child's bounding cylinder)"};
       },
       compile_point_as_given<TapeOp::p_twist>,
       {{"rate", {1.5}}}},
      {{Op::warp, "warp", 3, 1, 1, 3,
        {P{"amplitude", 1, {0.2}}, P{"frequency", 1, {20}}, P{"rates", 4, {2, 5, 2.7, 3}}, P{"offset_z", 1, {2}}},
        "child at p - w(p, time), w = (sin(f p.y sin(r0 t)) a sin(r1 t), sin(f p.x sin(r2 t)) a sin(r3 t), "
        "offset_z)"},
       [](const Node& n, std::span<const FieldInfo> cs, double time) {
         const double amp = n.scalar("amplitude"), f = n.scalar("frequency");
         const auto r = n.param("rates");
         const double ax = std::abs(amp * std::sin(r[1] * time)), ay = std::abs(amp * std::sin(r[3] * time));
         const double gx = ax * std::abs(f * std::sin(r[0] * time)), gy = ay * std::abs(f * std::sin(r[2] * time));
         const glm::dvec3 shift{0, 0, n.scalar("offset_z")};
         const Box3& b = cs[0].bounds;
         return FieldInfo{weaker(cs[0].kind, Kind::lipschitz), cs[0].lipschitz * (1 + std::max(gx, gy)),
                          Box3{b.lo + shift - glm::dvec3(ax, ay, 0), b.hi + shift + glm::dvec3(ax, ay, 0)},
                          "sinusoidal warp: Lipschitz 1 + largest warp slope"};
       },
       [](Compiler& c, const Node& n) {
         const double amp = n.scalar("amplitude"), f = n.scalar("frequency"), t = c.time();
         const auto r = n.param("rates");
         c.point_op(TapeOp::p_warp,
                    c.constants({amp * std::sin(r[1] * t), f * std::sin(r[0] * t), amp * std::sin(r[3] * t),
                                 f * std::sin(r[2] * t), n.scalar("offset_z")}),
                    n.children[0]);
       },
       {{"amplitude", {0.1}}, {"frequency", {3}}, {"offset_z", {0}}}},
  };
}

}  // namespace marchcheck::sdf::ops
