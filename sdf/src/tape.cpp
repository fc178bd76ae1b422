#include "marchcheck/sdf/tape.hpp"

#include <cmath>
#include <numbers>

namespace marchcheck::sdf {

namespace {

constexpr double kDegree = std::numbers::pi / 180;

struct Compiler {
  Tape tape;
  double time;
  int values = 0, points = 1;

  std::uint32_t push_constants(std::initializer_list<double> list) {
    const auto offset = static_cast<std::uint32_t>(tape.constants.size());
    tape.constants.insert(tape.constants.end(), list.begin(), list.end());
    return offset;
  }
  std::uint32_t push_constants(std::span<const double> list) {
    const auto offset = static_cast<std::uint32_t>(tape.constants.size());
    tape.constants.insert(tape.constants.end(), list.begin(), list.end());
    return offset;
  }
  void emit(TapeOp op, std::uint32_t arg = 0, int material = -1) { tape.code.push_back({op, arg, material}); }

  void value_pushed() {
    ++values;
    tape.value_depth = std::max(tape.value_depth, values);
    if (values > kMaxValueStack) throw CompileError("scene needs more than 32 intermediate values: nest less deeply");
  }
  void point_op(TapeOp op, std::uint32_t arg, const Node& child) {
    emit(op, arg);
    ++points;
    tape.point_depth = std::max(tape.point_depth, points);
    if (points > kMaxPointStack) throw CompileError("scene nests more than 31 domain operators");
    node(child);
    emit(TapeOp::p_pop);
    --points;
  }
  void combine(TapeOp op, const Node& n, std::uint32_t arg = 0) {
    node(n.children[0]);
    for (size_t i = 1; i < n.children.size(); ++i) {
      node(n.children[i]);
      emit(op, arg);
      --values;
    }
  }

  void primitive(TapeOp op, std::uint32_t arg, int material) {
    emit(op, arg, material);
    value_pushed();
  }

  // The child evaluated in double at every grid point, once, here.
  std::uint32_t sample_grid(const Node& n) {
    const GridLayout g = grid_layout(n, derive_info(n.children[0], time).bounds);
    const Tape child = compile(n.children[0], time);
    const auto offset = push_constants({static_cast<double>(g.count.x), static_cast<double>(g.count.y),
                                        static_cast<double>(g.count.z), g.lo.x, g.lo.y, g.lo.z, g.cell});
    for (int z = 0; z < g.count.z; ++z)
      for (int y = 0; y < g.count.y; ++y)
        for (int x = 0; x < g.count.x; ++x)
          tape.constants.push_back(evaluate(child, g.lo + glm::dvec3(x, y, z) * g.cell));
    return offset;
  }

  void node(const Node& n) {
    const int mat = n.material;
    switch (n.op) {
      case Op::sphere: primitive(TapeOp::sphere, push_constants(n.params), mat); return;
      case Op::plane: {
        const glm::dvec3 nn = glm::normalize(n.vec3("normal"));
        primitive(TapeOp::plane, push_constants({nn.x, nn.y, nn.z, n.scalar("offset")}), mat);
        return;
      }
      case Op::box: primitive(TapeOp::box, push_constants(n.params), mat); return;
      case Op::round_box: primitive(TapeOp::round_box, push_constants(n.params), mat); return;
      case Op::box_frame: primitive(TapeOp::box_frame, push_constants(n.params), mat); return;
      case Op::torus: primitive(TapeOp::torus, push_constants(n.params), mat); return;
      case Op::capped_torus: {
        const double ang = n.scalar("angle_deg") * kDegree;
        primitive(TapeOp::capped_torus,
                  push_constants({std::sin(ang), std::cos(ang), n.scalar("major"), n.scalar("minor")}), mat);
        return;
      }
      case Op::capsule: {
        const glm::dvec3 a = n.vec3("a"), ba = n.vec3("b") - a;
        const double len2 = glm::dot(ba, ba);
        primitive(TapeOp::capsule,
                  push_constants({a.x, a.y, a.z, ba.x, ba.y, ba.z, len2 > 0 ? 1 / len2 : 0, n.scalar("radius")}), mat);
        return;
      }
      case Op::capped_cylinder: primitive(TapeOp::capped_cylinder, push_constants(n.params), mat); return;
      case Op::cone: {
        const double h = n.scalar("height");
        primitive(TapeOp::cone, push_constants({h * std::tan(n.scalar("angle_deg") * kDegree), -h}), mat);
        return;
      }
      case Op::ellipsoid: primitive(TapeOp::ellipsoid, push_constants(n.params), mat); return;
      case Op::octahedron: primitive(TapeOp::octahedron, push_constants(n.params), mat); return;
      case Op::octahedron_bound: primitive(TapeOp::octahedron_bound, push_constants(n.params), mat); return;
      case Op::heightfield: {
        const auto offset = push_constants({static_cast<double>(n.params.size() / 2)});
        push_constants(n.params);
        primitive(TapeOp::heightfield, offset, mat);
        return;
      }
      case Op::mandelbulb: primitive(TapeOp::mandelbulb, push_constants(n.params), mat); return;
      case Op::mesh:
        tape.meshes.push_back(n.mesh);
        primitive(TapeOp::mesh, static_cast<std::uint32_t>(tape.meshes.size() - 1), mat);
        return;
      case Op::grid: primitive(TapeOp::grid, sample_grid(n), mat); return;
      case Op::circle: primitive(TapeOp::circle, push_constants(n.params), mat); return;
      case Op::rect: primitive(TapeOp::rect, push_constants(n.params), mat); return;
      case Op::segment: {
        const auto a = n.param("a"), b = n.param("b");
        const double bx = b[0] - a[0], by = b[1] - a[1], len2 = bx * bx + by * by;
        primitive(TapeOp::segment, push_constants({a[0], a[1], bx, by, len2 > 0 ? 1 / len2 : 0, n.scalar("radius")}),
                  mat);
        return;
      }
      default: break;
    }
    switch (n.op) {
      case Op::revolve: point_op(TapeOp::p_revolve, push_constants(n.params), n.children[0]); break;
      case Op::extrude:
        node(n.children[0]);
        emit(TapeOp::extrude, push_constants(n.params));
        break;
      case Op::union_: combine(TapeOp::min, n); break;
      case Op::intersection: combine(TapeOp::max, n); break;
      case Op::subtraction: combine(TapeOp::subtract, n); break;
      case Op::smooth_union: combine(TapeOp::smooth_min, n, push_constants(n.params)); break;
      case Op::smooth_intersection: combine(TapeOp::smooth_max, n, push_constants(n.params)); break;
      case Op::smooth_subtraction: combine(TapeOp::smooth_subtract, n, push_constants(n.params)); break;
      case Op::round:
        node(n.children[0]);
        emit(TapeOp::round, push_constants(n.params));
        break;
      case Op::onion:
        node(n.children[0]);
        emit(TapeOp::onion, push_constants(n.params));
        break;
      case Op::displace:
        node(n.children[0]);
        emit(TapeOp::displace, push_constants(n.params));
        break;
      case Op::translate: point_op(TapeOp::p_translate, push_constants(n.params), n.children[0]); break;
      case Op::rotate:
      case Op::affine:
      case Op::animate: {
        ModelTransform m;
        if (n.op == Op::rotate) {
          m = {rotation_matrix(n.vec3("axis"), n.scalar("angle_deg") * kDegree), {}};
        } else {
          m = model_transform(n, time);
        }
        const glm::dmat3 inv = glm::inverse(m.a);
        const glm::dvec3 it = -(inv * m.t);
        // glm is column-major: inv[col][row]; the tape stores rows.
        point_op(TapeOp::p_affine,
                 push_constants({inv[0][0], inv[1][0], inv[2][0], it.x, inv[0][1], inv[1][1], inv[2][1], it.y,
                                 inv[0][2], inv[1][2], inv[2][2], it.z}),
                 n.children[0]);
        break;
      }
      case Op::scale: {
        const double s = n.scalar("factor");
        point_op(TapeOp::p_scale, push_constants({1 / s}), n.children[0]);
        emit(TapeOp::scale_value, push_constants({s}));
        break;
      }
      case Op::repeat: point_op(TapeOp::p_repeat, push_constants(n.params), n.children[0]); break;
      case Op::repeat_limited: point_op(TapeOp::p_repeat_limited, push_constants(n.params), n.children[0]); break;
      case Op::mirror: point_op(TapeOp::p_mirror, push_constants(n.params), n.children[0]); break;
      case Op::twist: point_op(TapeOp::p_twist, push_constants(n.params), n.children[0]); break;
      case Op::warp: {
        const double amp = n.scalar("amplitude"), f = n.scalar("frequency");
        const auto r = n.param("rates");
        point_op(TapeOp::p_warp,
                 push_constants({amp * std::sin(r[1] * time), f * std::sin(r[0] * time), amp * std::sin(r[3] * time),
                                 f * std::sin(r[2] * time), n.scalar("offset_z")}),
                 n.children[0]);
        break;
      }
      default: throw CompileError("internal: operator without a compiler rule");
    }
    if (mat >= 0) emit(TapeOp::set_material, 0, mat);
  }
};

}  // namespace

Tape compile(const Node& root, double time) {
  if (auto error = validate_tree(root); !error.empty()) throw CompileError(error);
  Compiler c{{}, time};
  c.node(root);
  c.tape.constants_f.assign(c.tape.constants.begin(), c.tape.constants.end());  // each rounded to float
  return std::move(c.tape);
}

}  // namespace marchcheck::sdf
