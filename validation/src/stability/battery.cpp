#include "battery.hpp"

#include <cmath>
#include <sstream>

namespace marchcheck::validation::stability {

Variants plus(Variants a, const Variants& more) {
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

std::string num(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

std::string decade(double v) {
  return "1e" + std::to_string(static_cast<int>(std::lround(std::log10(v))));
}

double angle_deg(dvec3 a, dvec3 b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180 / kPi;
}

}  // namespace marchcheck::validation::stability
