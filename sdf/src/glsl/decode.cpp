// SPIR-V (as compile_field leaves it: one function, SSA values) decoded into slots and flat instructions.
#include "program.hpp"

#include <spirv/unified1/GLSL.std.450.h>
#include <spirv/unified1/spirv.hpp>

#include <atomic>
#include <bit>
#include <cstring>
#include <unordered_map>
#include <unordered_set>

namespace marchcheck::sdf::glsl {

namespace {

struct TypeInfo {
  spv::Op op = spv::OpNop;
  std::uint32_t size = 0;   // slots
  Kind kind = Kind::floating;  // of its scalars (the first member's for a struct)
  std::uint32_t elem = 0;   // vector: component type; matrix: column type; array: element; pointer: pointee
  std::uint32_t count = 0;  // vector: components; matrix: columns; array: length
  std::vector<std::uint32_t> members = {};
  bool opaque = false;  // a texture, sampler or buffer (or an array of, or pointer to, them): never evaluated
};

class Decoder {
 public:
  Decoder(const std::vector<std::uint32_t>& words, const GlslSpec& spec, const std::string& file)
      : words_(words), spec_(spec), file_(file) {}

  Program run() {
    static std::atomic<std::uint64_t> next_id{1};
    p_.id = next_id++;
    if (words_.size() < 5 || words_[0] != spv::MagicNumber) fail("internal: not SPIR-V");
    for (size_t at = 5; at < words_.size();) {
      const std::uint32_t count = words_[at] >> 16;
      const auto op = static_cast<spv::Op>(words_[at] & 0xffff);
      if (count == 0 || at + count > words_.size()) fail("internal: truncated SPIR-V");
      w_ = &words_[at + 1];
      n_ = count - 1;
      instruction(op);
      at += count;
    }
    resolve_blocks();
    return std::move(p_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw GlslError(file_ + ": " + what); }

  std::string literal_string(std::uint32_t from) const {
    std::string s;
    for (std::uint32_t k = from; k < n_; ++k) {
      char c[4];
      std::memcpy(c, &w_[k], 4);
      for (char ch : c) {
        if (ch == 0) return s;
        s += ch;
      }
    }
    return s;
  }

  const TypeInfo& type(std::uint32_t id) const {
    const auto it = types_.find(id);
    if (it == types_.end()) fail("internal: unknown type %" + std::to_string(id));
    return it->second;
  }
  std::uint32_t slot(std::uint32_t id) const {
    const auto it = slot_of_.find(id);
    if (it == slot_of_.end()) fail("internal: value %" + std::to_string(id) + " used before it is defined");
    return it->second;
  }
  std::uint32_t size_of(std::uint32_t id) const { return type(type_of_.at(id)).size; }
  Kind kind_of(std::uint32_t id) const { return type(type_of_.at(id)).kind; }

  std::uint32_t allocate(std::uint32_t result, std::uint32_t result_type) {
    const std::uint32_t at = p_.slots;
    p_.slots += std::max<std::uint32_t>(1, type(result_type).size);
    slot_of_[result] = at;
    type_of_[result] = result_type;
    return at;
  }
  void constant(std::uint32_t at, double f, std::int64_t i) {
    constant_at_[at] = p_.constant_slots.size();
    p_.constant_slots.push_back(at);
    p_.constant_f.push_back(f);
    p_.constant_i.push_back(i);
  }

  void add_type(std::uint32_t id, TypeInfo t) { types_[id] = std::move(t); }

  // The slot offset and type reached by constant indices into a composite of type t.
  std::pair<std::uint32_t, std::uint32_t> member(std::uint32_t t, const std::uint32_t* index, std::uint32_t count) const {
    std::uint32_t offset = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
      const TypeInfo& ti = type(t);
      if (ti.op == spv::OpTypeStruct) {
        for (std::uint32_t m = 0; m < index[k]; ++m) offset += type(ti.members[m]).size;
        t = ti.members[index[k]];
      } else {
        offset += index[k] * type(ti.elem).size;
        t = ti.elem;
      }
    }
    return {offset, t};
  }

  void emit(Instr in) { p_.code.push_back(in); }
  std::uint32_t list(const std::vector<std::uint32_t>& values) {
    const auto at = static_cast<std::uint32_t>(p_.lists.size());
    p_.lists.insert(p_.lists.end(), values.begin(), values.end());
    return at;
  }
  void gather(std::uint32_t result, std::uint32_t result_type, const std::vector<std::uint32_t>& sources) {
    Instr in{Code::gather};
    in.r = allocate(result, result_type);
    in.n = static_cast<std::uint32_t>(sources.size());
    in.list = list(sources);
    in.list_size = in.n;
    emit(in);
  }
  // An instruction on operands a (and b, c) whose result has the result type's size; a scalar operand among
  // vectors is broadcast.
  void componentwise(Code code, std::uint16_t ext, std::uint32_t result, std::uint32_t result_type,
                     std::initializer_list<std::uint32_t> operands) {
    Instr in{code, ext};
    in.r = allocate(result, result_type);
    in.n = type(result_type).size;
    std::uint32_t* slots[] = {&in.a, &in.b, &in.c};
    std::uint32_t* steps[] = {&in.step_a, &in.step_b, &in.step_c};
    int k = 0;
    for (const std::uint32_t id : operands) {
      *slots[k] = slot(id);
      *steps[k] = size_of(id) == 1 && in.n > 1 ? 0 : 1;
      ++k;
    }
    emit(in);
  }

  // An instruction over the components of its first operand (c: their count), with a second one or not.
  void over_components(Code code, std::uint16_t ext, bool second) {
    Instr in{code, ext};
    in.r = allocate(w_[1], w_[0]);
    in.a = slot(w_[2]);
    if (second) in.b = slot(w_[3]);
    in.c = size_of(w_[2]);
    emit(in);
  }

  void instruction(spv::Op op);
  bool memory_or_composite(spv::Op op);  // each true when it decoded op
  bool arithmetic(spv::Op op);
  bool control(spv::Op op);
  void types_and_constants(spv::Op op);
  void variable(std::uint32_t result_type, std::uint32_t result, spv::StorageClass storage);
  void ext_inst();
  void resolve_blocks();

  const std::vector<std::uint32_t>& words_;
  const GlslSpec& spec_;
  const std::string& file_;
  const std::uint32_t* w_ = nullptr;  // the current instruction's operands
  std::uint32_t n_ = 0;
  Program p_;
  std::unordered_map<std::uint32_t, TypeInfo> types_;
  std::unordered_map<std::uint32_t, std::uint32_t> slot_of_, type_of_;
  std::unordered_map<std::uint32_t, std::int64_t> int_constants_;
  std::unordered_map<std::uint32_t, std::string> names_;
  std::unordered_map<std::uint32_t, std::uint32_t> block_of_;  // label -> block
  // Branch targets and phi operands name labels and values that may come later: resolved at the end.
  struct LabelUse {
    size_t at;   // instruction
    char field;  // 'a', 'b' or 'c'
    std::uint32_t label;
  };
  std::vector<LabelUse> label_ids_;
  struct PhiValue {
    std::uint32_t value;
    size_t block, phi, pair;
  };
  std::vector<PhiValue> pending_phi_values_;
  std::unordered_map<std::uint32_t, size_t> constant_at_;  // slot -> index into the constants
  std::unordered_set<std::uint32_t> opaque_;               // variables of textures, samplers, buffers
  void refuse_opaque(std::uint32_t pointer) const {
    if (opaque_.count(pointer))
      fail("textures, samplers and buffers are not supported in a field (" + names_.at(pointer) + ")");
  }
  std::uint32_t glsl_set_ = 0;
  int functions_ = 0;
  bool has_output_ = false;
};

void Decoder::types_and_constants(spv::Op op) {
  using namespace spv;
  switch (op) {
    case OpTypeVoid: add_type(w_[0], {op, 0}); return;
    case OpTypeBool: add_type(w_[0], {op, 1, Kind::integer}); return;
    case OpTypeInt:
      if (w_[1] != 32) fail("only 32-bit integers are supported");
      add_type(w_[0], {op, 1, Kind::integer});
      return;
    case OpTypeFloat: add_type(w_[0], {op, 1, Kind::floating}); return;
    case OpTypeVector:
    case OpTypeMatrix: {
      const TypeInfo& e = type(w_[1]);
      add_type(w_[0], {op, e.size * w_[2], e.kind, w_[1], w_[2]});
      return;
    }
    case OpTypeArray: {
      const TypeInfo& e = type(w_[1]);
      const auto length = static_cast<std::uint32_t>(int_constants_.at(w_[2]));
      TypeInfo t{op, e.size * length, e.kind, w_[1], length};
      t.opaque = e.opaque;
      add_type(w_[0], t);
      return;
    }
    case OpTypeStruct: {
      TypeInfo t{op};
      for (std::uint32_t k = 1; k < n_; ++k) {
        t.members.push_back(w_[k]);
        t.size += type(w_[k]).size;
      }
      if (!t.members.empty()) t.kind = type(t.members[0]).kind;
      add_type(w_[0], t);
      return;
    }
    case OpTypePointer: {
      TypeInfo t{op, 1, Kind::integer, w_[2]};
      t.opaque = type(w_[2]).opaque;
      add_type(w_[0], t);
      return;
    }
    case OpTypeFunction: add_type(w_[0], {op, 0}); return;
    case OpTypeImage:
    case OpTypeSampler:
    case OpTypeSampledImage:
    case OpTypeRuntimeArray: {  // a pasted shader's iChannel0 is fine as long as the field does not read it
      TypeInfo t{op};
      t.opaque = true;
      add_type(w_[0], t);
      return;
    }
    case OpConstant:
    case OpSpecConstant: {
      const std::uint32_t at = allocate(w_[1], w_[0]);
      if (type(w_[0]).kind == Kind::integer) {
        int_constants_[w_[1]] = static_cast<std::int32_t>(w_[2]);
        constant(at, 0, w_[2]);
      } else if (n_ == 4) {
        double d;
        const std::uint64_t bits = w_[2] | (static_cast<std::uint64_t>(w_[3]) << 32);
        std::memcpy(&d, &bits, 8);
        constant(at, d, 0);
      } else {
        constant(at, std::bit_cast<float>(w_[2]), 0);
      }
      return;
    }
    case OpConstantTrue:
    case OpConstantFalse:
    case OpSpecConstantTrue:
    case OpSpecConstantFalse:
      constant(allocate(w_[1], w_[0]), 0, op == OpConstantTrue || op == OpSpecConstantTrue);
      return;
    case OpConstantNull:
    case OpUndef: {
      const std::uint32_t at = allocate(w_[1], w_[0]);
      for (std::uint32_t k = 0; k < type(w_[0]).size; ++k) constant(at + k, 0, 0);
      return;
    }
    case OpConstantComposite:
    case OpSpecConstantComposite: {
      const std::uint32_t at = allocate(w_[1], w_[0]);
      std::uint32_t k = 0;
      for (std::uint32_t c = 2; c < n_; ++c) {
        const std::uint32_t from = slot(w_[c]);
        for (std::uint32_t j = 0; j < size_of(w_[c]); ++j, ++k) {
          const size_t i = constant_at_.at(from + j);
          constant(at + k, p_.constant_f[i], p_.constant_i[i]);
        }
      }
      return;
    }
    default: fail("internal: not a type or constant");
  }
}

void Decoder::variable(std::uint32_t result_type, std::uint32_t result, spv::StorageClass storage) {
  const std::uint32_t pointee = type(result_type).elem;
  const TypeInfo& t = type(pointee);
  if (t.opaque) {  // refused where the field reads it, not here
    opaque_.insert(result);
    return;
  }
  const std::uint32_t base = p_.slots;
  p_.slots += std::max<std::uint32_t>(1, t.size);
  constant(allocate(result, result_type), 0, base);  // a pointer to its storage, fixed
  const std::string& name = names_[result];
  const bool initialised = n_ > 3;
  switch (storage) {
    case spv::StorageClassInput:
      if (name == "marchcheck_p") {
        p_.input = base;
        p_.has_input = true;
      }
      return;
    case spv::StorageClassOutput:
      if (name == "marchcheck_result") {
        p_.output = base;
        has_output_ = true;
      }
      return;
    case spv::StorageClassUniformConstant:
    case spv::StorageClassUniform: {
      const auto given = spec_.uniforms.find(name);
      Program::UniformSlot u{base, t.size, given != spec_.uniforms.end() ? given->second : std::vector<double>{}, t.kind};
      if (!u.value.empty() && u.value.size() != t.size)
        fail("uniform " + name + " has " + std::to_string(t.size) + " components, the scene gives " +
             std::to_string(u.value.size()));
      u.value.resize(t.size, 0.0);
      p_.uniforms.push_back(u);
      return;
    }
    case spv::StorageClassFunction:
    case spv::StorageClassPrivate:
      // A local's initialiser runs where it is declared; a global's, and every variable without one, is reset
      // before each evaluation, so no value leaks from one point to the next.
      if (initialised && storage == spv::StorageClassFunction && !p_.blocks.empty()) {
        Instr in{Code::store};
        in.a = slot(result);
        in.b = slot(w_[3]);
        in.n = t.size;
        emit(in);
        return;
      }
      {
        Program::UniformSlot reset{base, t.size, std::vector<double>(t.size, 0.0), t.kind};
        if (initialised)
          for (std::uint32_t k = 0; k < t.size; ++k) {
            const auto c = constant_at_.find(slot(w_[3]) + k);
            if (c == constant_at_.end()) fail("a global variable's initialiser is not a constant");
            reset.value[k] = t.kind == Kind::integer ? static_cast<double>(p_.constant_i[c->second]) : p_.constant_f[c->second];
          }
        p_.uniforms.push_back(reset);
      }
      return;
    default: fail("a variable in storage class " + std::to_string(storage) + " is not supported");
  }
}

// GLSL.std.450's functions: float ones by number (run by the evaluator's fn tables), integer ones as integer
// instructions, the vector ones apart.
void Decoder::ext_inst() {
  const std::uint32_t result_type = w_[0], result = w_[1];
  if (w_[2] != glsl_set_) fail("an extended instruction set other than GLSL.std.450 is not supported");
  const auto which = static_cast<std::uint16_t>(w_[3]);
  const std::uint32_t args = n_ - 4;
  const std::uint32_t* a = w_ + 4;
  switch (which) {
    case GLSLstd450Length:
    case GLSLstd450Distance:
    case GLSLstd450Normalize:
    case GLSLstd450Cross:
    case GLSLstd450Reflect:
    case GLSLstd450Refract:
    case GLSLstd450FaceForward: {
      Instr in{Code::vector_fn, which};
      in.r = allocate(result, result_type);
      in.n = size_of(a[0]);  // the operands' size; the result is a scalar or that size
      in.a = slot(a[0]);
      if (args > 1) in.b = slot(a[1]);
      if (args > 2) in.c = slot(a[2]);
      emit(in);
      return;
    }
    case GLSLstd450Modf:
    case GLSLstd450ModfStruct:
    case GLSLstd450Frexp:
    case GLSLstd450FrexpStruct:
    case GLSLstd450Determinant:
    case GLSLstd450MatrixInverse:
    case GLSLstd450PackHalf2x16:
    case GLSLstd450UnpackHalf2x16:
      fail("the GLSL built-in #" + std::to_string(which) + " (modf, frexp, determinant, inverse, pack/unpack) is not supported");
    default: break;
  }
  const bool integer = type(result_type).kind == Kind::integer;
  const Code code = args == 1 ? (integer ? Code::i_unary : Code::f_unary)
                    : args == 2 ? (integer ? Code::i_binary : Code::f_binary)
                                : Code::f_ternary;
  if (integer && args == 3 && which != GLSLstd450SClamp && which != GLSLstd450UClamp)
    fail("the integer GLSL built-in #" + std::to_string(which) + " is not supported");
  // Integer clamps are binary integer instructions with a third operand.
  if (args == 1) componentwise(code, which, result, result_type, {a[0]});
  if (args == 2) componentwise(code, which, result, result_type, {a[0], a[1]});
  if (args == 3) componentwise(integer ? Code::i_binary : Code::f_ternary, which, result, result_type, {a[0], a[1], a[2]});
}

void Decoder::instruction(spv::Op op) {
  using namespace spv;
  switch (op) {
    case OpName: names_[w_[0]] = literal_string(1); return;
    case OpExtInstImport:
      if (literal_string(1) != "GLSL.std.450") fail("the extended instructions " + literal_string(1) + " are not supported");
      glsl_set_ = w_[0];
      return;
    case OpCapability:
    case OpExtension:
    case OpMemoryModel:
    case OpEntryPoint:
    case OpExecutionMode:
    case OpSource:
    case OpSourceContinued:
    case OpSourceExtension:
    case OpString:
    case OpLine:
    case OpNoLine:
    case OpModuleProcessed:
    case OpMemberName:
    case OpDecorate:
    case OpMemberDecorate:
    case OpDecorationGroup:
    case OpGroupDecorate:
    case OpSelectionMerge:
    case OpLoopMerge:
    case OpFunctionEnd:
    case OpNop:
      return;
    case OpTypeVoid: case OpTypeBool: case OpTypeInt: case OpTypeFloat: case OpTypeVector: case OpTypeMatrix:
    case OpTypeArray: case OpTypeStruct: case OpTypePointer: case OpTypeFunction: case OpTypeImage:
    case OpTypeSampler: case OpTypeSampledImage: case OpTypeRuntimeArray: case OpConstant: case OpSpecConstant:
    case OpConstantTrue: case OpConstantFalse: case OpSpecConstantTrue: case OpSpecConstantFalse:
    case OpConstantNull: case OpUndef: case OpConstantComposite: case OpSpecConstantComposite:
      types_and_constants(op);
      return;
    case OpVariable: variable(w_[0], w_[1], static_cast<StorageClass>(w_[2])); return;
    case OpFunction:
      if (++functions_ > 1) fail("a function could not be inlined (recursion is not GLSL)");
      return;
    case OpFunctionParameter: fail("internal: main takes no parameters");
    case OpFunctionCall: fail("a function call could not be inlined");
    case OpLabel:
      block_of_[w_[0]] = static_cast<std::uint32_t>(p_.blocks.size());
      p_.blocks.push_back({static_cast<std::uint32_t>(p_.code.size()), {}});
      return;
    case OpPhi: {
      Phi phi{allocate(w_[1], w_[0]), type(w_[0]).size, {}};
      // Values from later blocks (loop back edges) are not decoded yet: ids and labels are resolved at the end.
      for (std::uint32_t k = 2; k + 1 < n_; k += 2) {
        pending_phi_values_.push_back({w_[k], p_.blocks.size() - 1, p_.blocks.back().phis.size(), phi.from.size()});
        phi.from.push_back({w_[k + 1], 0});
      }
      p_.blocks.back().phis.push_back(phi);
      return;
    }
    default:
      if (!memory_or_composite(op) && !arithmetic(op) && !control(op))
        fail("the SPIR-V instruction with opcode " + std::to_string(op) +
             " is not supported by the evaluator (derivatives, textures, atomics, barriers, doubles' own ops)");
  }
}

// Loads, stores, access chains and the composites: copies of slots.
bool Decoder::memory_or_composite(spv::Op op) {
  using namespace spv;
  switch (op) {
    case OpLoad: {
      refuse_opaque(w_[2]);
      Instr in{Code::load};
      in.r = allocate(w_[1], w_[0]);
      in.n = type(w_[0]).size;
      in.a = slot(w_[2]);
      emit(in);
      return true;
    }
    case OpStore: {
      Instr in{Code::store};
      in.a = slot(w_[0]);
      in.b = slot(w_[1]);
      in.n = size_of(w_[1]);
      emit(in);
      return true;
    }
    case OpAccessChain:
    case OpInBoundsAccessChain: {
      refuse_opaque(w_[2]);
      Instr in{Code::access};
      in.a = slot(w_[2]);
      std::uint32_t t = type(type_of_.at(w_[2])).elem;
      std::uint32_t offset = 0;
      std::vector<std::uint32_t> dynamic;  // (index slot, stride) pairs
      for (std::uint32_t k = 3; k < n_; ++k) {
        const TypeInfo& ti = type(t);
        const auto known = int_constants_.find(w_[k]);
        if (ti.op == OpTypeStruct) {
          const auto index = static_cast<std::uint32_t>(known->second);
          offset += member(t, &index, 1).first;
          t = ti.members[index];
          continue;
        }
        const std::uint32_t stride = type(ti.elem).size;
        if (known != int_constants_.end()) {
          offset += static_cast<std::uint32_t>(known->second) * stride;
        } else {
          dynamic.push_back(slot(w_[k]));
          dynamic.push_back(stride);
        }
        t = ti.elem;
      }
      in.r = allocate(w_[1], w_[0]);
      in.b = offset;
      in.list = list(dynamic);
      in.list_size = static_cast<std::uint32_t>(dynamic.size());
      emit(in);
      return true;
    }
    case OpCompositeExtract: {
      const auto [offset, t] = member(type_of_.at(w_[2]), w_ + 3, n_ - 3);
      std::vector<std::uint32_t> src;
      for (std::uint32_t k = 0; k < type(t).size; ++k) src.push_back(slot(w_[2]) + offset + k);
      gather(w_[1], w_[0], src);
      return true;
    }
    case OpCompositeInsert: {
      const auto [offset, t] = member(w_[0], w_ + 4, n_ - 4);
      std::vector<std::uint32_t> src;
      for (std::uint32_t k = 0; k < type(w_[0]).size; ++k)
        src.push_back(k >= offset && k < offset + type(t).size ? slot(w_[2]) + k - offset : slot(w_[3]) + k);
      gather(w_[1], w_[0], src);
      return true;
    }
    case OpCompositeConstruct: {
      std::vector<std::uint32_t> src;
      for (std::uint32_t c = 2; c < n_; ++c)
        for (std::uint32_t k = 0; k < size_of(w_[c]); ++k) src.push_back(slot(w_[c]) + k);
      gather(w_[1], w_[0], src);
      return true;
    }
    case OpCopyObject: {
      std::vector<std::uint32_t> src;
      for (std::uint32_t k = 0; k < type(w_[0]).size; ++k) src.push_back(slot(w_[2]) + k);
      gather(w_[1], w_[0], src);
      return true;
    }
    case OpVectorShuffle: {
      const std::uint32_t first = size_of(w_[2]);
      std::vector<std::uint32_t> src;
      for (std::uint32_t k = 4; k < n_; ++k) {
        const std::uint32_t c = w_[k] == 0xffffffff ? 0 : w_[k];
        src.push_back(c < first ? slot(w_[2]) + c : slot(w_[3]) + c - first);
      }
      gather(w_[1], w_[0], src);
      return true;
    }
    case OpTranspose: {
      const TypeInfo& t = type(w_[0]);
      const std::uint32_t cols = t.count, rows = type(t.elem).size;  // of the result
      std::vector<std::uint32_t> src;
      for (std::uint32_t c = 0; c < cols; ++c)
        for (std::uint32_t r = 0; r < rows; ++r) src.push_back(slot(w_[2]) + r * cols + c);
      gather(w_[1], w_[0], src);
      return true;
    }
    case OpVectorExtractDynamic: over_components(Code::extract_at, 0, true); return true;
    case OpVectorInsertDynamic: {
      Instr in{Code::insert_at};
      in.r = allocate(w_[1], w_[0]);
      in.n = type(w_[0]).size;
      in.a = slot(w_[2]);
      in.c = slot(w_[3]);
      in.b = slot(w_[4]);
      emit(in);
      return true;
    }
    default: return false;
  }
}

// Arithmetic, comparisons, conversions, products and the GLSL built-ins.
bool Decoder::arithmetic(spv::Op op) {
  using namespace spv;
  switch (op) {
    case OpFAdd: case OpFSub: case OpFMul: case OpFDiv: case OpFRem: case OpFMod:
      componentwise(Code::f_binary, static_cast<std::uint16_t>(op), w_[1], w_[0], {w_[2], w_[3]});
      return true;
    case OpVectorTimesScalar:
    case OpMatrixTimesScalar:
      componentwise(Code::f_binary, static_cast<std::uint16_t>(OpFMul), w_[1], w_[0], {w_[2], w_[3]});
      return true;
    case OpFNegate: componentwise(Code::f_unary, static_cast<std::uint16_t>(op), w_[1], w_[0], {w_[2]}); return true;
    case OpIAdd: case OpISub: case OpIMul: case OpSDiv: case OpUDiv: case OpSRem: case OpSMod: case OpUMod:
    case OpBitwiseAnd: case OpBitwiseOr: case OpBitwiseXor: case OpShiftLeftLogical: case OpShiftRightLogical:
    case OpShiftRightArithmetic: case OpLogicalAnd: case OpLogicalOr: case OpLogicalEqual: case OpLogicalNotEqual:
      componentwise(Code::i_binary, static_cast<std::uint16_t>(op), w_[1], w_[0], {w_[2], w_[3]});
      return true;
    case OpSNegate: case OpNot: case OpLogicalNot:
      componentwise(Code::i_unary, static_cast<std::uint16_t>(op), w_[1], w_[0], {w_[2]});
      return true;
    case OpFOrdEqual: case OpFOrdNotEqual: case OpFOrdLessThan: case OpFOrdGreaterThan: case OpFOrdLessThanEqual:
    case OpFOrdGreaterThanEqual: case OpFUnordEqual: case OpFUnordNotEqual: case OpFUnordLessThan:
    case OpFUnordGreaterThan: case OpFUnordLessThanEqual: case OpFUnordGreaterThanEqual: case OpIEqual:
    case OpINotEqual: case OpSLessThan: case OpSGreaterThan: case OpSLessThanEqual: case OpSGreaterThanEqual:
    case OpULessThan: case OpUGreaterThan: case OpULessThanEqual: case OpUGreaterThanEqual:
      componentwise(Code::compare, static_cast<std::uint16_t>(op), w_[1], w_[0], {w_[2], w_[3]});
      return true;
    case OpIsNan: case OpIsInf:
      componentwise(Code::compare, static_cast<std::uint16_t>(op), w_[1], w_[0], {w_[2]});
      return true;
    case OpSelect: componentwise(Code::select, 0, w_[1], w_[0], {w_[2], w_[3], w_[4]}); return true;
    case OpAny: case OpAll: over_components(Code::reduce, static_cast<std::uint16_t>(op), false); return true;
    case OpConvertFToS: case OpConvertFToU: case OpConvertSToF: case OpConvertUToF: case OpBitcast:
      componentwise(Code::convert, static_cast<std::uint16_t>(op), w_[1], w_[0], {w_[2]});
      // A bitcast's direction, kept in step_b's place (unused by conversions otherwise): 1 float to integer, 0 integer
      // to float, 2 between integers (int and uint: the same bits).
      p_.code.back().step_b = kind_of(w_[2]) == Kind::floating ? 1 : type(w_[0]).kind == Kind::floating ? 0 : 2;
      return true;
    case OpDot: over_components(Code::dot, 0, true); return true;
    case OpMatrixTimesVector: case OpVectorTimesMatrix: case OpMatrixTimesMatrix: {
      Instr in{Code::matrix, static_cast<std::uint16_t>(op)};
      in.r = allocate(w_[1], w_[0]);
      in.n = type(w_[0]).size;
      in.a = slot(w_[2]);
      in.b = slot(w_[3]);
      const TypeInfo& left = type(type_of_.at(w_[2]));
      const TypeInfo& right = type(type_of_.at(w_[3]));
      // step_a: rows of the left matrix (or the vector's size); step_b: the inner dimension.
      if (op == OpMatrixTimesVector) {
        in.step_a = type(left.elem).size;
        in.step_b = left.count;
      } else if (op == OpVectorTimesMatrix) {
        in.step_a = type(right.elem).size;
        in.step_b = right.count;
      } else {
        in.step_a = type(left.elem).size;
        in.step_b = left.count;
        in.c = right.count;
      }
      emit(in);
      return true;
    }
    case OpExtInst: ext_inst(); return true;
    default: return false;
  }
}

// Branches, returns and discards.
bool Decoder::control(spv::Op op) {
  using namespace spv;
  switch (op) {
    case OpBranch: {
      Instr in{Code::branch};
      emit(in);
      label_ids_.push_back({p_.code.size() - 1, 'a', w_[0]});
      return true;
    }
    case OpBranchConditional: {
      Instr in{Code::branch_if};
      in.a = slot(w_[0]);
      emit(in);
      label_ids_.push_back({p_.code.size() - 1, 'b', w_[1]});
      label_ids_.push_back({p_.code.size() - 1, 'c', w_[2]});
      return true;
    }
    case OpSwitch: {
      Instr in{Code::switch_};
      in.a = slot(w_[0]);
      std::vector<std::uint32_t> cases;
      for (std::uint32_t k = 2; k + 1 < n_; k += 2) {
        cases.push_back(w_[k]);
        cases.push_back(w_[k + 1]);  // a label, resolved at the end
      }
      in.list = list(cases);
      in.list_size = static_cast<std::uint32_t>(cases.size());
      emit(in);
      label_ids_.push_back({p_.code.size() - 1, 'b', w_[1]});
      return true;
    }
    case OpReturn: case OpReturnValue: emit({Code::ret}); return true;
    case OpKill: case OpTerminateInvocation: case OpDemoteToHelperInvocation: case OpUnreachable:
      emit({Code::kill});
      return true;
    default: return false;
  }
}

void Decoder::resolve_blocks() {
  for (const auto& [at, field, label] : label_ids_) {
    Instr& in = p_.code[at];
    (field == 'a' ? in.a : field == 'b' ? in.b : in.c) = block_of_.at(label);
  }
  for (Instr& in : p_.code)
    if (in.code == Code::switch_)
      for (std::uint32_t k = 1; k < in.list_size; k += 2) p_.lists[in.list + k] = block_of_.at(p_.lists[in.list + k]);
  for (const PhiValue& v : pending_phi_values_) p_.blocks[v.block].phis[v.phi].from[v.pair].second = slot(v.value);
  for (Block& b : p_.blocks)
    for (Phi& phi : b.phis)
      for (auto& [parent, value] : phi.from) parent = block_of_.at(parent);
  if (p_.blocks.empty() || !has_output_) fail("internal: main has no body or no result");
}

}  // namespace

Program decode(const std::vector<std::uint32_t>& words, const GlslSpec& spec, const std::string& file) {
  return Decoder(words, spec, file).run();
}

}  // namespace marchcheck::sdf::glsl
