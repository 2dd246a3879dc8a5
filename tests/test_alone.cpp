// test_alone.cpp - the lone-solid shortcut (Scene::aloneMask, scene.cpp;
// trace_tree's kOnlyShift, trace.cpp; docs/tracer-speed.md "Round nine"): a
// ray into a closed convex solid that no other foreground bound comes near
// tests that solid alone. It must change nothing: every ray traced with the
// scene's mask and with the mask cleared (no shortcut) gives the same colour
// (every bit), the same path record and the same ray counts. Over the
// scenes' own frames, over seeded scenes with neighbours on both sides of
// the test's reach, and on the hard rays: from the surface, grazing and
// tangent, from inside near a cylinder's rim.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <initializer_list>
#include <random>

#include "scenes.h"
#include "trace.h"

namespace {

Material make_mat(Vec3 color, float diffuse, float specular, float shininess, float reflect,
                  float transmit, float ior, float roughness = 0.3f, float f0 = 0.1f) {
  return Material{color, diffuse, specular, shininess, reflect, transmit, ior, roughness, f0};
}
const Material kGlass =
    make_mat(v3(0.9f, 0.95f, 1), 0.05f, 0.8f, 80, 0.1f, 0.85f, 1.5f, 0.15f, 0.05f);
const Material kGold = make_mat(v3(1, 0.7f, 0.2f), 0.5f, 0.9f, 40, 0.4f, 0, 1, 0.25f, 0.8f);

Scene base_scene(ShadingModel model, float lx, float lz) {
  Scene s;
  scene_clear(s);
  s.model = model;
  s.background = v3(0.3f, 0.5f, 0.8f);
  s.ambient = v3(0.1f);
  s.maxDepth = 6;
  s.camera = Camera{v3(0, 0, -5), v3(0, 0, 0), v3(0, 1, 0), 1.0f};
  scene_add_light(s, v3(lx, 6, lz), v3(1));
  scene_add_light(s, v3(-lz, 3, lx), v3(0.6f));
  return s;
}

// The reach of near_capsule() (scene.cpp) for a sphere of radius r beside
// closed convex solid c: the test marks c alone when the sphere's bound
// centre is further than this from c's capsule. shape_bound pads the radius
// by kBoundPad (r + max_abs(centre)); the centre is where the sphere will
// be, `foot + dir * reach`, which this solves for (two rounds: the pad
// moves with the centre by 1e-3 of the move).
float reach_of(const Shape& c, float r, Vec3 foot, Vec3 dir) {
  float reach = 0;
  for (int k = 0; k < 3; ++k) {
    float bound = r + kBoundPad * (r + max_abs(foot + dir * reach));
    reach = (bound + rt_max(c.r0, c.r1) + kAloneSlack * c.size) * (1 + kAloneSlack);
  }
  return reach;
}

// Traces `ray` in s and in s with aloneMask cleared; counts a difference in
// colour bits, record or ray counts.
struct Compare {
  long rays = 0, differ = 0, glassFirst = 0;
  void ray(const Scene& s, const Scene& plain, const Ray& r, u32 glassMask) {
    PathRecord ra{}, rb{};
    TraceContext ca{&s, {0, 0, 0}, &ra}, cb{&plain, {0, 0, 0}, &rb};
    Vec3 x = trace(ca, r, 1), y = trace(cb, r, 1);
    ++rays;
    u32 first = ra.node[0] & 31u;
    glassFirst += first && (glassMask >> (first - 1) & 1);
    if (std::memcmp(&x, &y, sizeof x) != 0 || !same_path(ra, rb) ||
        ca.stats.secondary != cb.stats.secondary || ca.stats.shadow != cb.stats.shadow)
      ++differ;
  }
};

Scene cleared(const Scene& s) {
  Scene plain = s;
  plain.aloneMask = 0;
  return plain;
}

TEST(Alone, MaskMarksClosedSolidsClearOfOtherBounds) {
  auto mask = [](std::initializer_list<Shape> fg, bool groundPlane) {
    Scene s = base_scene(kPhong, 1, 1);
    for (const Shape& sh : fg)
      scene_add(s, sh, kGlass);
    if (groundPlane) scene_add_background(s, make_plane(v3(0, 1, 0), -10), kGold);
    return s.aloneMask;
  };
  Shape a = make_sphere(v3(0, 0, 0), 1.0f);
  EXPECT_EQ(mask({a, make_sphere(v3(3, 0, 0), 0.5f)}, false), 3u);
  EXPECT_EQ(mask({a, make_sphere(v3(1.4f, 0, 0), 0.5f)}, false), 0u); // bounds overlap
  // A closed cylinder (bound radius 2.06 about (0, 2, 0)) and a sphere beside
  // its axis: the bounding spheres overlap, the capsule (radius 0.5) does not
  // (the sphere is not alone: the cylinder's bound comes near it).
  Shape cyl = make_cylinder(v3(0, 0, 0), v3(0, 1, 0), 0.5f, 4.0f, kCapBase | kCapTop);
  EXPECT_EQ(mask({cyl, make_sphere(v3(1.3f, 2, 0), 0.5f)}, false), 1u);
  EXPECT_EQ(mask({cyl, make_sphere(v3(0, 5.2f, 0), 0.5f)}, false), 3u); // above the top cap
  EXPECT_EQ(mask({cyl, make_sphere(v3(0.9f, 2, 0), 0.5f)}, false), 0u); // within reach
  EXPECT_EQ(mask({cyl, make_sphere(v3(0, 4.9f, 0), 0.5f)}, false), 2u); // at the cap
  // Open frusta are not closed convex solids; a cone's apex needs no cap.
  Shape open = make_cylinder(v3(0, 0, 0), v3(0, 1, 0), 0.5f, 4.0f, kCapBase);
  EXPECT_EQ(mask({open, make_sphere(v3(3, 2, 0), 0.5f)}, false), 2u);
  Shape cone = make_cone(v3(0, 0, 0), v3(0, 1, 0), 1.0f, 0.0f, 2.0f, kCapBase);
  EXPECT_EQ(mask({cone, make_sphere(v3(3, 2, 0), 0.5f)}, false), 3u);
  // A background object is never tested against a ray that found a
  // foreground hit; a foreground plane may be hit from anywhere.
  EXPECT_EQ(mask({a, make_sphere(v3(3, 0, 0), 0.5f)}, true), 3u);
  EXPECT_EQ(mask({a, make_plane(v3(0, 1, 0), -10)}, false), 0u);
  // A triangle is flat, never alone; it clears a solid it comes near.
  EXPECT_EQ(mask({a, make_triangle(v3(5, 0, 0), v3(6, 0, 0), v3(5, 1, 0))}, false), 1u);
  EXPECT_EQ(mask({a, make_triangle(v3(0.5f, 0, 0), v3(6, 0, 0), v3(5, 1, 0))}, false), 0u);
  // The edge of the reach, beside the cylinder's side and off its top cap's
  // rim (the capsule's end is a half ball): 1e-3 inside it is near, 1e-3
  // outside it is clear.
  // (Beside the side the sphere is within the cylinder's bound: bit 1 clear.)
  float reach = reach_of(cyl, 0.5f, v3(0, 2, 0), v3(1, 0, 0));
  EXPECT_EQ(mask({cyl, make_sphere(v3(reach * 0.999f, 2, 0), 0.5f)}, false), 0u);
  EXPECT_EQ(mask({cyl, make_sphere(v3(reach * 1.001f, 2, 0), 0.5f)}, false), 1u);
  Vec3 out = normalize(v3(1, 1, 0));
  reach = reach_of(cyl, 0.5f, v3(0, 4, 0), out);
  EXPECT_EQ(mask({cyl, make_sphere(v3(0, 4, 0) + out * (reach * 0.999f), 0.5f)}, false), 2u);
  EXPECT_EQ(mask({cyl, make_sphere(v3(0, 4, 0) + out * (reach * 1.001f), 0.5f)}, false), 3u);
}

// Seeded scenes of a glass sphere, a glass closed cylinder and a glass cone
// with a gold and a glass sphere placed 0.97 .. 1.1 times the test's reach
// from two of them (so both sides of the reach's edge occur, some within
// the slack), rays from around the scene and from inside the solids.
TEST(Alone, RaysIntoAloneSolidsTraceAsWithoutTheShortcut) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), f(0.97f, 1.1f);
  Compare cmp;
  long nearAlone = 0, nearNot = 0;
  for (int sceneIndex = 0; sceneIndex < 60; ++sceneIndex) {
    Scene s = base_scene(sceneIndex % 2 ? kPhong : kCookTorrance, 5 * u(rng), 5 * u(rng));
    Vec3 axis = normalize(v3(0.3f * u(rng), 1, 0.3f * u(rng)));
    Shape solid[3] = {make_sphere(v3(-3, 1.5f, 0), 0.8f),
                      make_cylinder(v3(0, 0.2f, 0), axis, 0.6f, 2.5f, kCapBase | kCapTop),
                      make_cone(v3(3, 0.2f, 0), axis, 0.9f, 0.0f, 2.0f, kCapBase)};
    for (const Shape& sh : solid)
      scene_add(s, sh, kGlass);
    for (int k = 0; k < 2; ++k) {
      const Shape& c = solid[(sceneIndex + k) % 3];
      float r = 0.3f + 0.2f * (u(rng) + 1);
      Vec3 side =
          normalize(cross(c.kind == kSphere ? v3(0, 1, 0) : c.b, v3(u(rng), u(rng), u(rng))));
      Vec3 foot = c.kind == kSphere ? c.a : c.a + c.b * (c.h * 0.5f * (u(rng) + 1));
      scene_add(s, make_sphere(foot + side * (reach_of(c, r, foot, side) * f(rng)), r),
                k ? kGold : kGlass);
    }
    scene_add_background(s, make_plane(v3(0, 1, 0), 0), kGold);
    for (int k = 0; k < 2; ++k) {
      bool alone = s.aloneMask >> ((sceneIndex + k) % 3) & 1;
      nearAlone += alone;
      nearNot += !alone;
    }
    Scene plain = cleared(s);
    for (int k = 0; k < 1500; ++k) {
      const Shape& c = solid[k % 3];
      Vec3 centre = c.kind == kSphere ? c.a : c.a + c.b * (0.5f * c.h);
      Vec3 org = k % 4 == 3 ? centre + v3(u(rng), u(rng), u(rng)) * 0.3f
                            : v3(6 * u(rng), 1.5f + 3 * u(rng), 6 * u(rng));
      Vec3 dir = normalize(centre + v3(u(rng), u(rng), u(rng)) * 0.8f - org);
      cmp.ray(s, plain, Ray{org, dir}, 7u);
    }
  }
  EXPECT_EQ(cmp.differ, 0) << "of " << cmp.rays;
  EXPECT_EQ(cmp.rays, 90000);
  EXPECT_GT(nearAlone, 20); // neighbour just beyond the reach: the shortcut is taken
  EXPECT_GT(nearNot, 20);   // just within: it is not
  EXPECT_GT(cmp.glassFirst, cmp.rays / 3);
}

// The hard rays, into solids that are alone (asserted) with a gold sphere
// 1.001 reach away: tangent and grazing rays (the refracted ray enters near
// total internal reflection, or the test's rounding decides hit or miss),
// rays from points on the surface (spawned rays start there), and rays from
// inside a closed cylinder near its cap's rim, towards the rim.
TEST(Alone, HardRaysTraceAsWithoutTheShortcut) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  Compare tangent, surface, rim;
  for (int sceneIndex = 0; sceneIndex < 12; ++sceneIndex) {
    Scene s = base_scene(sceneIndex % 2 ? kPhong : kCookTorrance, 5 * u(rng), 5 * u(rng));
    Vec3 axis = normalize(v3(0.4f * u(rng), 1, 0.4f * u(rng)));
    Shape sphere = make_sphere(v3(-2.5f, 1.5f, 0.3f * u(rng)), 0.7f + 0.2f * u01(rng));
    Shape cyl = make_cylinder(v3(1.5f, 0.2f, 0), axis, 0.55f, 3.0f, kCapBase | kCapTop);
    scene_add(s, sphere, kGlass);
    scene_add(s, cyl, kGlass);
    Vec3 side = normalize(cross(axis, v3(0, 0, 1)));
    Vec3 foot = cyl.a + axis * 1.5f;
    scene_add(s, make_sphere(foot + side * (reach_of(cyl, 0.3f, foot, side) * 1.001f), 0.3f),
              kGold);
    scene_add_background(s, make_plane(v3(0, 1, 0), 0), kGold);
    ASSERT_EQ(s.aloneMask, 3u);
    Scene plain = cleared(s);
    Vec3 cc = cyl.a + axis * (0.5f * cyl.h);
    for (int k = 0; k < 2000; ++k) {
      // Tangent and grazing: the ray's closest approach to the sphere's
      // centre is r (1 - 2^-e), e from 4 to 24 (the last within rounding).
      Vec3 org = sphere.a + normalize(v3(u(rng), u(rng), u(rng))) * 5.0f;
      Vec3 toC = sphere.a - org;
      Vec3 perp = normalize(cross(toC, v3(u(rng), u(rng), u(rng))));
      float miss = sphere.r0 * (1.0f - std::ldexp(1.0f, -(4 + k % 21)));
      tangent.ray(s, plain, Ray{org, normalize(toC + perp * miss)}, 3u);
      // The same past the cylinder's side.
      Vec3 orgC = cc + normalize(cross(axis, v3(u(rng), u(rng), u(rng)))) * 5.0f;
      Vec3 toA = cc + axis * (u(rng) * 1.2f) - orgC;
      Vec3 perpC = normalize(cross(toA, axis));
      tangent.ray(
          s, plain,
          Ray{orgC, normalize(toA + perpC * (cyl.r0 * (1.0f - std::ldexp(1.0f, -(4 + k % 21)))))},
          3u);
      // From the surface: a point of the sphere (to float rounding), in
      // random directions, inward and outward.
      Vec3 n = normalize(v3(u(rng), u(rng), u(rng)));
      surface.ray(s, plain, Ray{sphere.a + n * sphere.r0, normalize(v3(u(rng), u(rng), u(rng)))},
                  3u);
      // From inside the cylinder within 1e-4 .. 1e-2 of its top rim, towards
      // points around the rim.
      Vec3 top = cyl.a + axis * cyl.h;
      Vec3 radial = normalize(cross(axis, v3(u(rng), u(rng), u(rng))));
      float in = std::ldexp(1.0f, -(7 + k % 7));
      Vec3 o = top + radial * (cyl.r0 - in) - axis * in;
      Vec3 target = top + normalize(cross(axis, v3(u(rng), u(rng), u(rng)))) * cyl.r0 +
                    axis * (0.02f * u(rng));
      rim.ray(s, plain, Ray{o, normalize(target - o)}, 3u);
    }
  }
  EXPECT_EQ(tangent.differ, 0) << "of " << tangent.rays;
  EXPECT_EQ(surface.differ, 0) << "of " << surface.rays;
  EXPECT_EQ(rim.differ, 0) << "of " << rim.rays;
  EXPECT_EQ(tangent.rays + surface.rays + rim.rays, 12 * 2000 * 4);
  EXPECT_GT(tangent.glassFirst, tangent.rays / 2);
  EXPECT_EQ(rim.glassFirst, rim.rays); // from inside, the cylinder is hit first
}

// trace()'s skip names objects only: bits from trace.cpp's kOnlyShift (16)
// up, which a waiting ray uses to name the lone solid it tests alone, are
// dropped, so a caller's stray high bits cannot make an object farther
// along the ray the hit.
TEST(Alone, CallersSkipHighBitsAreIgnored) {
  Scene s = base_scene(kPhong, 1, 1);
  for (int i = 0; i < 5; ++i)
    scene_add(s, make_sphere(v3(10.0f * (i % 4 != 0) * (float)i, 0, i == 4 ? 8.0f : 3.0f), 1.0f),
              i ? kGold : kGlass);
  ASSERT_NE(s.aloneMask & 1u, 0u); // object 0, in front of object 4, is alone
  Ray ray{v3(0, 0, -2), v3(0, 0, 1)};
  for (u32 high : {1u << 16, 5u << 16, 0xFFFFu << 16}) {
    PathRecord ra{}, rb{};
    TraceContext ca{&s, {0, 0, 0}, &ra}, cb{&s, {0, 0, 0}, &rb};
    Vec3 x = trace(ca, ray, 1, 1.0f, high), y = trace(cb, ray, 1);
    EXPECT_EQ(std::memcmp(&x, &y, sizeof x), 0) << high;
    EXPECT_TRUE(same_path(ra, rb)) << high;
    EXPECT_EQ(ra.node[0] & 31u, 1u); // object 0 first
  }
}

// The scenes' own frames: over 16 frames of both scenes, every pixel of
// 160x120 (primary rays through trace()) as with the mask cleared. The
// scenes' glass is alone in most of them: scene 2's cylinders always.
TEST(Alone, ScenesFramesAsWithoutTheShortcut) {
  Compare cmp;
  long aloneGlass = 0;
  for (int i = 0; i < 16; ++i) {
    double t = 4.0 * i + 1.1;
    Scene s;
    build_timeline_scene(s, t);
    Scene plain = cleared(s);
    u32 glass = 0;
    for (int k = 0; k < s.numForeground; ++k)
      if (s.objects[k].mat.transmit > 0) glass |= 1u << k;
    aloneGlass += __builtin_popcount(s.aloneMask & glass);
    CameraRays cam = camera_rays(s.camera, 160, 120);
    for (int y = 0; y < 120; ++y)
      for (int x = 0; x < 160; ++x)
        cmp.ray(s, plain, primary_ray(cam, (float)x, (float)y), glass);
  }
  EXPECT_EQ(cmp.differ, 0) << "of " << cmp.rays;
  EXPECT_GT(aloneGlass, 24); // of 32 glass objects in the 16 frames
  EXPECT_GT(cmp.glassFirst, cmp.rays / 20);
}

} // namespace
