// The hard-case battery's shared pieces. Each family's file in this folder defines its cases and registers each
// (name, what it checks, criterion, variants, body) beside its body; stability.cpp adds the families in battery
// order and runs the cases.
#pragma once

#include "marchcheck/march/marcher.hpp"
#include "marchcheck/march/render.hpp"
#include "marchcheck/march/tolerances.hpp"
#include "marchcheck/validation/stability.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace marchcheck::validation::stability {

using glm::dvec3;
using glm::vec3;
using march::MarchSettings;
using march::Outcome;
using march::TapeField;

inline constexpr double kPi = std::numbers::pi;

// What a case fills in: its numbers, the clauses of its criterion it checked, and the first reason one failed.
struct Run {
  std::map<std::string, double>& m;
  const std::string& variant;  // the broken variant to run, "" for the marchers as they are
  std::vector<std::string> clauses, failed;
  std::string why;
  bool as(std::string_view v) const { return variant == v; }
  bool naive() const { return as("naive"); }
  // One clause of the criterion: each has a variant of its own that fails it alone.
  void require(const std::string& clause, bool condition, const std::string& reason) {
    if (std::find(clauses.begin(), clauses.end(), clause) == clauses.end()) clauses.push_back(clause);
    check(clause, condition, reason);
  }
  // What the case needs in order to test anything at all (not a clause: no variant of its own).
  void needs(const std::string& what, bool condition, const std::string& reason) { check("needs." + what, condition, reason); }
  bool ok() const { return failed.empty(); }

 private:
  void check(const std::string& id, bool condition, const std::string& reason) {
    if (condition || std::find(failed.begin(), failed.end(), id) != failed.end()) return;
    if (failed.empty()) why = reason;
    failed.push_back(id);
  }
};

struct Entry {
  std::string name, checks, criterion;
  std::vector<StabilityVariant> variants;  // the naive one first
  std::function<void(Run&, const StabilityOptions&)> run;
};

using Variants = std::vector<StabilityVariant>;

// The cases in battery order, as the families add them.
struct Battery {
  std::vector<Entry> entries;
  void add(std::string name, std::string checks, std::string criterion, Variants variants,
           std::function<void(Run&, const StabilityOptions&)> run) {
    entries.push_back({std::move(name), std::move(checks), std::move(criterion), std::move(variants), std::move(run)});
  }
};

// a followed by more: a case's naive variant, then variants it shares with other cases.
Variants plus(Variants a, const Variants& more);

// v to 3 significant digits, for the texts.
std::string num(double v);

// "1e<k>", k the decimal logarithm of v rounded: v's decade, in case and metric names.
std::string decade(double v);

// The angle between a and b in degrees.
double angle_deg(dvec3 a, dvec3 b);

// The loop most shader code writes: no input guard, no finite check, no inside outcome, and a loop that ran
// out of steps read as a hit (its t is below max_dist). The naive variant of the degenerate-input cases.
template <class T, class F>
march::RayRecord<T> naive_march(const F& f, glm::vec<3, T> o, glm::vec<3, T> d, const MarchSettings& s) {
  march::RayRecord<T> r;
  T t = 0;
  for (int i = 0; i < s.max_steps; ++i) {
    const T v = f(o + d * t);
    ++r.steps;
    ++r.evals;
    if (v < T(s.hit_eps)) break;
    t += v;
    if (t > T(s.max_dist)) {
      r.outcome = Outcome::miss_far;
      r.t = t;
      return r;
    }
  }
  r.outcome = Outcome::hit;
  r.t = t;
  return r;
}

// Each family adds its cases; make_battery calls these in this order, which is the battery's.
void add_grazing_and_start_cases(Battery& b);
void add_shadow_cases(Battery& b);
void add_far_and_scale_cases(Battery& b);
void add_thin_cases(Battery& b);
void add_normal_cases(Battery& b);
void add_lipschitz_and_mandelbulb_cases(Battery& b);
void add_input_cases(Battery& b);
void add_mesh_cases(Battery& b);

}  // namespace marchcheck::validation::stability
