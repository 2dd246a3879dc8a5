// The scenes' objects that never move are stored as Shapes (scenes.cpp:
// kLowerCone, kFloor, kStage), not built each frame, so that intro.exe
// needs no plane or triangle builder. Each must be, bit for bit, what its
// builder returns for the arguments scenes.cpp names; on a mismatch the
// test prints the builder's Shape as the hex floats to paste.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "scenes.h"

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
  expect_same(kFloor, make_plane(v3(0, 1, 0), 0.0f), "kFloor");
  Vec3 a = v3(-7, 0, -7), b = v3(7, 0, -7), c = v3(7, 0, 7), d = v3(-7, 0, 7);
  expect_same(kStage[0], make_triangle(a, c, b), "kStage[0]");
  expect_same(kStage[1], make_triangle(a, d, c), "kStage[1]");
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
  shape_bound(kStage[1], centre, radius);
  EXPECT_EQ(s.boundX[6], centre.x);
  EXPECT_EQ(s.boundR[6], radius);
}

} // namespace
