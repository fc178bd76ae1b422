// Camera-relative marching: the scene rewritten about the eye so a far scene keeps float precision near the
// camera. Marching f(q + eye) with q small loses nothing only if eye is folded into the scene's own offsets in
// double before anything is rounded to float; that is what this rewrite does.
#pragma once

#include "marchcheck/sdf/node.hpp"
#include "marchcheck/sdf/scene.hpp"
#include "marchcheck/sdf/tape.hpp"

#include <glm/glm.hpp>

namespace marchcheck::march {

// The field g(q) = f(q + eye): translations absorb -eye (subtracted in double), unions, intersections and
// subtractions pass it to their children; any other node is wrapped whole (correct, but without the gain).
sdf::Node camera_relative(const sdf::Node& root, glm::dvec3 eye);

// What the scene's march measures positions from: its camera's eye where it declares coordinates camera, else the
// world's origin. A world point p is the march's p - march_origin, subtracted in double.
glm::dvec3 march_origin(const sdf::Scene& scene);

// The scene's tape (sdf::compile(scene): its time and precision) in coordinates measured from origin.
sdf::Tape march_tape(const sdf::Scene& scene, glm::dvec3 origin);

}  // namespace marchcheck::march
