// Surface normals from the field: finite differences (central, forward, tetrahedral) and forward-mode
// automatic differentiation through the same templated field code (analytic).
#pragma once

#include "marchcheck/sdf/scalar.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <glm/glm.hpp>

#include <cmath>

namespace marchcheck::march {

using sdf::NormalMethod;

template <class T>
struct NormalResult {
  glm::vec<3, T> n{0};  // unit length; zero when the gradient vanishes or is not finite
  int evals = 0;
};

namespace detail {
template <class T>
inline glm::vec<3, T> unit_or_zero(glm::vec<3, T> g) {
  const T len = std::sqrt(g.x * g.x + g.y * g.y + g.z * g.z);
  if (!(len > 0) || !std::isfinite(len)) return glm::vec<3, T>(0);
  return g / len;
}
}  // namespace detail

// Central differences, for any field callable with glm::vec<3, T>.
template <class T, class F>
NormalResult<T> central_normal(const F& f, glm::vec<3, T> p, T eps) {
  using V = glm::vec<3, T>;
  const V g(f(p + V(eps, 0, 0)) - f(p - V(eps, 0, 0)), f(p + V(0, eps, 0)) - f(p - V(0, eps, 0)),
            f(p + V(0, 0, eps)) - f(p - V(0, 0, eps)));
  return {detail::unit_or_zero(g), 6};
}

// f must be callable with glm::vec<3, T> (and with glm::vec<3, sdf::Dual<T>> for the analytic method).
template <class T, class F>
NormalResult<T> estimate_normal(const F& f, glm::vec<3, T> p, NormalMethod method, T eps) {
  using V = glm::vec<3, T>;
  switch (method) {
    case NormalMethod::central: return central_normal(f, p, eps);
    case NormalMethod::forward: {
      const T f0 = f(p);
      const V g(f(p + V(eps, 0, 0)) - f0, f(p + V(0, eps, 0)) - f0, f(p + V(0, 0, eps)) - f0);
      return {detail::unit_or_zero(g), 4};
    }
    case NormalMethod::tetra: {
      const V k0(1, -1, -1), k1(-1, -1, 1), k2(-1, 1, -1), k3(1, 1, 1);
      const V g = k0 * f(p + k0 * eps) + k1 * f(p + k1 * eps) + k2 * f(p + k2 * eps) + k3 * f(p + k3 * eps);
      return {detail::unit_or_zero(g), 4};
    }
    case NormalMethod::analytic: {
      using D = sdf::Dual<T>;
      const glm::vec<3, D> q(D(p.x, V(1, 0, 0)), D(p.y, V(0, 1, 0)), D(p.z, V(0, 0, 1)));
      return {detail::unit_or_zero(f(q).d), 1};
    }
  }
  return {};
}

}  // namespace marchcheck::march
