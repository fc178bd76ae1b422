// The 2D shapes and the operators that make 3D shapes of them (kernels: marchcheck/sdf/kernels/shapes_2d.hpp).
#include "rules.hpp"

#include <algorithm>
#include <cmath>

namespace marchcheck::sdf::ops {

namespace {

using P = ParamSpec;

FieldInfo exact_2d(double lo_x, double lo_y, double hi_x, double hi_y) {
  return {Kind::exact, 1, Box3{{lo_x, lo_y, 0}, {hi_x, hi_y, 0}}, "closed form"};
}

}  // namespace

std::vector<OpRules> shape_2d_rules() {
  return {
      {{Op::circle, "circle", 2, 0, 0, 0, {P{"center", 2, {0, 0}}, P{"radius", 1, {}, kPositive}}, "2D disc"},
       [](const Node& n, auto, double) {
         const double r = n.scalar("radius");
         const auto c = n.param("center");
         return exact_2d(c[0] - r, c[1] - r, c[0] + r, c[1] + r);
       },
       compile_as_given<TapeOp::circle>,
       {{"center", {0.1, 0.2}}, {"radius", {0.25}}}},
      {{Op::rect, "rect", 2, 0, 0, 0, {P{"center", 2, {0, 0}}, P{"half_size", 2, {}, kPositive}}, "2D rectangle"},
       [](const Node& n, auto, double) {
         const auto c = n.param("center"), h = n.param("half_size");
         return exact_2d(c[0] - h[0], c[1] - h[1], c[0] + h[0], c[1] + h[1]);
       },
       compile_as_given<TapeOp::rect>,
       {{"center", {0.1, 0}}, {"half_size", {0.5, 0.4}}}},
      {{Op::segment, "segment", 2, 0, 0, 0, {P{"a", 2, {}}, P{"b", 2, {}}, P{"radius", 1, {0}, 0}},
        "2D segment, thickened by radius"},
       [](const Node& n, auto, double) {
         const auto a = n.param("a"), b = n.param("b");
         const double r = n.scalar("radius");
         return exact_2d(std::min(a[0], b[0]) - r, std::min(a[1], b[1]) - r, std::max(a[0], b[0]) + r,
                         std::max(a[1], b[1]) + r);
       },
       [](Compiler& c, const Node& n) {
         const auto a = n.param("a"), b = n.param("b");
         const double bx = b[0] - a[0], by = b[1] - a[1], len2 = bx * bx + by * by;
         c.primitive(TapeOp::segment, c.constants({a[0], a[1], bx, by, len2 > 0 ? 1 / len2 : 0, n.scalar("radius")}),
                     n);
       },
       {{"a", {-0.5, -0.2}}, {"b", {0.5, 0.3}}, {"radius", {0.15}}}},
      {{Op::revolve, "revolve", 3, 1, 1, 2, {P{"offset", 1, {0}, 0}},
        "a 2D shape (x: distance from the y axis minus offset, y: height) revolved about y"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         const Box3& b = cs[0].bounds;
         const double reach = n.scalar("offset") + std::max(std::abs(b.lo.x), std::abs(b.hi.x));
         return like_child(cs[0], Box3{{-reach, b.lo.y, -reach}, {reach, b.hi.y, reach}},
                           "revolution keeps the 2D shape's kind");
       },
       [](Compiler& c, const Node& n) { c.point_op(TapeOp::p_revolve, c.constants(n.params), n.children[0]); },
       {{"offset", {0.6}}}},
      {{Op::extrude, "extrude", 3, 1, 1, 2, {P{"half_depth", 1, {}, kPositive}}, "a 2D shape in xy extruded along z"},
       [](const Node& n, std::span<const FieldInfo> cs, double) {
         const Box3& b = cs[0].bounds;
         const double h = n.scalar("half_depth");
         return like_child(cs[0], Box3{{b.lo.x, b.lo.y, -h}, {b.hi.x, b.hi.y, h}},
                           "extrusion keeps the 2D shape's kind");
       },
       [](Compiler& c, const Node& n) { c.modify(TapeOp::extrude, n, c.constants(n.params)); },
       {{"half_depth", {0.3}}}},
  };
}

}  // namespace marchcheck::sdf::ops
