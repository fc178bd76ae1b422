#include "marchcheck/validation/reference.hpp"

#include "marchcheck/validation/certified.hpp"
#include "marchcheck/validation/mesh_reference.hpp"

#include "marchcheck/sdf/interval.hpp"

#include "marchcheck/march/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace marchcheck::validation {

namespace {

using sdf::Node;
using sdf::Op;
using glm::dvec3;

constexpr double kInf = std::numeric_limits<double>::infinity();

Span make_span(double t0, double t1, dvec3 n0, dvec3 n1) { return {t0, t1, n0, n1}; }

// Roots of a t^2 + b t + c, stable form; false when none.
bool quadratic(double a, double b, double c, double& t0, double& t1) {
  if (a == 0) return false;
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return false;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  t0 = q / a;
  t1 = q != 0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

Spans sphere_spans(double r, dvec3 o, dvec3 d) {
  double t0, t1;
  if (!quadratic(glm::dot(d, d), 2 * glm::dot(o, d), glm::dot(o, o) - r * r, t0, t1)) return {};
  return {make_span(t0, t1, glm::normalize(o + d * t0), glm::normalize(o + d * t1))};
}

Spans plane_spans(dvec3 n, double h, dvec3 o, dvec3 d) {
  n = glm::normalize(n);
  const double dn = glm::dot(d, n), on = glm::dot(o, n) + h;
  if (dn == 0) return on < 0 ? Spans{make_span(-kInf, kInf, n, n)} : Spans{};
  const double t = -on / dn;
  return dn < 0 ? Spans{make_span(t, kInf, n, n)} : Spans{make_span(-kInf, t, n, n)};
}

// The slab |x_axis| < half along the ray.
bool slab(double o, double d, double half, double& t0, double& t1) {
  if (d == 0) {
    if (std::abs(o) >= half) return false;
    t0 = -kInf;
    t1 = kInf;
    return true;
  }
  t0 = (-half - o) / d;
  t1 = (half - o) / d;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

Spans box_spans(dvec3 b, dvec3 o, dvec3 d) {
  double lo = -kInf, hi = kInf;
  dvec3 n_lo(0), n_hi(0);
  for (int i = 0; i < 3; ++i) {
    double t0, t1;
    if (!slab(o[i], d[i], b[i], t0, t1)) return {};
    dvec3 axis(0);
    axis[i] = 1;
    if (t0 > lo) {
      lo = t0;
      n_lo = axis * (d[i] > 0 ? -1.0 : 1.0);
    }
    if (t1 < hi) {
      hi = t1;
      n_hi = axis * (d[i] > 0 ? 1.0 : -1.0);
    }
  }
  if (lo >= hi) return {};
  return {make_span(lo, hi, n_lo, n_hi)};
}

// Infinite cylinder about y of radius r.
bool cylinder(double r, dvec3 o, dvec3 d, double& t0, double& t1) {
  const double a = d.x * d.x + d.z * d.z;
  if (a == 0) {
    if (o.x * o.x + o.z * o.z >= r * r) return false;
    t0 = -kInf;
    t1 = kInf;
    return true;
  }
  return quadratic(a, 2 * (o.x * d.x + o.z * d.z), o.x * o.x + o.z * o.z - r * r, t0, t1);
}

Spans capped_cylinder_spans(double h, double r, dvec3 o, dvec3 d) {
  double c0, c1, s0, s1;
  if (!cylinder(r, o, d, c0, c1) || !slab(o.y, d.y, h, s0, s1)) return {};
  const double t0 = std::max(c0, s0), t1 = std::min(c1, s1);
  if (t0 >= t1) return {};
  auto normal = [&](double t, bool side) {
    const dvec3 p = o + d * t;
    return side ? glm::normalize(dvec3(p.x, 0, p.z)) : dvec3(0, p.y > 0 ? 1 : -1, 0);
  };
  return {make_span(t0, t1, normal(t0, c0 >= s0), normal(t1, c1 <= s1))};
}

Spans unite(const Spans& a, const Spans& b);

Spans capsule_spans(dvec3 a, dvec3 b, double r, dvec3 o, dvec3 d) {
  // Two end spheres and the cylinder between them, in a frame whose y axis runs from a to b.
  const dvec3 axis = b - a;
  const double len = glm::length(axis);
  const dvec3 y = axis / len;
  const dvec3 x = glm::normalize(glm::cross(y, std::abs(y.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  const dvec3 z = glm::cross(x, y);
  const dvec3 centre = (a + b) * 0.5;
  auto to_local = [&](dvec3 v) { return dvec3(glm::dot(v, x), glm::dot(v, y), glm::dot(v, z)); };
  Spans body = capped_cylinder_spans(len / 2, r, to_local(o - centre), to_local(d));
  for (auto& s : body) {
    s.n0 = x * s.n0.x + y * s.n0.y + z * s.n0.z;
    s.n1 = x * s.n1.x + y * s.n1.y + z * s.n1.z;
  }
  return unite(unite(body, sphere_spans(r, o - a, d)), sphere_spans(r, o - b, d));
}

// Ray-torus (major R about y, minor r): the quartic along the ray, its roots bracketed on a fine sampling of
// the ray's stretch inside the bounding box and polished by bisection and Newton.
Spans torus_spans(double big, double small, dvec3 o, dvec3 d) {
  double t_lo, t_hi;
  const Spans bound = box_spans(dvec3(big + small, small, big + small) * 1.0001, o, d);
  if (bound.empty()) return {};
  t_lo = bound[0].t0;
  t_hi = bound[0].t1;
  auto g = [&](double t) {
    const dvec3 p = o + d * t;
    const double k = glm::dot(p, p) + big * big - small * small;
    return k * k - 4 * big * big * (p.x * p.x + p.z * p.z);
  };
  const int n = 4096;
  std::vector<double> roots;
  double prev_t = t_lo, prev = g(t_lo);
  for (int i = 1; i <= n; ++i) {
    const double t = t_lo + (t_hi - t_lo) * i / n, v = g(t);
    if ((prev < 0) != (v < 0)) {
      double a = prev_t, b = t;
      for (int it = 0; it < 200 && b - a > 1e-15 * (1 + std::abs(a)); ++it) {
        const double m = 0.5 * (a + b);
        ((g(m) < 0) == (prev < 0) ? a : b) = m;
      }
      roots.push_back(0.5 * (a + b));
    }
    prev_t = t;
    prev = v;
  }
  auto normal = [&](double t) {
    const dvec3 p = o + d * t;
    const dvec3 ring = big * glm::normalize(dvec3(p.x, 0, p.z));
    return glm::normalize(p - ring);
  };
  Spans out;
  const bool starts_inside = g(t_lo) < 0;
  size_t i = 0;
  if (starts_inside) {
    out.push_back(make_span(t_lo, roots.empty() ? t_hi : roots[0], normal(t_lo), roots.empty() ? normal(t_hi) : normal(roots[0])));
    i = 1;
  }
  for (; i + 1 < roots.size(); i += 2) out.push_back(make_span(roots[i], roots[i + 1], normal(roots[i]), normal(roots[i + 1])));
  if (i < roots.size()) out.push_back(make_span(roots[i], t_hi, normal(roots[i]), normal(t_hi)));
  return out;
}

Spans unite(const Spans& a, const Spans& b) {
  Spans all = a;
  all.insert(all.end(), b.begin(), b.end());
  std::sort(all.begin(), all.end(), [](const Span& x, const Span& y) { return x.t0 < y.t0; });
  Spans out;
  for (const auto& s : all) {
    if (!out.empty() && s.t0 <= out.back().t1) {
      if (s.t1 > out.back().t1) {
        out.back().t1 = s.t1;
        out.back().n1 = s.n1;
      }
    } else {
      out.push_back(s);
    }
  }
  return out;
}

Spans intersect(const Spans& a, const Spans& b) {
  Spans out;
  for (const auto& x : a)
    for (const auto& y : b) {
      const double t0 = std::max(x.t0, y.t0), t1 = std::min(x.t1, y.t1);
      if (t0 < t1) out.push_back(make_span(t0, t1, x.t0 >= y.t0 ? x.n0 : y.n0, x.t1 <= y.t1 ? x.n1 : y.n1));
    }
  std::sort(out.begin(), out.end(), [](const Span& p, const Span& q) { return p.t0 < q.t0; });
  return out;
}

// a minus b: a intersected with the complement of b, whose spans' surfaces face the other way.
Spans subtract(const Spans& a, const Spans& b) {
  Spans complement;
  double t = -kInf;
  dvec3 n(0);
  for (const auto& s : b) {
    if (s.t0 > t) complement.push_back(make_span(t, s.t0, n, -s.n0));
    t = s.t1;
    n = -s.n1;
  }
  if (t < kInf) complement.push_back(make_span(t, kInf, n, n));
  return intersect(a, complement);
}

bool is_rigid(const glm::dmat3& a) {
  const glm::dmat3 should_be_identity = glm::transpose(a) * a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::abs(should_be_identity[i][j] - (i == j ? 1.0 : 0.0)) > 1e-9) return false;
  return true;
}

// The motion of a rotate, affine or animate node.
sdf::ModelTransform motion(const Node& n, double time) {
  if (n.op != Op::rotate) return sdf::model_transform(n, time);
  return {sdf::rotation_matrix(n.vec3("axis"), n.scalar("angle_deg") * std::numbers::pi / 180), {}};
}

Spans cast(const Node& n, dvec3 o, dvec3 d, double time, const MeshReferences& meshes) {
  switch (n.op) {
    case Op::sphere: return sphere_spans(n.scalar("radius"), o, d);
    case Op::plane: return plane_spans(n.vec3("normal"), n.scalar("offset"), o, d);
    case Op::box: return box_spans(n.vec3("half_size"), o, d);
    case Op::torus: return torus_spans(n.scalar("major"), n.scalar("minor"), o, d);
    case Op::capsule: return capsule_spans(n.vec3("a"), n.vec3("b"), n.scalar("radius"), o, d);
    case Op::capped_cylinder: return capped_cylinder_spans(n.scalar("half_height"), n.scalar("radius"), o, d);
    case Op::mesh: return meshes.at(n.mesh.get())->spans(o, d);
    case Op::union_: {
      Spans out;
      for (const auto& c : n.children) out = unite(out, cast(c, o, d, time, meshes));
      return out;
    }
    case Op::intersection: {
      Spans out = cast(n.children[0], o, d, time, meshes);
      for (size_t i = 1; i < n.children.size(); ++i) out = intersect(out, cast(n.children[i], o, d, time, meshes));
      return out;
    }
    case Op::subtraction: return subtract(cast(n.children[0], o, d, time, meshes), cast(n.children[1], o, d, time, meshes));
    case Op::translate: return cast(n.children[0], o - n.vec3("offset"), d, time, meshes);
    case Op::scale: {
      const double s = n.scalar("factor");
      return cast(n.children[0], o / s, d / s, time, meshes);  // t is unchanged: o + t d scales as a whole
    }
    case Op::rotate:
    case Op::affine:
    case Op::animate: {
      const sdf::ModelTransform m = motion(n, time);
      const glm::dmat3 inv = glm::inverse(m.a);
      Spans out = cast(n.children[0], inv * (o - m.t), inv * d, time, meshes);
      for (auto& s : out) {
        s.n0 = m.a * s.n0;
        s.n1 = m.a * s.n1;
      }
      return out;
    }
    default: return {};
  }
}

// The Mandelbulb under a chain of rigid motions and uniform scales, or nullptr.
const Node* placed_mandelbulb(const Node& n, double time) {
  switch (n.op) {
    case Op::mandelbulb: return &n;
    case Op::affine:
    case Op::animate:
      if (!is_rigid(sdf::model_transform(n, time).a)) return nullptr;
      [[fallthrough]];
    case Op::translate:
    case Op::rotate:
    case Op::scale: return placed_mandelbulb(n.children[0], time);
    default: return nullptr;
  }
}

// The ray taken into the set's frame through the chain placed_mandelbulb accepted; t is the same in every frame.
ReferenceHit placed_first_hit(const Node& n, const EscapeTimeSet& set, dvec3 o, dvec3 d, double t_max, double time) {
  switch (n.op) {
    case Op::translate: return placed_first_hit(n.children[0], set, o - n.vec3("offset"), d, t_max, time);
    case Op::scale: {
      const double s = n.scalar("factor");
      return placed_first_hit(n.children[0], set, o / s, d / s, t_max, time);
    }
    case Op::rotate:
    case Op::affine:
    case Op::animate: {
      const sdf::ModelTransform m = motion(n, time);
      const glm::dmat3 inv = glm::transpose(m.a);  // rigid
      ReferenceHit h = placed_first_hit(n.children[0], set, inv * (o - m.t), inv * d, t_max, time);
      h.normal = m.a * h.normal;
      return h;
    }
    default: {
      const double len = glm::length(d);  // the set samples along a unit direction
      ReferenceHit h = set.first_hit(o, d / len, t_max * len);
      h.t /= len;
      return h;
    }
  }
}

std::optional<EscapeTimeSet> escape_set_of(const Node& node, double time) {
  const Node* bulb = placed_mandelbulb(node, time);
  return bulb ? std::optional<EscapeTimeSet>(*bulb) : std::nullopt;
}

// A union the exact caster cannot take whole but each of whose parts one reference can cast (a Mandelbulb
// beside exact shapes): the parts, whose nearest first hit is the union's.
std::vector<Reference> referenced_union_parts(const Node& n, double time) {
  if (n.op != Op::union_ || exact_supported(n, time)) return {};
  std::vector<Reference> parts;
  for (const auto& c : n.children) {
    if (!exact_supported(c, time) && !placed_mandelbulb(c, time)) return {};
    parts.emplace_back(c, time);
  }
  return parts;
}

}  // namespace

bool exact_supported(const Node& n, double time) {
  switch (n.op) {
    case Op::sphere:
    case Op::plane:
    case Op::box:
    case Op::torus:
    case Op::capsule:
    case Op::capped_cylinder: return true;
    case Op::mesh: return n.mesh != nullptr;
    case Op::affine:
    case Op::animate:
      if (!is_rigid(sdf::model_transform(n, time).a)) return false;
      [[fallthrough]];
    case Op::union_:
    case Op::intersection:
    case Op::subtraction:
    case Op::translate:
    case Op::rotate:
    case Op::scale:
      return std::all_of(n.children.begin(), n.children.end(), [&](const Node& c) { return exact_supported(c, time); });
    default: return false;
  }
}

MeshReferences mesh_references(const Node& node) {
  MeshReferences out;
  if (node.op == Op::mesh && node.mesh)
    out[node.mesh.get()] = std::make_shared<const MeshReference>(node.mesh->mesh(), node.mesh->report());
  for (const auto& c : node.children) out.merge(mesh_references(c));
  return out;
}

Spans cast_exact(const Node& node, dvec3 origin, dvec3 direction, double time, const MeshReferences& meshes) {
  return cast(node, origin, direction, time, meshes);
}

Reference::Reference(const Node& node, double time)
    : Reference(node, time, sdf::derive_info(node, time).lipschitz) {}

Reference::Reference(const Node& node, double time, double declared_lipschitz)
    : node_(node), time_(time), meshes_(mesh_references(node)), exact_(exact_supported(node, time)),
      escape_set_(escape_set_of(node, time)),
      parts_(referenced_union_parts(node, time)),
      tape_(sdf::compile(node, time)),
      lipschitz_(declared_lipschitz),
      certified_(!exact_ && !escape_set_ && parts_.empty() && sdf::interval_supported(tape_)) {}

ReferenceKind Reference::kind() const {
  if (exact_) return ReferenceKind::exact;
  if (escape_set_) return ReferenceKind::escape_time;
  if (!parts_.empty()) return ReferenceKind::parts;
  return certified_ ? ReferenceKind::certified : ReferenceKind::numerical;
}

std::string Reference::judged_by() const {
  switch (kind()) {
    case ReferenceKind::exact: return "exact";
    case ReferenceKind::escape_time: return "escape-time set";
    case ReferenceKind::certified: return "certified";
    case ReferenceKind::numerical: return "numerical";
    case ReferenceKind::parts: break;
  }
  std::string out;
  for (const auto& part : parts_) {
    const std::string name = part.judged_by();
    if (out.find(name) == std::string::npos) out += (out.empty() ? "" : " + ") + name;
  }
  return out;
}

double Reference::t_error_bound(double t) const {
  if (exact_) return 0;
  return certified_ ? kCertifiedWidth * (1 + t) : march::tolerance::kReferenceBisection;
}

ReferenceHit Reference::first_hit(dvec3 o, dvec3 d, double t_max) const {
  ReferenceHit out;
  if (exact_) {
    for (const auto& s : cast(node_, o, d, time_, meshes_)) {
      if (s.t1 <= 0) continue;
      if (s.t0 <= 0) {
        out.inside = true;
        return out;
      }
      if (s.t0 > t_max) return out;
      out.hit = true;
      out.t = s.t0;
      out.normal = glm::normalize(s.n0);
      return out;
    }
    return out;
  }
  if (escape_set_) return placed_first_hit(node_, *escape_set_, o, d, t_max, time_);
  if (!parts_.empty()) {
    ReferenceHit nearest;
    for (const auto& part : parts_) {
      const ReferenceHit h = part.first_hit(o, d, t_max);
      if (h.inside) return h;
      if (h.hit && (!nearest.hit || h.t < nearest.t)) nearest = h;
    }
    return nearest;
  }
  if (!certified_) return numerical_first_hit(o, d, t_max);
  const CertifiedHit c = certified_first_hit(tape_, o, d, t_max);
  switch (c.verdict) {
    case CertifiedHit::Verdict::hit:
      out.hit = c.t <= t_max;
      out.t = c.t;
      out.normal = c.normal;
      return out;
    case CertifiedHit::Verdict::inside: out.inside = true; return out;
    case CertifiedHit::Verdict::miss: return out;
    case CertifiedHit::Verdict::undecidable: break;
  }
  out = numerical_first_hit(o, d, t_max);
  out.undecided = true;
  return out;
}

ReferenceHit Reference::numerical_first_hit(dvec3 o, dvec3 d, double t_max) const {
  ReferenceHit out;
  // Steps of f / L can never jump a surface when L bounds the slope; every sign change is bisected.
  auto f = [&](double t) { return sdf::evaluate(tape_, o + d * t); };
  double t = 0, v = f(0);
  if (v < 0) {
    out.inside = true;
    return out;
  }
  for (int i = 0; i < 200000 && t < t_max; ++i) {
    const double step = std::max(v / lipschitz_, march::tolerance::reference_min_step(t));
    const double next = t + step, w = f(next);
    if (w < march::tolerance::kReferenceTouch) {
      double a = t, b = next;
      for (int it = 0; it < 200 && b - a > march::tolerance::kReferenceBisection; ++it) {
        const double m = 0.5 * (a + b);
        (f(m) < 0 ? b : a) = m;
      }
      out.hit = b <= t_max;
      out.t = 0.5 * (a + b);
      out.normal = field_normal(tape_, o + d * out.t, d);
      return out;
    }
    t = next;
    v = w;
  }
  out.unknown = t < t_max;
  return out;
}

void probe_nearest(const Reference& ref, dvec3 p, std::initializer_list<dvec3> likely, NearestSurface& near) {
  auto probe = [&](dvec3 dir) {
    if (!(glm::length(dir) > 0)) return;
    dir = glm::normalize(dir);
    const ReferenceHit h = ref.first_hit(p, dir, std::isfinite(near.distance) ? near.distance : 1e9);
    near.inside = near.inside || h.inside;
    if (h.hit && h.t < near.distance) {
      near.distance = h.t;
      near.toward = dir;
    }
  };
  for (const dvec3 dir : likely) probe(dir);
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c)
        if (a != 0 || b != 0 || c != 0) probe(dvec3(a, b, c));
}

}  // namespace marchcheck::validation
