// Camera-relative marching: the scene rewritten about the eye so a far scene keeps float precision near the
// camera. Marching f(q + eye) with q small loses nothing only if eye is folded into the scene's own offsets in
// double before anything is rounded to float; that is what this rewrite does.
#pragma once

#include "marchcheck/sdf/node.hpp"

#include <glm/glm.hpp>

namespace marchcheck::march {

// The field g(q) = f(q + eye): translations absorb -eye (subtracted in double), unions, intersections and
// subtractions pass it to their children; any other node is wrapped whole (correct, but without the gain).
sdf::Node camera_relative(const sdf::Node& root, glm::dvec3 eye);

}  // namespace marchcheck::march
