// Combinations of shapes: union, intersection, subtraction and their smooth forms (kernels:
// marchcheck/sdf/kernels/combinations.hpp).
#include "rules.hpp"

namespace marchcheck::sdf::ops {

namespace {

using P = ParamSpec;

enum class Bounds { hull, overlap, first };

// min/max-like operators keep 1-Lipschitz fields 1-Lipschitz with the combined zero set, so exact and bound
// children give a bound; a child with only a Lipschitz bound gives only that. The smooth forms, smin = w a +
// (1 - w) b with w in [0,1] along the blend, are still max(L)-Lipschitz. Each is monotone in every child and moves
// by c where all children do, so children within lipschitz |q - p| + width of themselves give a field within the
// largest of each: a perturbation is kept where any child declares one.
FieldInfo combined(const Node& n, std::span<const FieldInfo> cs, Bounds bounds) {
  FieldInfo out;
  out.kind = Kind::bound;
  out.lipschitz = 0;
  out.bounds = cs.front().bounds;
  Perturbation perturbation{0, 0};
  bool declared = false;
  for (const auto& c : cs) {
    out.kind = weaker(out.kind, c.kind);
    out.lipschitz = std::max(out.lipschitz, c.lipschitz);
    const Perturbation p = c.perturbation_or_plain();
    perturbation = {std::max(perturbation.lipschitz, p.lipschitz), std::max(perturbation.width, p.width)};
    declared = declared || c.perturbation;
    if (bounds == Bounds::hull)
      out.bounds = {glm::min(out.bounds.lo, c.bounds.lo), glm::max(out.bounds.hi, c.bounds.hi)};
    if (bounds == Bounds::overlap)
      out.bounds = {glm::max(out.bounds.lo, c.bounds.lo), glm::min(out.bounds.hi, c.bounds.hi)};
  }
  if (declared) out.perturbation = perturbation;
  const std::string what(op_info(n.op).name);
  out.reason = out.kind >= Kind::lipschitz
                   ? what + " of an " + std::string(to_string(out.kind)) + " field"
                   : what + " of exact/bound fields: a bound (exact only on parts of the surface)";
  return out;
}

template <Bounds B>
FieldInfo derive_combined(const Node& n, std::span<const FieldInfo> cs, double) {
  return combined(n, cs, B);
}

}  // namespace

std::vector<OpRules> combination_rules() {
  return {
      {{Op::union_, "union", 3, 1, -1, 3, {}, "min of the children"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         return cs.size() == 1 ? cs[0] : combined(n, cs, Bounds::hull);
       },
       [](Compiler& c, const Node& n) { c.fold(TapeOp::min_, n); },
       {}},
      {{Op::intersection, "intersection", 3, 2, -1, 3, {}, "max of the children"},
       derive_combined<Bounds::overlap>,
       [](Compiler& c, const Node& n) { c.fold(TapeOp::max_, n); },
       {}},
      {{Op::subtraction, "subtraction", 3, 2, 2, 3, {}, "first child minus the second: max(a, -b)"},
       derive_combined<Bounds::first>,
       [](Compiler& c, const Node& n) { c.fold(TapeOp::subtract, n); },
       {}},
      {{Op::smooth_union, "smooth_union", 3, 1, -1, 3, {P{"k", 1, {}, kPositive}}, "polynomial smooth min"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         FieldInfo out = combined(n, cs, Bounds::hull);
         out.bounds = expand(out.bounds, n.scalar("k") / 4);  // it adds up to k/4 of material between children
         return out;
       },
       [](Compiler& c, const Node& n) { c.fold(TapeOp::smooth_min, n, c.constants(n.params)); },
       {{"k", {0.3}}}},
      {{Op::smooth_intersection, "smooth_intersection", 3, 2, -1, 3, {P{"k", 1, {}, kPositive}},
        "polynomial smooth max"},
       derive_combined<Bounds::overlap>,
       [](Compiler& c, const Node& n) { c.fold(TapeOp::smooth_max, n, c.constants(n.params)); },
       {{"k", {0.3}}}},
      {{Op::smooth_subtraction, "smooth_subtraction", 3, 2, 2, 3, {P{"k", 1, {}, kPositive}},
        "polynomial smooth max(a, -b)"},
       derive_combined<Bounds::first>,
       [](Compiler& c, const Node& n) { c.fold(TapeOp::smooth_subtract, n, c.constants(n.params)); },
       {{"k", {0.2}}}},
  };
}

}  // namespace marchcheck::sdf::ops
