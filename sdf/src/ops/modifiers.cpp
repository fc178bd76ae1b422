// Operators that modify a distance: offset, shell, displacement, and sampling on a grid (kernels:
// marchcheck/sdf/kernels/modifiers.hpp).
#include "rules.hpp"

#include <cmath>

namespace marchcheck::sdf::ops {

namespace {

using P = ParamSpec;

// The child evaluated in double at every grid point, once, at compile time.
std::uint32_t grid_samples(Compiler& c, const Node& n) {
  const GridLayout g = grid_layout(n, derive_info(n.children[0], c.time()).bounds);
  const Tape child = compile(n.children[0], c.time());
  const auto offset = c.constants({static_cast<double>(g.count.x), static_cast<double>(g.count.y),
                                   static_cast<double>(g.count.z), g.lo.x, g.lo.y, g.lo.z, g.cell});
  std::vector<double> samples;
  samples.reserve(static_cast<size_t>(g.count.x) * static_cast<size_t>(g.count.y) * static_cast<size_t>(g.count.z));
  for (int z = 0; z < g.count.z; ++z)
    for (int y = 0; y < g.count.y; ++y)
      for (int x = 0; x < g.count.x; ++x) samples.push_back(evaluate(child, g.lo + glm::dvec3(x, y, z) * g.cell));
  c.constants(samples);
  return offset;
}

}  // namespace

std::vector<OpRules> modifier_rules() {
  return {
      {{Op::round, "round", 3, 1, 1, 3, {P{"radius", 1, {}, 0}}, "d - radius"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         FieldInfo out = like_child(cs[0], expand(cs[0].bounds, n.scalar("radius") * cs[0].lipschitz),
                                    "offset surface: exact outside the original, a bound elsewhere");
         if (out.kind == Kind::exact && n.scalar("radius") > 0) out.kind = Kind::bound;
         return out;
       },
       [](Compiler& c, const Node& n) { c.modify(TapeOp::round_, n, c.constants(n.params)); },
       {{"radius", {0.1}}}},
      {{Op::onion, "onion", 3, 1, 1, 3, {P{"thickness", 1, {}, kPositive}}, "|d| - thickness (a shell)"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         FieldInfo out = like_child(cs[0], expand(cs[0].bounds, n.scalar("thickness") * cs[0].lipschitz),
                                    "shell |d| - t: a bound");
         if (out.kind == Kind::exact) out.kind = Kind::bound;
         return out;
       },
       [](Compiler& c, const Node& n) { c.modify(TapeOp::onion, n, c.constants(n.params)); },
       {{"thickness", {0.1}}}},
      {{Op::displace, "displace", 3, 1, 1, 3, {P{"amplitude", 1, {}}, P{"frequency", 1, {}, 0}},
        "d + amplitude * sin(f x) sin(f y) sin(f z)"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         // |grad(a sin x sin y sin z)|^2 = a^2 w^2 (c1^2 s2^2 s3^2 + ...) <= a^2 w^2.
         const double a = std::abs(n.scalar("amplitude")), w = n.scalar("frequency");
         FieldInfo out{weaker(cs[0].kind, Kind::lipschitz), cs[0].lipschitz + a * w, expand(cs[0].bounds, a),
                       "displacement adds amplitude * frequency to the Lipschitz bound"};
         // The child plus a term within [-a, a]: the child's band grows by 2a, its smooth part stays.
         const Perturbation child = cs[0].perturbation_or_plain();
         out.perturbation = Perturbation{child.lipschitz, child.width + 2 * a};
         return out;
       },
       [](Compiler& c, const Node& n) { c.modify(TapeOp::displace, n, c.constants(n.params)); },
       {{"amplitude", {0.08}}, {"frequency", {6}}}},
      {{Op::grid, "grid", 3, 1, 1, 3, {P{"resolution", 1, {64}, 2, 256}, P{"padding", 1, {0.1}, 0}},
        "the child sampled on a regular grid (resolution samples along the longest side of its bounds grown by "
        "padding) and interpolated trilinearly; outside the grid, the value at the nearest grid point plus the "
        "distance to it"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         // Along each axis the interpolant's slope is a weighted mean of sample differences over one cell, each
         // at most the child's L; outside the grid the added distance has slope 1. So |grad| <= sqrt(3) max(L,
         // 1). Interpolation is no bound: between samples it can exceed the distance (by up to sqrt(3)/2 of a
         // cell for an exact child).
         return FieldInfo{weaker(cs[0].kind, Kind::lipschitz), std::sqrt(3.0) * std::max(cs[0].lipschitz, 1.0),
                          grid_layout(n, cs[0].bounds).box(),
                          "trilinear interpolation of samples: each axis's slope at most the child's L, so |grad| <= "
                          "sqrt(3) L"};
       },
       [](Compiler& c, const Node& n) { c.primitive(TapeOp::grid, grid_samples(c, n), n); },
       {{"resolution", {48}}},
       [](const Node& n) {
         if (derive_info(n.children[0]).bounds.is_finite()) return std::string();
         return std::string("/child: a grid needs a child with finite bounds");
       }},
  };
}

}  // namespace marchcheck::sdf::ops
