#include "rules.hpp"

#include <cstdio>
#include <cstdlib>

namespace marchcheck::sdf::ops {

namespace {

// Every family's rows, indexed by Op; an operator without exactly one row is a programming error, caught at
// the first use (and by the test that runs every operator).
std::vector<OpRules> build_table() {
  std::vector<OpRules> all;
  for (auto family : {primitive_rules, shape_2d_rules, combination_rules, modifier_rules, domain_rules})
    for (auto& row : family()) all.push_back(std::move(row));
  std::sort(all.begin(), all.end(), [](const OpRules& a, const OpRules& b) { return a.info.op < b.info.op; });
  for (size_t i = 0; i < static_cast<size_t>(Op::count_); ++i)
    if (i >= all.size() || static_cast<size_t>(all[i].info.op) != i ||
        (i + 1 < all.size() && all[i + 1].info.op == all[i].info.op)) {
      std::fprintf(stderr, "marchcheck: operator %zu has no rules or more than one row\n", i);
      std::abort();
    }
  return all;
}

}  // namespace

const OpRules& rules(Op op) {
  static const std::vector<OpRules> table = build_table();
  return table[static_cast<size_t>(op)];
}

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

FieldInfo like_child(const FieldInfo& child, Box3 bounds, const char* reason) {
  FieldInfo out = child;
  out.bounds = bounds;
  out.reason = reason;
  return out;
}

}  // namespace marchcheck::sdf::ops
