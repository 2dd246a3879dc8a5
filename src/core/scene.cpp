// scene.cpp - building a scene's fixed-size arrays.
#include "scene.h"

namespace {

Object make_object(const Shape& shape, const Material& m) {
  Object o{shape, m, {0, 0, 0}, kHuge};
  shape_bound(shape, o.boundCentre, o.boundRadius);
  return o;
}

}  // namespace

void scene_clear(Scene& s) {
  s.numObjects = s.numForeground = s.numLights = 0;
  s.maxDepth = 4;
}

void scene_add(Scene& s, const Shape& shape, const Material& m) {
  if (s.numObjects >= kMaxObjects || s.numForeground != s.numObjects) return;
  s.objects[s.numObjects++] = make_object(shape, m);
  s.numForeground = s.numObjects;
}

void scene_add_background(Scene& s, const Shape& shape, const Material& m) {
  if (s.numObjects >= kMaxObjects) return;
  s.objects[s.numObjects++] = make_object(shape, m);
}

void scene_add_light(Scene& s, Vec3 pos, Vec3 color) {
  if (s.numLights < kMaxLights) s.lights[s.numLights++] = Light{pos, color};
}
