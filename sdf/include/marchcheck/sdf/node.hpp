// The distance-field language: a tree of primitives and operators, each with a declared distance kind.
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace marchcheck::sdf {

enum class Op : unsigned char {
  // 3D primitives
  sphere,
  plane,
  box,
  round_box,
  box_frame,
  torus,
  capped_torus,
  capsule,
  capped_cylinder,
  cone,
  ellipsoid,
  octahedron,
  octahedron_bound,
  heightfield,
  mandelbulb,
  mesh,
  glsl,  // a field written in GLSL (marchcheck/sdf/glsl_field.hpp)
  // 2D shapes (children of revolve and extrude)
  circle,
  rect,
  segment,
  // shapes from 2D
  revolve,
  extrude,
  // combinations
  union_,
  intersection,
  subtraction,
  smooth_union,
  smooth_intersection,
  smooth_subtraction,
  // modifiers of the distance
  round,
  onion,
  displace,
  grid,
  // domain operators
  translate,
  rotate,
  scale,
  affine,
  animate,
  repeat,
  repeat_limited,
  mirror,
  twist,
  warp,
  count_
};

// What |f| is with respect to the Euclidean distance to the zero set.
enum class Kind : unsigned char {
  exact,     // |f| equals the distance
  bound,     // |f| never exceeds the distance
  lipschitz,  // neither, but Lipschitz with a known constant L: only f/L is safe to step by
  estimate    // no distance property and no Lipschitz constant (a fractal's escape-time distance estimate):
              // its FieldInfo::lipschitz is the divisor it is stepped by, a heuristic that only validation
              // against the set's own definition can judge
};

std::string_view to_string(Kind kind);

struct ParamSpec {
  std::string_view name;
  int size;  // number of values; 0 = any number of pairs
  std::vector<double> fallback;  // empty = required
  double min = -1e300;           // allowed range for every component
  double max = 1e300;
};

struct OpInfo {
  Op op;
  std::string_view name;
  int dimension;     // 3 or 2: the space its value lives in
  int min_children;  // 0 for primitives
  int max_children;  // -1 = any number
  int child_dimension;
  std::vector<ParamSpec> params;
  std::string_view summary;
};

// Each operator's rules live in one row of its family's file (sdf/src/ops/), its kernels in one family header
// (marchcheck/sdf/kernels/).
const OpInfo& op_info(Op op);
// nullptr when no operator has this name.
const OpInfo* find_op(std::string_view name);
std::vector<Op> all_ops();

class MeshDistance;
class GlslField;

struct Node {
  Op op = Op::sphere;
  std::vector<double> params;  // the OpInfo's params, flattened in order
  std::vector<Node> children;
  int material = -1;  // index into the scene's materials; -1 = inherit from the children
  // Mesh nodes: where the triangles come from (a file path, or a generator such as "procedural:icosphere(1,4)"),
  // and, once a mesh loader has read it, the triangles with their distance structure (immutable, shared by copies).
  std::string source;
  std::shared_ptr<const MeshDistance> mesh;
  // Glsl nodes: the compiled field, with what the node says of it (its source, function, uniforms, kind).
  std::shared_ptr<const GlslField> glsl;

  // The values of the named parameter (aborts on a name the op does not have: a programming error).
  std::span<const double> param(std::string_view name) const;
  double scalar(std::string_view name) const { return param(name)[0]; }
  glm::dvec3 vec3(std::string_view name) const;
};

// Builds a node with every parameter at its default, then the given ones.
Node make(Op op, std::vector<std::pair<std::string_view, std::vector<double>>> values = {},
          std::vector<Node> children = {}, int material = -1);

// Builders that read like the GLSL people write.
Node sphere(double radius, int material = -1);
Node plane(glm::dvec3 normal, double offset, int material = -1);
Node box(glm::dvec3 half_size, int material = -1);
Node torus(double major, double minor, int material = -1);
Node translate(glm::dvec3 offset, Node child);
Node unite(std::vector<Node> children);
Node intersect(Node a, Node b);
Node subtract(Node a, Node b);
Node smooth_union(double k, std::vector<Node> children);
// A mesh node for the given source, its triangles not yet loaded (see load_meshes in scene_file.hpp).
Node mesh(std::string source, int material = -1);

struct Box3 {
  glm::dvec3 lo{-INFINITY};
  glm::dvec3 hi{INFINITY};
  bool is_finite() const;
  glm::dvec3 center() const { return (lo + hi) * 0.5; }
  glm::dvec3 size() const { return hi - lo; }
};

// A field that is a smooth one plus a perturbation within a band `width` wide (a height field's noise, a
// displacement): f(q) >= f(p) - lipschitz |q - p| - width for all p and q, where lipschitz bounds only the smooth
// part. Far from the surface a march may step (f - width) / lipschitz, longer than f / L. Every field of Lipschitz
// bound L is one with {L, 0}.
struct Perturbation {
  double lipschitz = 1;
  double width = 0;
};

// What a field declares about itself, derived bottom-up from its tree.
struct FieldInfo {
  FieldInfo() = default;
  FieldInfo(Kind k, double l, Box3 b, std::string why) : kind(k), lipschitz(l), bounds(b), reason(std::move(why)) {}
  Kind kind = Kind::exact;
  double lipschitz = 1.0;  // bound on |grad f|
  Box3 bounds;             // encloses the zero set (and f <= 0 region); infinite when unknown
  std::string reason;      // why the kind is what it is, for reports
  // Declared by height fields and displacements; kept by the operators that keep the property (min/max and their
  // smooth forms, motions, offsets, shells, mirrors); dropped by the rest.
  std::optional<Perturbation> perturbation;
  // The declared perturbation, else {L, 0}.
  Perturbation perturbation_or_plain() const { return perturbation.value_or(Perturbation{lipschitz, 0}); }
};

glm::dmat3 rotation_matrix(glm::dvec3 axis, double angle_rad);

// The model matrix x -> a x + t of an affine or animate node at the given time.
struct ModelTransform {
  glm::dmat3 a;
  glm::dvec3 t;
};
ModelTransform model_transform(const Node& node, double time);

// The samples of a grid node: count[i] of them along axis i, cell apart, from lo; centred on the child's bounds.
struct GridLayout {
  glm::dvec3 lo;
  double cell;
  glm::ivec3 count;
  Box3 box() const { return {lo, lo + glm::dvec3(count - 1) * cell}; }
};
GridLayout grid_layout(const Node& grid, const Box3& child_bounds);

// time feeds the animated operators (animate, warp).
FieldInfo derive_info(const Node& node, double time = 0.0);
// Boxes whose union holds the field's zero set and inside, at most max_boxes of them: a union's children's (in turn
// their own), else the node's derived bounds; where there would be more, the hull of them all. Tighter than the
// hull alone: a sphere over a ground leaves the air between them out.
std::vector<Box3> bounding_boxes(const Node& node, double time, size_t max_boxes);

// A valid instance of the operator, for documentation and for tests that run every operator: its example
// parameters, and children when it takes them (a box off the origin, then a sphere; circles for 2D children).
// A mesh example comes loaded.
Node example(Op op);

// Checks shape (children counts and dimensions, parameter sizes and ranges); returns "" when valid,
// otherwise a message naming the path (e.g. "/children/1/radius") and the problem.
std::string validate_tree(const Node& node);

}  // namespace marchcheck::sdf
