// Each operator's rules, in one row of its family's file (primitives, shapes_2d, combinations, modifiers,
// domain): its description and parameters, what it declares about its field (kind, Lipschitz constant,
// bounds), how it compiles to tape instructions (whose kernels live in marchcheck/sdf/kernels/, by family),
// any check beyond its parameters' ranges, and an example for documentation and for the test that runs every
// operator through every evaluator.
#pragma once

#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <algorithm>
#include <initializer_list>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace marchcheck::sdf::ops {

class Compiler;

struct OpRules {
  OpInfo info;
  // children: the children's infos, derived first. time feeds the animated operators.
  FieldInfo (*derive)(const Node& node, std::span<const FieldInfo> children, double time);
  void (*compile)(Compiler& c, const Node& node);
  // The values of the parameters without a default, for example(); its children are example_children's.
  std::vector<std::pair<std::string_view, std::vector<double>>> example;
  // "" when the node is valid beyond its shape and ranges, else the problem, after its path and ": ".
  std::string (*check)(const Node& node) = nullptr;
  void (*example_attach)(Node& n) = nullptr;  // what a mesh or glsl example loads
  std::vector<Node> (*example_children)() = nullptr;  // instead of the usual ones
};

std::vector<OpRules> primitive_rules();
std::vector<OpRules> shape_2d_rules();
std::vector<OpRules> combination_rules();
std::vector<OpRules> modifier_rules();
std::vector<OpRules> domain_rules();

// The rules of every operator, indexed by Op.
const OpRules& rules(Op op);

// Compiles a tree to a tape; the operators' compile rules call back into it for their children.
class Compiler {
 public:
  explicit Compiler(double time) : time_(time) {}
  double time() const { return time_; }
  Tape finish();

  void node(const Node& n);
  std::uint32_t constants(std::initializer_list<double> values) {
    return constants(std::span(values.begin(), values.size()));
  }
  std::uint32_t constants(std::span<const double> values);
  // A primitive's instruction: pushes a value that carries the node's material.
  void primitive(TapeOp op, std::uint32_t arg, const Node& n);
  std::uint32_t mesh(std::shared_ptr<const MeshDistance> mesh);
  std::uint32_t glsl(std::shared_ptr<const GlslField> field);
  // The child evaluated at the point the instruction pushes, then that point popped.
  void point_op(TapeOp op, std::uint32_t arg, const Node& child);
  // The children folded left by a binary instruction.
  void fold(TapeOp op, const Node& n, std::uint32_t arg = 0);
  // The only child, then an instruction that changes its value.
  void modify(TapeOp op, const Node& n, std::uint32_t arg);
  void emit(TapeOp op, std::uint32_t arg = 0, int material = -1) { tape_.code.push_back({op, arg, material}); }

 private:
  void value_pushed();
  Tape tape_;
  double time_;
  int values_ = 0, points_ = 1;
  bool material_set_ = false;  // the last node's value already carries its material
};

// Bounds arithmetic for the derive rules.
inline Box3 symmetric_box(glm::dvec3 half) { return {-half, half}; }
inline Box3 expand(Box3 b, double r) { return {b.lo - r, b.hi + r}; }
Box3 transform_box(const Box3& b, const glm::dmat3& a, glm::dvec3 t);  // the image of b under x -> A x + t
inline Kind weaker(Kind a, Kind b) { return std::max(a, b); }
// The child's info with new bounds and reason; its perturbation too, which motions, offsets and shells (|f| - t)
// keep: they move f(q) - f(p) by no more than |q - p| does.
FieldInfo like_child(const FieldInfo& child, Box3 bounds, const char* reason);

inline constexpr double kPositive = 1e-12;  // the least value of parameters that must be positive
inline constexpr double kDegree = std::numbers::pi / 180;

// The compile rule of a primitive whose constants are its parameters as given.
template <TapeOp Instruction>
void compile_as_given(Compiler& c, const Node& n) {
  c.primitive(Instruction, c.constants(n.params), n);
}

}  // namespace marchcheck::sdf::ops
