// The scenes' objects that never move are stored as Shapes (scenes.cpp:
// kLowerCone, kFloor, kStage), not built each frame, so that intro.exe
// needs no plane or triangle builder. Each must be, bit for bit, what its
// builder returns for the arguments scenes.cpp names; on a mismatch the
// test prints the builder's Shape as the hex floats to paste.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "scenes.h"
#include "trace.h"

namespace {

// The Shape as an initialiser of hex floats (exact), in member order.
std::string literal(const Shape& s) {
  const float f[] = {s.a.x, s.a.y, s.a.z, s.b.x, s.b.y, s.b.z, s.c.x,        s.c.y, s.c.z,
                     s.r0,  s.r1,  s.h,   s.n.x, s.n.y, s.n.z, s.sideMargin, s.size};
  char b[64];
  std::snprintf(b, sizeof b, "{%d, %d", (int)s.kind, (int)s.caps);
  std::string out = b;
  for (float v : f) {
    std::snprintf(b, sizeof b, ", %af", (double)v);
    out += b;
  }
  return out + "}";
}

void expect_same(const Shape& stored, const Shape& built, const char* name) {
  // Builders and static initialisation both leave the padding bytes zero.
  EXPECT_EQ(0, std::memcmp(&stored, &built, sizeof(Shape)))
      << name << " differs from its builder's Shape: " << literal(built);
}

TEST(Scenes, StoredShapesAreTheBuildersShapes) {
  expect_same(kLowerCone, make_cone(v3(0, 0, 0), v3(0, 1, 0), 1.5f, 0.32f, 1.75f, kCapBase),
              "kLowerCone");
  Shape floor = make_plane(v3(0, 1, 0), 0.0f); // flagged for the tree's inline test (shapes.h)
  floor.caps = kInlinePlane;
  expect_same(kFloor, floor, "kFloor");
  Vec3 a = v3(-7, 0, -7), b = v3(7, 0, -7), c = v3(7, 0, 7), d = v3(-7, 0, 7);
  Shape first = make_triangle(a, c, b); // and flagged as a pair's first half (shapes.h)
  first.caps = kPairNext;
  expect_same(kStage[0], first, "kStage[0]");
  expect_same(kStage[1], make_triangle(a, d, c), "kStage[1]");
}

// The stage is a triangle pair (kPairNext, shapes.h; the tree tests both
// halves with intersect_pair()): its precondition, bit for bit, and the
// second half unflagged. The scene puts them next to each other with one
// bound (StoredShapesAreInTheScenes).
TEST(Scenes, StageIsATrianglePair) {
  const Shape &f = kStage[0], &s = kStage[1];
  ASSERT_EQ(f.kind, kTriangle);
  ASSERT_EQ(s.kind, kTriangle);
  EXPECT_EQ(f.caps, kPairNext);
  EXPECT_EQ(s.caps, 0);
  EXPECT_EQ(0, std::memcmp(&f.a, &s.a, sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(&f.n, &s.n, sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(&f.sideMargin, &s.sideMargin, sizeof(float)));
  EXPECT_EQ(0, std::memcmp(&f.b, &s.c, sizeof(Vec3)));
}

// The scenes put them in: scene 1's object 0 and its last (background)
// object, scene 2's two background objects, each with its bound.
TEST(Scenes, StoredShapesAreInTheScenes) {
  Scene s;
  build_scene1(s, 12.0f);
  ASSERT_EQ(s.numObjects, 6);
  EXPECT_EQ(0, std::memcmp(&s.objects[0].shape, &kLowerCone, sizeof(Shape)));
  EXPECT_EQ(0, std::memcmp(&s.objects[5].shape, &kFloor, sizeof(Shape)));
  EXPECT_EQ(s.numForeground, 5);
  EXPECT_EQ(s.unboundedMask, 1u << 5);
  Vec3 centre;
  float radius;
  shape_bound(kLowerCone, centre, radius);
  EXPECT_EQ(s.boundR[0], radius);
  build_scene2(s, 20.0f);
  ASSERT_EQ(s.numObjects, 7);
  EXPECT_EQ(s.numForeground, 5);
  EXPECT_EQ(0, std::memcmp(&s.objects[5].shape, &kStage[0], sizeof(Shape)));
  EXPECT_EQ(0, std::memcmp(&s.objects[6].shape, &kStage[1], sizeof(Shape)));
  for (int i = 5; i < 7; ++i) {
    EXPECT_EQ(s.boundX[i], kStageBound.centre.x);
    EXPECT_EQ(s.boundY[i], kStageBound.centre.y);
    EXPECT_EQ(s.boundR[i], kStageBound.radius);
  }
}

// The stage's shared bound (scenes.cpp, kStageBound), a sphere of radius
// 1024.0625 below the stage: every point of the stage lies inside it by at
// least 1/128 (in double: the farthest points are the corners), and no ray
// that meets the stage is culled by the bound tests. Seeded rays, 100,000
// per class, compared with nearest_among() over every object without any
// bound (trace.h): the object and t bit for bit, from first_hit() (the
// secondary rays' bound_mask) and from the full trace of frames (the
// packets' terms) elsewhere (md5 of the bench's frames). Classes: rays
// from just above the bound's top (y 0.0625 .. 0.3) grazing upwards and
// downwards (dir.y of +-2^-24 .. 2^-4); rays from the scene's space (the
// glass, the gold, the camera's orbit) to points of the stage within 2^-20
// .. 2^-4 of its edges and corners, and beyond them; rays from below.
TEST(Scenes, StageBoundHoldsTheStage) {
  Vec3 c = kStageBound.centre;
  double r = kStageBound.radius, least = 1e30;
  for (const Shape& t : kStage)
    for (Vec3 v : {t.a, t.b, t.c}) {
      double dx = (double)v.x - c.x, dy = (double)v.y - c.y, dz = (double)v.z - c.z;
      double inside = r - std::sqrt(dx * dx + dy * dy + dz * dz);
      if (inside < least) least = inside;
    }
  EXPECT_GT(least, 1.0 / 128);
  EXPECT_LT(least, 1.0 / 64); // the top stays near the stage: y < 1/16 + 1/64
  Scene s;
  build_scene2(s, 20.0f);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  u32 all = (1u << s.numObjects) - 1;
  long rays = 0, differ = 0, stageHits = 0, grazing = 0;
  auto check = [&](Vec3 org, Vec3 dir) {
    Ray ray{org, normalize(dir)};
    Hit a, b;
    int ia = first_hit(s, ray, a), ib = nearest_among(s, ray, all, b);
    ++rays;
    stageHits += ib >= 5;
    if (ia != ib || (ia >= 0 && std::memcmp(&a.t, &b.t, sizeof a.t) != 0)) ++differ;
  };
  for (int k = 0; k < 100000; ++k) {
    // Just above the top, grazing.
    float dy = std::ldexp(1.0f, -(4 + k % 21)) * (k & 1 ? 1.0f : -1.0f);
    check(v3(9 * u(rng), 0.0625f + 0.25f * u01(rng), 9 * u(rng)), v3(u(rng), dy, u(rng)));
    grazing += dy > 0;
    // From the scene's space to the stage's edges and corners and past them.
    float e = std::ldexp(1.0f, -(4 + k % 17)) * u(rng);
    Vec3 target = k % 3 == 0   ? v3(7 * (k & 4 ? 1 : -1) + e, 0, 7 * (k & 8 ? 1 : -1) - e)
                  : k % 3 == 1 ? v3(7 * (k & 4 ? 1 : -1) + e, 0, 7 * u(rng))
                               : v3(7 * u(rng), 0, 7 * (k & 8 ? 1 : -1) + e);
    Vec3 org = k % 2 ? v3(9 * u(rng), 0.1f + 4 * u01(rng), 9 * u(rng))
                     : v3(12 * u(rng), 2 + 2 * u01(rng), 12 * u(rng));
    check(org, target - org);
    // From below the stage, upwards (its back) and sideways.
    check(v3(9 * u(rng), -3 * u01(rng), 9 * u(rng)), v3(u(rng), 0.5f * u(rng), u(rng)));
  }
  EXPECT_EQ(differ, 0) << "of " << rays;
  EXPECT_EQ(rays, 300000);
  EXPECT_GT(stageHits, 50000);
  EXPECT_EQ(grazing, 50000);
}

} // namespace
