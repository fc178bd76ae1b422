// The evaluator of a GLSL field's decoded SPIR-V, in float, double and Dual: every operation as GLSL defines
// it, in the scalar's own precision (float as a GPU computes it, no contraction: -ffp-contract=off).
#include "marchcheck/sdf/glsl_field.hpp"

#include "program.hpp"

#include "marchcheck/sdf/half.hpp"
#include "marchcheck/sdf/lipschitz.hpp"

#include <spirv/unified1/GLSL.std.450.h>
#include <spirv/unified1/spirv.hpp>

#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace marchcheck::sdf {

std::size_t GlslField::instructions() const { return program_->code.size(); }

namespace glsl {

namespace {

template <class T>
using Value = decltype(value_of(T{}));

// f(x) with the chain rule for Dual: df is the derivative at the value.
template <class T, class F, class D>
T chain(T x, F f, D df) {
  if constexpr (is_dual<T>::value) {
    return T(f(x.v), x.d * df(x.v));
  } else {
    return f(x);
  }
}

template <class T>
T constant(double v) {
  return T(static_cast<Value<T>>(v));
}

template <class T>
T floor_of(T x) {
  return chain(x, [](auto v) { return vmath::floor(v); }, [](auto) { return decltype(value_of(T{}))(0); });
}

// ln 2 in S (binary16: float's, rounded).
template <class S>
constexpr S ln2() {
  if constexpr (std::is_floating_point_v<S>) {
    return std::numbers::ln2_v<S>;
  } else {
    return S(std::numbers::ln2_v<float>);
  }
}

template <class T>
T f_unary(std::uint16_t which, T x) {
  using S = Value<T>;
  switch (which) {
    case spv::OpFNegate: return -x;
    case GLSLstd450Round: return chain(x, [](S v) { return std::round(v); }, [](S) { return S(0); });
    case GLSLstd450RoundEven: return chain(x, [](S v) { return std::nearbyint(v); }, [](S) { return S(0); });
    case GLSLstd450Trunc: return chain(x, [](S v) { return std::trunc(v); }, [](S) { return S(0); });
    case GLSLstd450FAbs: return chain(x, [](S v) { return std::abs(v); }, [](S v) { return v < 0 ? S(-1) : S(1); });
    case GLSLstd450FSign:
      return chain(x, [](S v) { return v > 0 ? S(1) : v < 0 ? S(-1) : S(0); }, [](S) { return S(0); });
    case GLSLstd450Floor: return floor_of(x);
    case GLSLstd450Ceil: return chain(x, [](S v) { return std::ceil(v); }, [](S) { return S(0); });
    case GLSLstd450Fract: return x - floor_of(x);
    case GLSLstd450Radians: return x * constant<T>(std::numbers::pi / 180);
    case GLSLstd450Degrees: return x * constant<T>(180 / std::numbers::pi);
    case GLSLstd450Sin: return chain(x, [](S v) { return vmath::sin(v); }, [](S v) { return vmath::cos(v); });
    case GLSLstd450Cos: return chain(x, [](S v) { return vmath::cos(v); }, [](S v) { return -vmath::sin(v); });
    case GLSLstd450Tan:
      return chain(x, [](S v) { return std::tan(v); }, [](S v) { return 1 / (vmath::cos(v) * vmath::cos(v)); });
    case GLSLstd450Asin:
      return chain(x, [](S v) { return std::asin(v); }, [](S v) { return 1 / std::sqrt(1 - v * v); });
    case GLSLstd450Acos:
      return chain(x, [](S v) { return vmath::acos(v); }, [](S v) { return -1 / std::sqrt(1 - v * v); });
    case GLSLstd450Atan: return chain(x, [](S v) { return vmath::atan(v); }, [](S v) { return 1 / (1 + v * v); });
    case GLSLstd450Sinh: return chain(x, [](S v) { return std::sinh(v); }, [](S v) { return std::cosh(v); });
    case GLSLstd450Cosh: return chain(x, [](S v) { return std::cosh(v); }, [](S v) { return std::sinh(v); });
    case GLSLstd450Tanh:
      return chain(x, [](S v) { return std::tanh(v); }, [](S v) { return 1 - std::tanh(v) * std::tanh(v); });
    case GLSLstd450Exp: return chain(x, [](S v) { return vmath::exp(v); }, [](S v) { return vmath::exp(v); });
    case GLSLstd450Log: return chain(x, [](S v) { return vmath::log(v); }, [](S v) { return 1 / v; });
    case GLSLstd450Exp2:
      return chain(x, [](S v) { return std::exp2(v); }, [](S v) { return std::exp2(v) * ln2<S>(); });
    case GLSLstd450Log2: return chain(x, [](S v) { return std::log2(v); }, [](S v) { return 1 / (v * ln2<S>()); });
    case GLSLstd450Sqrt:  // the derivative at 0 is infinite: 0 keeps a gradient through a kink finite
      return chain(x, [](S v) { return std::sqrt(v); }, [](S v) { return v > 0 ? S(0.5) / std::sqrt(v) : S(0); });
    case GLSLstd450InverseSqrt:
      return chain(x, [](S v) { return 1 / std::sqrt(v); }, [](S v) { return S(-0.5) / (v * std::sqrt(v)); });
    default: return constant<T>(std::numeric_limits<double>::quiet_NaN());
  }
}

template <class T>
T pick_min(T a, T b) {
  return value_of(b) < value_of(a) ? b : a;
}
template <class T>
T pick_max(T a, T b) {
  return value_of(a) < value_of(b) ? b : a;
}

template <class T>
T f_binary(std::uint16_t which, T x, T y) {
  using S = Value<T>;
  switch (which) {
    case spv::OpFAdd: return x + y;
    case spv::OpFSub: return x - y;
    case spv::OpFMul: return x * y;
    case spv::OpFDiv: return x / y;
    case spv::OpFMod: return x - y * floor_of(x / y);  // GLSL's mod
    case spv::OpFRem: return x - y * chain(x / y, [](S v) { return std::trunc(v); }, [](S) { return S(0); });
    case GLSLstd450Atan2:
      if constexpr (is_dual<T>::value) {
        return T(vmath::atan2(x.v, y.v), (x.d * y.v - y.d * x.v) / (x.v * x.v + y.v * y.v));
      } else {
        return vmath::atan2(x, y);
      }
    case GLSLstd450Pow:
      if constexpr (is_dual<T>::value) {
        const S v = vmath::pow(x.v, y.v);
        const S log_x = x.v > 0 ? vmath::log(x.v) : S(0);
        return T(v, x.d * (y.v * vmath::pow(x.v, y.v - 1)) + y.d * (log_x * v));
      } else {
        return vmath::pow(x, y);
      }
    case GLSLstd450FMin:
    case GLSLstd450NMin: return pick_min(x, y);
    case GLSLstd450FMax:
    case GLSLstd450NMax: return pick_max(x, y);
    case GLSLstd450Step: return value_of(y) < value_of(x) ? constant<T>(0) : constant<T>(1);
    default: return constant<T>(std::numeric_limits<double>::quiet_NaN());
  }
}

template <class T>
T f_ternary(std::uint16_t which, T x, T y, T z) {
  switch (which) {
    case GLSLstd450FClamp:
    case GLSLstd450NClamp: return pick_min(pick_max(x, y), z);
    case GLSLstd450FMix: return x * (constant<T>(1) - z) + y * z;  // the GLSL specification's x (1 - a) + y a
    case GLSLstd450SmoothStep: {
      const T t = pick_min(pick_max((z - x) / (y - x), constant<T>(0)), constant<T>(1));
      return t * t * (constant<T>(3) - constant<T>(2) * t);
    }
    case GLSLstd450Fma:
      if constexpr (is_dual<T>::value) {
        return x * y + z;
      } else {
        return std::fma(x, y, z);  // fused, as GLSL's fma is
      }
    default: return constant<T>(std::numeric_limits<double>::quiet_NaN());
  }
}

// 32-bit integers kept as their bit patterns, zero-extended; booleans as 0 and 1.
std::int64_t bits(std::int64_t v) { return static_cast<std::uint32_t>(v); }
std::int32_t as_signed(std::int64_t v) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(v)); }
std::uint32_t as_unsigned(std::int64_t v) { return static_cast<std::uint32_t>(v); }

std::int64_t i_unary(std::uint16_t which, std::int64_t x) {
  switch (which) {
    case spv::OpSNegate: return bits(-static_cast<std::int64_t>(as_signed(x)));
    case spv::OpNot: return bits(~as_unsigned(x));
    case spv::OpLogicalNot: return !x;
    case GLSLstd450SAbs: return bits(std::abs(static_cast<std::int64_t>(as_signed(x))));
    case GLSLstd450SSign: return bits(as_signed(x) > 0 ? 1 : as_signed(x) < 0 ? -1 : 0);
    default: return 0;
  }
}

std::int64_t i_binary(std::uint16_t which, std::int64_t x, std::int64_t y, std::int64_t z) {
  const std::int32_t sx = as_signed(x), sy = as_signed(y);
  const std::uint32_t ux = as_unsigned(x), uy = as_unsigned(y);
  switch (which) {
    case spv::OpIAdd: return bits(ux + uy);
    case spv::OpISub: return bits(ux - uy);
    case spv::OpIMul: return bits(ux * uy);
    case spv::OpSDiv: return sy == 0 ? 0 : bits(sx / sy);
    case spv::OpUDiv: return uy == 0 ? 0 : bits(ux / uy);
    case spv::OpSRem: return sy == 0 ? 0 : bits(sx % sy);
    case spv::OpSMod: return sy == 0 ? 0 : bits(((sx % sy) + sy) % sy);
    case spv::OpUMod: return uy == 0 ? 0 : bits(ux % uy);
    case spv::OpBitwiseAnd: return bits(ux & uy);
    case spv::OpBitwiseOr: return bits(ux | uy);
    case spv::OpBitwiseXor: return bits(ux ^ uy);
    case spv::OpShiftLeftLogical: return bits(ux << (uy & 31));
    case spv::OpShiftRightLogical: return bits(ux >> (uy & 31));
    case spv::OpShiftRightArithmetic: return bits(sx >> (uy & 31));
    case spv::OpLogicalAnd: return x && y;
    case spv::OpLogicalOr: return x || y;
    case spv::OpLogicalEqual: return (x != 0) == (y != 0);
    case spv::OpLogicalNotEqual: return (x != 0) != (y != 0);
    case GLSLstd450UMin: return bits(std::min(ux, uy));
    case GLSLstd450SMin: return bits(std::min(sx, sy));
    case GLSLstd450UMax: return bits(std::max(ux, uy));
    case GLSLstd450SMax: return bits(std::max(sx, sy));
    case GLSLstd450SClamp: return bits(std::min(std::max(sx, sy), as_signed(z)));
    case GLSLstd450UClamp: return bits(std::min(std::max(ux, uy), as_unsigned(z)));
    default: return 0;
  }
}

template <class S>
bool compare_f(std::uint16_t which, S x, S y) {
  const bool unordered = std::isnan(x) || std::isnan(y);
  switch (which) {
    case spv::OpFOrdEqual: return x == y;
    case spv::OpFOrdNotEqual: return !unordered && x != y;
    case spv::OpFOrdLessThan: return x < y;
    case spv::OpFOrdGreaterThan: return x > y;
    case spv::OpFOrdLessThanEqual: return x <= y;
    case spv::OpFOrdGreaterThanEqual: return x >= y;
    case spv::OpFUnordEqual: return unordered || x == y;
    case spv::OpFUnordNotEqual: return unordered || x != y;
    case spv::OpFUnordLessThan: return unordered || x < y;
    case spv::OpFUnordGreaterThan: return unordered || x > y;
    case spv::OpFUnordLessThanEqual: return unordered || x <= y;
    case spv::OpFUnordGreaterThanEqual: return unordered || x >= y;
    case spv::OpIsNan: return std::isnan(x);
    case spv::OpIsInf: return std::isinf(x);
    default: return false;
  }
}

bool compare_i(std::uint16_t which, std::int64_t x, std::int64_t y) {
  switch (which) {
    case spv::OpIEqual: return as_unsigned(x) == as_unsigned(y);
    case spv::OpINotEqual: return as_unsigned(x) != as_unsigned(y);
    case spv::OpSLessThan: return as_signed(x) < as_signed(y);
    case spv::OpSGreaterThan: return as_signed(x) > as_signed(y);
    case spv::OpSLessThanEqual: return as_signed(x) <= as_signed(y);
    case spv::OpSGreaterThanEqual: return as_signed(x) >= as_signed(y);
    case spv::OpULessThan: return as_unsigned(x) < as_unsigned(y);
    case spv::OpUGreaterThan: return as_unsigned(x) > as_unsigned(y);
    case spv::OpULessThanEqual: return as_unsigned(x) <= as_unsigned(y);
    case spv::OpUGreaterThanEqual: return as_unsigned(x) >= as_unsigned(y);
    default: return false;
  }
}

bool is_float_comparison(std::uint16_t which) {
  return (which >= spv::OpFOrdEqual && which <= spv::OpFUnordGreaterThanEqual) || which == spv::OpIsNan ||
         which == spv::OpIsInf;
}

// The slots of one evaluation, per thread and scalar: constants set once per program.
template <class T>
struct Frame {
  std::uint64_t program = 0;
  std::vector<T> f;
  std::vector<std::int64_t> i;
  std::vector<T> phi_f;
  std::vector<std::int64_t> phi_i;
  bool exhausted = false;  // the last evaluation ran out of steps
};

template <class T>
Frame<T>& frame_for(const Program& p) {
  thread_local Frame<T> frame;
  if (frame.program != p.id) {
    frame.f.assign(p.slots, constant<T>(0));
    frame.i.assign(p.slots, 0);
    for (size_t k = 0; k < p.constant_slots.size(); ++k) {
      frame.f[p.constant_slots[k]] = constant<T>(p.constant_f[k]);
      frame.i[p.constant_slots[k]] = p.constant_i[k];
    }
    frame.program = p.id;
  }
  return frame;
}

template <class T>
class Evaluator {
 public:
  Evaluator(const Program& p, Frame<T>& frame) : p_(p), f_(frame.f.data()), i_(frame.i.data()), frame_(frame) {}

  T run(glm::vec<3, T> at) {
    for (const auto& u : p_.uniforms)
      for (std::uint32_t k = 0; k < u.n; ++k) {
        f_[u.slot + k] = constant<T>(u.value[k]);
        i_[u.slot + k] = bits(static_cast<std::int64_t>(u.value[k]));
      }
    if (p_.has_input)  // a field that does not read its point has none
      for (int k = 0; k < 3; ++k) f_[p_.input + static_cast<std::uint32_t>(k)] = at[k];
    std::uint32_t block = 0, pc = p_.blocks[0].first;
    frame_.exhausted = false;
    for (std::uint64_t steps = 0; steps < GlslField::kMaxSteps; ++steps) {
      const Instr& in = p_.code[pc++];
      switch (in.code) {
        case Code::branch: jump(block, in.a, pc); break;
        case Code::branch_if: jump(block, i_[in.a] ? in.b : in.c, pc); break;
        case Code::switch_: {
          std::uint32_t target = in.b;
          for (std::uint32_t k = 0; k + 1 < in.list_size; k += 2)
            if (as_unsigned(i_[in.a]) == p_.lists[in.list + k]) target = p_.lists[in.list + k + 1];
          jump(block, target, pc);
          break;
        }
        case Code::ret: return f_[p_.output];  // and .y after it, material()'s
        case Code::kill: return constant<T>(std::numeric_limits<double>::quiet_NaN());
        default: execute(in); break;
      }
    }
    frame_.exhausted = true;  // a loop that does not end
    return constant<T>(std::numeric_limits<double>::quiet_NaN());
  }

 private:
  // The target's phis read their values from the block left, all before any is written.
  void jump(std::uint32_t& block, std::uint32_t target, std::uint32_t& pc) {
    const Block& b = p_.blocks[target];
    auto& tf = frame_.phi_f;
    auto& ti = frame_.phi_i;
    tf.clear();
    ti.clear();
    for (const Phi& phi : b.phis)
      for (const auto& [parent, value] : phi.from)
        if (parent == block) {
          for (std::uint32_t k = 0; k < phi.n; ++k) {
            tf.push_back(f_[value + k]);
            ti.push_back(i_[value + k]);
          }
          break;
        }
    size_t at = 0;
    for (const Phi& phi : b.phis)
      for (std::uint32_t k = 0; k < phi.n && at < tf.size(); ++k, ++at) {
        f_[phi.r + k] = tf[at];
        i_[phi.r + k] = ti[at];
      }
    block = target;
    pc = b.first;
  }

  void copy(std::uint32_t to, std::uint32_t from) {
    f_[to] = f_[from];
    i_[to] = i_[from];
  }

  void execute(const Instr& in) {
    const std::uint32_t n = in.n;
    switch (in.code) {
      case Code::gather:
        for (std::uint32_t k = 0; k < n; ++k) copy(in.r + k, p_.lists[in.list + k]);
        break;
      case Code::extract_at: {
        const auto at = std::min<std::uint32_t>(as_unsigned(i_[in.b]), in.c - 1);
        copy(in.r, in.a + at);
        break;
      }
      case Code::insert_at: {
        for (std::uint32_t k = 0; k < n; ++k) copy(in.r + k, in.a + k);
        copy(in.r + std::min<std::uint32_t>(as_unsigned(i_[in.b]), n - 1), in.c);
        break;
      }
      case Code::load: {
        const auto from = static_cast<std::uint32_t>(i_[in.a]);
        for (std::uint32_t k = 0; k < n; ++k) copy(in.r + k, from + k);
        break;
      }
      case Code::store: {
        const auto to = static_cast<std::uint32_t>(i_[in.a]);
        for (std::uint32_t k = 0; k < n; ++k) copy(to + k, in.b + k);
        break;
      }
      case Code::access: {
        std::int64_t at = i_[in.a] + in.b;
        for (std::uint32_t k = 0; k + 1 < in.list_size; k += 2)
          at += static_cast<std::int64_t>(as_signed(i_[p_.lists[in.list + k]])) * p_.lists[in.list + k + 1];
        i_[in.r] = at;
        break;
      }
      case Code::f_unary:
        for (std::uint32_t k = 0; k < n; ++k) f_[in.r + k] = f_unary(in.ext, f_[in.a + k * in.step_a]);
        break;
      case Code::f_binary:
        for (std::uint32_t k = 0; k < n; ++k)
          f_[in.r + k] = f_binary(in.ext, f_[in.a + k * in.step_a], f_[in.b + k * in.step_b]);
        break;
      case Code::f_ternary:
        for (std::uint32_t k = 0; k < n; ++k)
          f_[in.r + k] =
              f_ternary(in.ext, f_[in.a + k * in.step_a], f_[in.b + k * in.step_b], f_[in.c + k * in.step_c]);
        break;
      case Code::i_unary:
        for (std::uint32_t k = 0; k < n; ++k) i_[in.r + k] = i_unary(in.ext, i_[in.a + k * in.step_a]);
        break;
      case Code::i_binary:
        for (std::uint32_t k = 0; k < n; ++k)
          i_[in.r + k] = i_binary(in.ext, i_[in.a + k * in.step_a], i_[in.b + k * in.step_b],
                                  in.c ? i_[in.c + k * in.step_c] : 0);
        break;
      case Code::compare:
        for (std::uint32_t k = 0; k < n; ++k)
          i_[in.r + k] = is_float_comparison(in.ext)
                             ? compare_f(in.ext, value_of(f_[in.a + k * in.step_a]), value_of(f_[in.b + k * in.step_b]))
                             : compare_i(in.ext, i_[in.a + k * in.step_a], i_[in.b + k * in.step_b]);
        break;
      case Code::select:
        for (std::uint32_t k = 0; k < n; ++k)
          copy(in.r + k, i_[in.a + k * in.step_a] ? in.b + k * in.step_b : in.c + k * in.step_c);
        break;
      case Code::convert:
        for (std::uint32_t k = 0; k < n; ++k) convert(in, in.r + k, in.a + k * in.step_a);
        break;
      case Code::dot: f_[in.r] = dot(in.a, in.b, in.c); break;
      case Code::matrix: matrix(in); break;
      case Code::vector_fn: vector_fn(in); break;
      case Code::reduce: {
        bool any = false, all = true;
        for (std::uint32_t k = 0; k < in.c; ++k) {
          any = any || i_[in.a + k];
          all = all && i_[in.a + k];
        }
        i_[in.r] = in.ext == spv::OpAny ? any : all;
        break;
      }
      default: break;
    }
  }

  void convert(const Instr& in, std::uint32_t r, std::uint32_t a) {
    switch (in.ext) {
      case spv::OpConvertFToS: i_[r] = bits(static_cast<std::int32_t>(value_of(f_[a]))); break;
      case spv::OpConvertFToU: i_[r] = bits(static_cast<std::uint32_t>(value_of(f_[a]))); break;
      case spv::OpConvertSToF: f_[r] = constant<T>(as_signed(i_[a])); break;
      case spv::OpConvertUToF: f_[r] = constant<T>(as_unsigned(i_[a])); break;
      default:  // a bitcast: a float's bits are its float rounding's, also in double (the shader's floats)
        if (in.step_b == 2) {
          i_[r] = i_[a];
        } else if (in.step_b == 1) {
          i_[r] = std::bit_cast<std::uint32_t>(static_cast<float>(value_of(f_[a])));
        } else {
          f_[r] = constant<T>(std::bit_cast<float>(as_unsigned(i_[a])));
        }
    }
  }

  void matrix(const Instr& in) {
    if (in.ext == spv::OpMatrixTimesVector) {  // rows = step_a, columns = step_b
      for (std::uint32_t row = 0; row < in.step_a; ++row) {
        T sum = f_[in.a + row] * f_[in.b];
        for (std::uint32_t c = 1; c < in.step_b; ++c) sum = sum + f_[in.a + c * in.step_a + row] * f_[in.b + c];
        f_[in.r + row] = sum;
      }
    } else if (in.ext == spv::OpVectorTimesMatrix) {  // the matrix: rows = step_a, columns = step_b
      for (std::uint32_t c = 0; c < in.step_b; ++c) {
        T sum = f_[in.a] * f_[in.b + c * in.step_a];
        for (std::uint32_t row = 1; row < in.step_a; ++row) sum = sum + f_[in.a + row] * f_[in.b + c * in.step_a + row];
        f_[in.r + c] = sum;
      }
    } else {  // left: rows step_a, inner step_b; right: c columns
      for (std::uint32_t c = 0; c < in.c; ++c)
        for (std::uint32_t row = 0; row < in.step_a; ++row) {
          T sum = f_[in.a + row] * f_[in.b + c * in.step_b];
          for (std::uint32_t j = 1; j < in.step_b; ++j)
            sum = sum + f_[in.a + j * in.step_a + row] * f_[in.b + c * in.step_b + j];
          f_[in.r + c * in.step_a + row] = sum;
        }
    }
  }

  T dot(std::uint32_t a, std::uint32_t b, std::uint32_t n) const {
    T sum = f_[a] * f_[b];
    for (std::uint32_t k = 1; k < n; ++k) sum = sum + f_[a + k] * f_[b + k];
    return sum;
  }

  void vector_fn(const Instr& in) {
    const std::uint32_t n = in.n;
    switch (in.ext) {
      case GLSLstd450Length: f_[in.r] = f_unary<T>(GLSLstd450Sqrt, dot(in.a, in.a, n)); break;
      case GLSLstd450Distance: {
        T sum = constant<T>(0);
        for (std::uint32_t k = 0; k < n; ++k) {
          const T d = f_[in.a + k] - f_[in.b + k];
          sum = k == 0 ? d * d : sum + d * d;
        }
        f_[in.r] = f_unary<T>(GLSLstd450Sqrt, sum);
        break;
      }
      case GLSLstd450Normalize: {
        const T length = f_unary<T>(GLSLstd450Sqrt, dot(in.a, in.a, n));
        for (std::uint32_t k = 0; k < n; ++k) f_[in.r + k] = f_[in.a + k] / length;
        break;
      }
      case GLSLstd450Cross: {
        const T* a = &f_[in.a];
        const T* b = &f_[in.b];
        const T x = a[1] * b[2] - b[1] * a[2], y = a[2] * b[0] - b[2] * a[0], z = a[0] * b[1] - b[0] * a[1];
        f_[in.r] = x;
        f_[in.r + 1] = y;
        f_[in.r + 2] = z;
        break;
      }
      case GLSLstd450FaceForward: {  // N, I, Nref
        const bool keep = value_of(dot(in.c, in.b, n)) < 0;
        for (std::uint32_t k = 0; k < n; ++k) f_[in.r + k] = keep ? f_[in.a + k] : -f_[in.a + k];
        break;
      }
      case GLSLstd450Reflect: {  // I, N: I - 2 dot(N, I) N
        const T d = dot(in.b, in.a, n);
        for (std::uint32_t k = 0; k < n; ++k) f_[in.r + k] = f_[in.a + k] - constant<T>(2) * d * f_[in.b + k];
        break;
      }
      case GLSLstd450Refract: {  // I, N, eta
        const T d = dot(in.b, in.a, n), eta = f_[in.c];
        const T k2 = constant<T>(1) - eta * eta * (constant<T>(1) - d * d);
        for (std::uint32_t k = 0; k < n; ++k)
          f_[in.r + k] = value_of(k2) < 0 ? constant<T>(0)
                                          : eta * f_[in.a + k] - (eta * d + f_unary<T>(GLSLstd450Sqrt, k2)) * f_[in.b + k];
        break;
      }
      default: break;
    }
  }

  const Program& p_;
  T* f_;
  std::int64_t* i_;
  Frame<T>& frame_;
};

}  // namespace

}  // namespace glsl

template <class T>
T GlslField::distance(glm::vec<3, T> p) const {
  if constexpr (std::is_same_v<T, float>)
    if (spec_.half) return distance(glm::vec<3, Half>(Half(p.x), Half(p.y), Half(p.z)));
  glsl::Frame<T>& frame = glsl::frame_for<T>(*program_);
  return glsl::Evaluator<T>(*program_, frame).run(p);
}

int GlslField::material(glm::dvec3 p) const {
  if (spec_.materials.empty()) return -1;
  glsl::Frame<double>& frame = glsl::frame_for<double>(*program_);
  glsl::Evaluator<double>(*program_, frame).run(p);
  const double y = frame.f[program_->output + 1];
  if (!(y > -0.5 && y < static_cast<double>(spec_.materials.size()) - 0.5)) return -1;
  return spec_.materials[static_cast<std::size_t>(std::lround(y))];
}

GlslField GlslField::with_half(bool half) const {
  GlslField out = *this;
  out.spec_.half = half;
  return out;
}

bool GlslField::exhausted() const { return glsl::frame_for<double>(*program_).exhausted; }

bool GlslField::finishes_at_origin() const {
  distance(glm::dvec3(0));
  return !exhausted();
}

GlslField::GlslField(GlslSpec spec, const std::string& text, const std::string& file) : spec_(std::move(spec)) {
  program_ = std::make_shared<const glsl::Program>(
      glsl::decode(glsl::compile_field(text, file, spec_.function), spec_, file));
  const auto unfinished = [&](glm::dvec3 p) {
    std::ostringstream at;
    at << "(" << p.x << ", " << p.y << ", " << p.z << ")";
    return GlslError(file + ": " + spec_.function + " does not finish within " + std::to_string(kMaxSteps) +
                     " SPIR-V instructions at " + at.str() + ": a loop that does not end?");
  };
  if (!finishes_at_origin()) throw unfinished(glm::dvec3(0));
  // Not declared: the steepest of 20000 nearby pairs (1e-5 apart) in [-4, 4]^3, a lower bound on the constant.
  // A point where it does not finish ends the measurement (each costs kMaxSteps instructions).
  if (spec_.measured)
    spec_.lipschitz = measured_slope(
        [&](glm::dvec3 p) {
          const double f = distance(p);
          if (exhausted()) throw unfinished(p);
          return f;
        },
        glm::dvec3(-4), glm::dvec3(4));
}


template float GlslField::distance(glm::vec<3, float>) const;
template double GlslField::distance(glm::vec<3, double>) const;
template Dual<float> GlslField::distance(glm::vec<3, Dual<float>>) const;
template Dual<double> GlslField::distance(glm::vec<3, Dual<double>>) const;
template Half GlslField::distance(glm::vec<3, Half>) const;

}  // namespace marchcheck::sdf
