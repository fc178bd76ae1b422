#include "marchcheck/sdf/node.hpp"

#include "marchcheck/meshes/io.hpp"
#include "marchcheck/sdf/mesh_distance.hpp"

#include "ops/rules.hpp"

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

const OpInfo& op_info(Op op) { return ops::rules(op).info; }

const OpInfo* find_op(std::string_view name) {
  for (size_t i = 0; i < static_cast<size_t>(Op::count_); ++i)
    if (const auto& info = op_info(static_cast<Op>(i)); info.name == name) return &info;
  return nullptr;
}

std::vector<Op> all_ops() {
  std::vector<Op> out;
  for (size_t i = 0; i < static_cast<size_t>(Op::count_); ++i) out.push_back(static_cast<Op>(i));
  return out;
}

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
  std::vector<FieldInfo> children;
  for (const auto& child : node.children) children.push_back(derive_info(child, time));
  return ops::rules(node.op).derive(node, children, time);
}

std::vector<Box3> bounding_boxes(const Node& node, double time, size_t max_boxes) {
  if (node.op != Op::union_) return {derive_info(node, time).bounds};
  std::vector<Box3> boxes;
  for (const auto& child : node.children) {
    const std::vector<Box3> own = bounding_boxes(child, time, max_boxes);
    boxes.insert(boxes.end(), own.begin(), own.end());
  }
  if (boxes.size() <= max_boxes) return boxes;
  // The union's derived bounds: the hull of its children's.
  Box3 hull = boxes.front();
  for (const Box3& b : boxes) hull = {glm::min(hull.lo, b.lo), glm::max(hull.hi, b.hi)};
  return {hull};
}

Node example(Op op) {
  const ops::OpRules& r = ops::rules(op);
  Node n = make(op, r.example);
  const int count = r.info.max_children < 0 ? std::max(r.info.min_children, 2) : r.info.max_children;
  if (r.example_children) n.children = r.example_children();
  for (int i = 0; i < count && !r.example_children; ++i) {
    if (r.info.child_dimension == 2) {
      n.children.push_back(make(Op::circle, {{"center", {0.1 + 0.3 * i, 0.2}}, {"radius", {0.25}}}));
    } else {
      // A shape without symmetries first (so twists and rotations show), then one overlapping it.
      n.children.push_back(i == 0 ? translate({0.2, 0.1, 0}, box({0.5, 0.4, 0.3})) : sphere(0.6));
    }
  }
  if (r.example_attach) r.example_attach(n);
  return n;
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
  if (const auto check = ops::rules(node.op).check; check && error.empty())
    if (const std::string problem = check(node); !problem.empty()) error = path + problem;
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
