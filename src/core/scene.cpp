// scene.cpp - building a scene's fixed-size arrays.
#include "scene.h"

namespace {

// Scene::lightFX.. for light l and bound slot i.
void light_terms(Scene& s, int l, int i) {
  Vec3 p = s.lights[l].pos;
  float fx = p.x - s.boundX[i], fy = p.y - s.boundY[i], fz = p.z - s.boundZ[i];
  s.lightFX[l][i] = fx;
  s.lightFY[l][i] = fy;
  s.lightFZ[l][i] = fz;
  s.lightC[l][i] = fx * fx + fy * fy + fz * fz - s.boundR2[i];
}

void add_object(Scene& s, const Shape& shape, const Material& m, const Bound* bound = nullptr) {
  int i = s.numObjects++;
  Object& o = s.objects[i];
  // Member by member (no temporary Object to copy); shape_bound sets the
  // bound's centre and radius on every path.
  o.shape = shape;
  o.mat = m;
  shape_bound(shape, o.boundCentre, o.boundRadius);
  if (bound) {
    o.boundCentre = bound->centre;
    o.boundRadius = bound->radius;
  }
  if (shape.kind == kEmpty) return; // boundR2 stays -1 (scene_clear): no ray passes
  if (o.boundRadius >= kHuge) {
    s.unboundedMask |= 1u << i;
    return;
  }
  s.boundX[i] = o.boundCentre.x;
  s.boundY[i] = o.boundCentre.y;
  s.boundZ[i] = o.boundCentre.z;
  s.boundR[i] = o.boundRadius;
  s.boundR2[i] = o.boundRadius * o.boundRadius;
  for (int l = 0; l < s.numLights; ++l)
    light_terms(s, l, i);
}

// May object j's bound come within the widened capsule of closed convex
// object i (Scene::aloneMask)? The capsule is the segment from the base a
// along the unit axis b over the height h, radius max(r0, r1); a sphere
// (b = 0, h = 0, r1 = 0: make_sphere leaves them so) is its own capsule. An
// unbounded object (radius kHuge) always may; an empty one (radius -1)
// comes out either way, and no ray hits it.
bool near_capsule(const Scene& s, int i, int j) {
  const Shape& c = s.objects[i].shape;
  const Object& o = s.objects[j];
  Vec3 e = o.boundCentre - c.a;
  e = e - c.b * rt_clamp(dot(e, c.b), 0.0f, c.h);
  float reach = (o.boundRadius + rt_max(c.r0, c.r1) + kAloneSlack * c.size) * (1 + kAloneSlack);
  return !(dot(e, e) > reach * reach); // NaN, Inf: may
}

// Scene::aloneMask of the foreground so far, from scratch (scene_add calls
// it after each object: up to 8 x 8 pairs, some thousand instructions a
// frame; not inlined into the scene builders' many calls).
__attribute__((noinline)) void alone_update(Scene& s) {
  u32 mask = 0;
  for (int i = 0; i < s.numForeground; ++i) {
    bool alone = closed_convex(s.objects[i].shape);
    for (int j = 0; j < s.numForeground; ++j)
      if (j != i && near_capsule(s, i, j)) alone = false;
    mask |= (u32)alone << i;
  }
  s.aloneMask = mask;
}

} // namespace

void scene_clear(Scene& s) {
  s.numObjects = s.numForeground = s.numLights = 0;
  s.maxDepth = 4;
  s.unboundedMask = s.aloneMask = 0;
  for (int i = 0; i < kMaxObjects; ++i) {
    s.boundX[i] = s.boundY[i] = s.boundZ[i] = s.boundR[i] = 0;
    s.boundR2[i] = -1;
  }
}

void scene_add(Scene& s, const Shape& shape, const Material& m) {
  if (s.numObjects >= kMaxObjects || s.numForeground != s.numObjects) return;
  add_object(s, shape, m);
  s.numForeground = s.numObjects;
  alone_update(s);
}

void scene_add_background(Scene& s, const Shape& shape, const Material& m, const Bound* bound) {
  if (s.numObjects >= kMaxObjects) return;
  add_object(s, shape, m, bound);
}

void scene_add_light(Scene& s, Vec3 pos, Vec3 color) {
  if (s.numLights >= kMaxLights) return;
  int l = s.numLights++;
  s.lights[l] = Light{pos, color};
  for (int i = 0; i < kMaxObjects; ++i)
    light_terms(s, l, i);
}
