// The GLSL field's SPIR-V, compiled and decoded into a flat program over slots, run in any of the tape's
// scalars. Internal to sdf.
#pragma once

#include "marchcheck/sdf/glsl_field.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace marchcheck::sdf::glsl {

// The shader around the user's source (its `function` at the input point, the distance out), compiled, every
// function inlined into main and variables made SSA values. Throws GlslError "file:line: message".
std::vector<std::uint32_t> compile_field(const std::string& source, const std::string& file,
                                         const std::string& function);

// Every value lives in slots: one per scalar component, each with a number (f) and an integer (i) cell, so a
// struct of floats and ints is one range. Pointers are integers: the first slot they point at.
enum class Code : std::uint16_t {
  gather,      // r[k] = s[src k] for k < n (copies, extracts, shuffles, constructions, inserts)
  extract_at,  // r = s[a + i[b]]: a vector's component at a run-time index
  insert_at,   // r = s[a..a + n), then r[i[b]] = s[c]
  load,        // r[k] = s[i[a] + k]
  store,       // s[i[a] + k] = s[b + k]
  access,      // i[r] = i[a] + sum of constant offset and index_k * stride_k
  f_unary,     // r[k] = fn(s[a + k]): ext = which
  f_binary,    // r[k] = fn(s[a + k * step_a], s[b + k * step_b])
  f_ternary,   // r[k] = fn(a, b, c), each with its step
  i_unary,
  i_binary,
  compare,     // i[r + k] = (f or i) comparison
  select,      // r[k] = i[cond + k * step] ? a[k] : b[k]
  convert,     // between int and float kinds, and bitcasts
  dot,         // r = sum a[k] b[k]
  matrix,      // products of matrices and vectors: ext = which
  vector_fn,   // length, distance, normalize, cross, reflect, refract, faceforward
  reduce,      // any, all
  branch,      // to block a
  branch_if,   // to block b if i[a] else block c
  switch_,     // on i[a]: default block b, then (literal, block) pairs
  ret,         // the function ends
  kill,        // discard: the field is NaN
};

struct Instr {
  Code code;
  std::uint16_t ext = 0;   // which function, comparison or conversion
  std::uint32_t n = 1;     // components of the result
  std::uint32_t r = 0;     // first slot of the result
  std::uint32_t a = 0, b = 0, c = 0;
  std::uint32_t step_a = 1, step_b = 1, step_c = 1;  // 0 broadcasts a scalar over the components
  std::uint32_t list = 0, list_size = 0;              // into Program::lists
};

struct Phi {
  std::uint32_t r, n;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> from;  // (parent block, value slot)
};

struct Block {
  std::uint32_t first;  // instruction index
  std::vector<Phi> phis;
};

enum class Kind : std::uint8_t { floating, integer };

struct Program {
  std::uint64_t id = 0;  // unique per decoded program: evaluators keep their constants per thread by it
  std::vector<Instr> code;
  std::vector<std::uint32_t> lists;
  std::vector<Block> blocks;
  std::uint32_t slots = 0;
  // Constant slots and their values, set once per thread and program.
  std::vector<std::uint32_t> constant_slots;
  std::vector<double> constant_f;
  std::vector<std::int64_t> constant_i;
  std::uint32_t input = 0, output = 0;  // storage slots of the point (3) and of the result (its .x first)
  bool has_input = false;
  struct UniformSlot {
    std::uint32_t slot, n;
    std::vector<double> value;
    Kind kind;
  };
  std::vector<UniformSlot> uniforms;
};

// Decodes the optimised SPIR-V of compile_field; uniforms get the spec's values. Throws GlslError naming what it
// does not run.
Program decode(const std::vector<std::uint32_t>& words, const GlslSpec& spec, const std::string& file);

}  // namespace marchcheck::sdf::glsl
