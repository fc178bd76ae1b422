// A user's shader in the form Shadertoy tutorials teach: a map, a marcher, a normal. rayMarch is right; each
// other marcher has one known bug, and marchcheck's tests expect each caught on the GL driver.
#define MAX_STEPS 64
#define MAX_DIST 30.0
#define SURF_DIST 0.001

float sdBox(vec3 p, vec3 b) {
  vec3 q = abs(p) - b;
  return length(max(q, 0.0)) + min(max(q.x, max(q.y, q.z)), 0.0);
}

// A sphere resting on a block: exact outside both, thick enough that steps of 1.2 f do not tunnel through.
float map(vec3 p) {
  float sphere = length(p - vec3(0.0, 1.0, 0.0)) - 1.0;
  float slab = sdBox(p - vec3(0.0, -1.0, 0.0), vec3(3.0, 1.0, 3.0));
  return min(sphere, slab);
}

float rayMarch(vec3 ro, vec3 rd) {
  float t = 0.0;
  for (int i = 0; i < MAX_STEPS; i++) {
    float d = map(ro + rd * t);
    if (abs(d) < SURF_DIST) break;
    t += d;
    if (t > MAX_DIST) break;
  }
  return t;
}

// Bug: steps along a direction that is not unit length (a camera's vec3(uv, 1.0) without normalize), so t
// is not the distance.
float rayMarchUnnormalised(vec3 ro, vec3 rd) {
  vec3 dir = rd * 1.25;
  float t = 0.0;
  for (int i = 0; i < MAX_STEPS; i++) {
    float d = map(ro + dir * t);
    if (abs(d) < SURF_DIST) break;
    t += d;
    if (t > MAX_DIST) break;
  }
  return t;
}

// Bug: one step more than MAX_STEPS (<= for <).
float rayMarchOffByOne(vec3 ro, vec3 rd) {
  float t = 0.0;
  for (int i = 0; i <= MAX_STEPS; i++) {
    float d = map(ro + rd * t);
    if (abs(d) < SURF_DIST) break;
    t += d;
    if (t > MAX_DIST) break;
  }
  return t;
}

// Bug: the hit test on f, not |f|: over-relaxed steps (1.2 f) that land inside the solid stop there.
float rayMarchSignedHit(vec3 ro, vec3 rd) {
  float t = 0.0;
  for (int i = 0; i < MAX_STEPS; i++) {
    float d = map(ro + rd * t);
    if (d < SURF_DIST) break;
    t += 1.2 * d;
    if (t > MAX_DIST) break;
  }
  return t;
}

// The same over-relaxed steps with the hit test on |f|: a step that lands inside comes back.
float rayMarchRelaxed(vec3 ro, vec3 rd) {
  float t = 0.0;
  for (int i = 0; i < MAX_STEPS; i++) {
    float d = map(ro + rd * t);
    if (abs(d) < SURF_DIST) break;
    t += 1.2 * d;
    if (t > MAX_DIST) break;
  }
  return t;
}

vec3 calcNormal(vec3 p) {
  vec2 e = vec2(0.0005, 0.0);
  return normalize(vec3(map(p + e.xyy) - map(p - e.xyy), map(p + e.yxy) - map(p - e.yxy),
                        map(p + e.yyx) - map(p - e.yyx)));
}

void mainImage(out vec4 fragColor, in vec2 fragCoord) {
  vec2 uv = (fragCoord - 0.5 * iResolution.xy) / iResolution.y;
  vec3 ro = vec3(0.0, 1.5, -5.0);
  vec3 rd = normalize(vec3(uv, 1.0));
  float t = rayMarch(ro, rd);
  vec3 col = vec3(0.0);
  if (t < MAX_DIST) col = vec3(0.5 + 0.5 * calcNormal(ro + rd * t).y);
  fragColor = vec4(col, 1.0);
}
