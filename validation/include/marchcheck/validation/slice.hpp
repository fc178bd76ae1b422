// The field made visible: the standard SDF debugging picture of a plane through the scene. Left, the distance as
// colour bands (warm outside, cool inside, a band per tenth of the slice's width, the zero contour white);
// right, |grad f| - 1 (grey where the field is a distance, red steeper, blue flatter), with the squares where
// the certified bound on |grad f| (interval arithmetic, certified.hpp) exceeds the declared Lipschitz constant
// outlined in yellow: where a marcher stepping f / L can step through the surface.
#pragma once

#include "marchcheck/march/render.hpp"
#include "marchcheck/sdf/scene.hpp"

#include <string>

namespace marchcheck::validation {

struct SlicePlane {
  int axis = 1;  // 0 x, 1 y, 2 z: the plane axis = value
  double value = 0;
};

// "y=0.5" (x, y or z, then a number). Throws std::invalid_argument saying what is wrong.
SlicePlane parse_plane(const std::string& text);

// The plane through the scene's region of interest: the horizontal plane (y) through the camera's target.
SlicePlane default_plane(const sdf::Scene& scene);

struct Slice {
  march::Image image;  // the two panels side by side: 2 width x height, RGB
  // The square of the plane shown: centre and half side, in the plane's two other axes.
  double centre_u = 0, centre_v = 0, half = 1;
  int cells = 0, cells_over = 0;  // certified squares, and those whose bound exceeds the declared constant
  double steepest_bound = 0;      // the largest certified bound over a square
  bool certified = false;         // the field has interval rules (else the right panel has no outlines)
};

// The plane over a square around the camera's target, as wide as the camera is far from it, each panel
// width x height pixels.
Slice slice(const sdf::Scene& scene, SlicePlane plane, int width, int height);

}  // namespace marchcheck::validation
