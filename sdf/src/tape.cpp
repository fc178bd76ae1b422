#include "marchcheck/sdf/tape.hpp"

#include "marchcheck/sdf/scene.hpp"
#include "ops/rules.hpp"

namespace marchcheck::sdf {

namespace ops {

void Compiler::node(const Node& n) {
  rules(n.op).compile(*this, n);
  // A primitive's instruction carries its material; any other node's value takes it after.
  if (!material_set_ && n.material >= 0) emit(TapeOp::set_material, 0, n.material);
  material_set_ = false;
}

std::uint32_t Compiler::constants(std::span<const double> values) {
  const auto offset = static_cast<std::uint32_t>(tape_.constants.size());
  tape_.constants.insert(tape_.constants.end(), values.begin(), values.end());
  return offset;
}

void Compiler::primitive(TapeOp op, std::uint32_t arg, const Node& n) {
  emit(op, arg, n.material);
  value_pushed();
  material_set_ = true;
}

std::uint32_t Compiler::mesh(std::shared_ptr<const MeshDistance> mesh) {
  tape_.meshes.push_back(std::move(mesh));
  return static_cast<std::uint32_t>(tape_.meshes.size() - 1);
}

std::uint32_t Compiler::glsl(std::shared_ptr<const GlslField> field) {
  tape_.glsl_fields.push_back(std::move(field));
  return static_cast<std::uint32_t>(tape_.glsl_fields.size() - 1);
}

void Compiler::value_pushed() {
  ++values_;
  tape_.value_depth = std::max(tape_.value_depth, values_);
  if (values_ > kMaxValueStack) throw CompileError("scene needs more than 32 intermediate values: nest less deeply");
}

void Compiler::point_op(TapeOp op, std::uint32_t arg, const Node& child) {
  emit(op, arg);
  ++points_;
  tape_.point_depth = std::max(tape_.point_depth, points_);
  if (points_ > kMaxPointStack) throw CompileError("scene nests more than 31 domain operators");
  node(child);
  emit(TapeOp::p_pop);
  --points_;
}

void Compiler::fold(TapeOp op, const Node& n, std::uint32_t arg) {
  node(n.children[0]);
  for (size_t i = 1; i < n.children.size(); ++i) {
    node(n.children[i]);
    emit(op, arg);
    --values_;
  }
}

void Compiler::modify(TapeOp op, const Node& n, std::uint32_t arg) {
  node(n.children[0]);
  emit(op, arg);
}

Tape Compiler::finish() {
  tape_.constants_f.assign(tape_.constants.begin(), tape_.constants.end());  // each rounded to float
  return std::move(tape_);
}

}  // namespace ops

Tape compile(const Node& root, double time) {
  if (auto error = validate_tree(root); !error.empty()) throw CompileError(error);
  ops::Compiler c(time);
  c.node(root);
  return c.finish();
}

Tape compile(const Scene& scene) { return compile(scene, scene.root); }

Tape compile(const Scene& scene, const Node& root) {
  Tape tape = compile(root, scene.time);
  tape.half = scene.march.precision == Precision::float16;
  return tape;
}

}  // namespace marchcheck::sdf
