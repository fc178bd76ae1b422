// A map() written the way Shadertoy code is: helpers, an overload, a #define, a const global, a struct, a for
// loop with break, an inout parameter, compound swizzle assignments and Shadertoy's iTime. Written for
// marchcheck's tests: a box frame of spheres and boxes above a rounded slab, each shape exact, so the union is a
// bound; twisted by iTime, which the scene leaves at 0.
#define SPHERE_RADIUS 0.35
const float kSpacing = 0.9;

struct Hit {
  float d;
  float material;
};

float sdSphere(vec3 p, float r) { return length(p) - r; }

float sdBox(vec3 p, vec3 b) {
  vec3 q = abs(p) - b;
  return length(max(q, 0.0)) + min(max(q.x, max(q.y, q.z)), 0.0);
}

float sdBox(vec2 p, vec2 b) {  // the overload: a 2D box
  vec2 d = abs(p) - b;
  return length(max(d, 0.0)) + min(max(d.x, d.y), 0.0);
}

void rotateXZ(inout vec3 p, float angle) {
  float c = cos(angle), s = sin(angle);
  p.xz *= mat2(c, -s, s, c);
}

Hit closer(Hit a, Hit b) { return a.d < b.d ? a : b; }

vec2 map(vec3 p) {
  vec3 q = p;
  rotateXZ(q, iTime);
  Hit h = Hit(1e9, 0.0);
  for (int i = 0; i < 16; ++i) {
    if (i == 3) break;  // three shapes along x
    vec3 c = q - vec3(float(i - 1) * kSpacing, 0.0, 0.0);
    h = closer(h, Hit(i == 1 ? sdBox(c, vec3(0.3)) : sdSphere(c, SPHERE_RADIUS), float(i)));
  }
  vec3 s = p;
  s.y += 0.75;
  s.xz -= vec2(0.1, 0.0);
  float slab = max(sdBox(s.xz, vec2(1.6, 0.8)), abs(s.y) - 0.1);
  return vec2(closer(h, Hit(slab, 3.0)).d, h.material);
}
