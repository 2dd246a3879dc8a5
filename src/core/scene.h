// scene.h - what a frame is made of: objects, lights, shading model, camera.
// A scene is plain data, rebuilt each frame by a pure function of time
// (scenes/scenes.h). Fixed-size arrays: no heap anywhere in the core.
#pragma once
#include "shapes.h"

enum ShadingModel : u8 { kPhong, kCookTorrance };

struct Material {
  Vec3 color;      // surface albedo, linear RGB in [0, 1]
  float diffuse;   // r_D
  float specular;  // r_S
  float shininess; // Phong exponent h
  float reflect;   // weight of the mirror-reflected colour
  float transmit;  // weight of the refracted colour; also the shadow-ray transmittance
  float ior;       // index of refraction of the solid (outside is 1.0, air)
  float roughness; // Cook-Torrance m (rms microfacet slope, radians), > 0
  float f0;        // Cook-Torrance Fresnel reflectance at normal incidence
};

struct Light {
  Vec3 pos;
  Vec3 color; // I_L, may exceed 1
};

// An object: shape, material, and a bounding sphere that rays test first
// (a cone or cylinder costs several times a sphere test; most rays miss).
// The bound is filled by scene_add from shape_bound(); an infinite plane has
// boundRadius = kHuge, which every ray passes.
struct Object {
  Shape shape;
  Material mat;
  Vec3 boundCentre;
  float boundRadius;
};

struct Camera {
  Vec3 pos, target, up;
  float fovY; // vertical field of view, radians
};

constexpr int kMaxObjects = 8; // scene 1 has 6, scene 2 has 7; a multiple of 4 (SSE)
constexpr int kMaxLights = 4;

// Objects [0, numForeground) are foreground; [numForeground, numObjects) are
// background objects (the ground). The background contract (SPEC, thesis
// 5.2): a background object is tested only when no foreground object was hit,
// and never by shadow rays. The scene's layout must make that true: nothing
// of the background may stand in front of a foreground object.
struct Scene {
  Object objects[kMaxObjects];
  int numObjects, numForeground;
  Light lights[kMaxLights];
  int numLights;
  ShadingModel model;
  Vec3 background; // colour of a ray that hits nothing
  Vec3 ambient;    // ambient light level, multiplied by the albedo once per hit
  int maxDepth;    // primary ray is depth 1; no secondary rays beyond maxDepth
  Camera camera;
  // The objects' bounding spheres again, structure-of-arrays, so that a ray
  // tests four bounds at once (trace.cpp). Filled by scene_add*; an unused
  // slot has boundR2 = -1, which no ray passes; an unbounded object (plane)
  // is in unboundedMask instead.
  alignas(16) float boundX[kMaxObjects];
  alignas(16) float boundY[kMaxObjects];
  alignas(16) float boundZ[kMaxObjects];
  alignas(16) float boundR[kMaxObjects];
  alignas(16) float boundR2[kMaxObjects];
  u32 unboundedMask;
  // Per light l and bound i, for shadow rays (trace.cpp), which all end at a
  // light: f = light - centre and c = |f|^2 - R^2 (unused slots: R^2 = -1,
  // which no ray passes). Filled by scene_add* and scene_add_light for every
  // pair whichever comes first.
  alignas(16) float lightFX[kMaxLights][kMaxObjects];
  alignas(16) float lightFY[kMaxLights][kMaxObjects];
  alignas(16) float lightFZ[kMaxLights][kMaxObjects];
  alignas(16) float lightC[kMaxLights][kMaxObjects];
  // Bit i set: foreground object i is a closed convex solid (closed_convex(),
  // shapes.h) and no other foreground object's bound comes within
  // kAloneSlack of it (of the capsule around its axis, or its sphere): a ray
  // from inside it meets it before anything else (trace.cpp, trace_tree's
  // lone-solid shortcut). Filled by scene_add.
  u32 aloneMask;
};
// The capsule around a closed convex object i is widened by kAloneSlack
// times its bound radius R_i, then the sum with the other bound's radius
// by as much again, for the rounding of the test: with a ray's origin at
// most kAloneSlack / 2 R_i off the surface (spawn offsets, trace.cpp) and
// hit points within the contract's error of the surfaces inside the
// padded bounds (shapes.h), a segment from inside i to i's exit stays
// clear of every other foreground bound.
constexpr float kAloneSlack = 1.0f / 256;

// Appending helpers used by scene builders. Foreground objects must all be
// added before the first background object.
void scene_clear(Scene& s);
void scene_add(Scene& s, const Shape& shape, const Material& m);
// A bounding sphere a scene gives for a background object instead of
// shape_bound()'s. It must contain the shape with a margin that covers the
// bound tests' rounding (scenes.cpp's stage: kStageBound, its test in
// tests/test_scenes.cpp).
struct Bound {
  Vec3 centre;
  float radius;
};
void scene_add_background(Scene& s, const Shape& shape, const Material& m,
                          const Bound* bound = nullptr);
void scene_add_light(Scene& s, Vec3 pos, Vec3 color);
