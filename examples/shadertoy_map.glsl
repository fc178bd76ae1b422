// A map as Shadertoy shaders write it: a rotated box and a sphere, smoothly joined, on a slab,
// the material in .y. The main job's report renders and judges it beside the built-in scenes. SURF_DIST is the
// hit threshold its marcher would use, and marchcheck's too.
#define SURF_DIST 0.001

float sdBox(vec3 p, vec3 b) {
  vec3 q = abs(p) - b;
  return length(max(q, 0.0)) + min(max(q.x, max(q.y, q.z)), 0.0);
}

float smin(float a, float b, float k) {
  float h = clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
  return mix(b, a, h) - k * h * (1.0 - h);
}

vec2 map(vec3 p) {
  vec3 q = p - vec3(0.0, 0.6, 0.0);
  q.xz *= mat2(0.8, -0.6, 0.6, 0.8);
  float shape = smin(sdBox(q, vec3(0.45)), length(p - vec3(0.7, 0.9, 0.2)) - 0.35, 0.1);
  float floor_ = sdBox(p - vec3(0.0, -0.1, 0.0), vec3(1.6, 0.1, 1.6));
  return shape < floor_ ? vec2(shape, 1.0) : vec2(floor_, 2.0);
}
