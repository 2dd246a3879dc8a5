// test_raytree.cpp - the ray tree traced without recursion (trace_hit in
// trace.cpp, docs/tracer-speed.md "Round seven"): the order of the path
// record's nodes, every ray of the deepest tree cast once, the depth bound
// of the slots of waiting rays, and the colour as the weighted sum of the
// nodes' own shading.
//
// The scene: four infinite planes, y = -1 and y = 2 mirrors, y = 0 and y = 1
// "glass" that reflects and transmits everything (reflect = transmit = 1,
// index 1, so a refracted ray goes straight on). No light; the ambient term
// is each node's own shading, red on glass and green on mirrors. Every
// ray, moving up or down between two planes, meets the next plane, so the
// tree is known in advance: a glass node has two children (the reflected
// ray back into its gap, the refracted ray into the next gap), a mirror node
// one. All weights are 1, so no ray is cut, every node is recorded up to
// kRecordDepth, and the colour counts the nodes: red = glass nodes, green =
// mirror nodes, blue = rays that saw nothing (none while the top mirror is there).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "trace.h"

namespace {

// Plane k of the four, bottom to top: y = -1, 0, 1, 2. Object index k.
constexpr float kPlaneY[4] = {-1, 0, 1, 2};
bool is_glass(int plane) { return plane == 1 || plane == 2; }

Scene slab_scene(int maxDepth, bool topMirror = true) {
  Scene s;
  scene_clear(s);
  s.model = kPhong;
  s.background = v3(0, 0, 1);
  s.ambient = v3(1);
  s.maxDepth = maxDepth;
  s.camera = Camera{v3(0, 0, -5), v3(0, 0, 0), v3(0, 1, 0), 1.0f};
  Material mirror{v3(0, 1, 0), 0, 0, 1, 1, 0, 1, 0.3f, 0.1f};
  Material glass{v3(1, 0, 0), 0, 0, 1, 1, 1, 1, 0.3f, 0.1f};
  for (int k = 0; k < (topMirror ? 4 : 3); ++k) {
    // Normals point into the slab [-1, 2]; two-sided anyway.
    Vec3 n = k < 2 ? v3(0, 1, 0) : v3(0, -1, 0);
    scene_add(s, make_plane(n, k < 2 ? kPlaneY[k] : -kPlaneY[k]), is_glass(k) ? glass : mirror);
  }
  return s;
}

// The tree by its geometry, depth first, the reflected child first: a ray
// in gap g (between planes g and g + 1) moving up meets plane g + 1, moving
// down plane g.
// Without the top mirror, a ray moving up in gap 2 sees nothing.
struct Expected {
  int glass = 0, mirror = 0, misses = 0;
  int maxWaiting = 0; // refracted rays waiting at once while a node is shaded
  std::vector<u32> record;
};
// A ray that has passed through glass (`past`) is recorded at any depth
// (all weights are 1, above kRecordWeightGlass), the others to kRecordDepth.
void expect_tree(int gap, bool up, int depth, int maxDepth, bool topMirror, Expected& e,
                 int waiting = 0, bool past = false) {
  int plane = up ? gap + 1 : gap;
  if (waiting > e.maxWaiting) e.maxWaiting = waiting;
  bool miss = plane == 3 && !topMirror;
  (miss ? e.misses : is_glass(plane) ? e.glass : e.mirror) += 1;
  if ((depth <= kRecordDepth || past) && (int)e.record.size() < kMaxPathNodes)
    e.record.push_back(miss ? 0u : u32(plane + 1));
  if (miss || depth >= maxDepth) return;
  expect_tree(gap, !up, depth + 1, maxDepth, topMirror, e, waiting + is_glass(plane),
              past); // reflected, its sibling waiting
  if (is_glass(plane))
    expect_tree(up ? gap + 1 : gap - 1, up, depth + 1, maxDepth, topMirror, e, waiting, true);
}

struct Traced {
  Vec3 color;
  RayStats stats;
  PathRecord record;
};
Traced trace_slab(const Scene& s, Vec3 org, Vec3 dir, float weight = 1.0f) {
  Traced r;
  r.record.count = 0;
  TraceContext ctx{&s, {0, 0, 0}, &r.record};
  r.color = trace(ctx, Ray{org, normalize(dir)}, 1, weight);
  r.stats = ctx.stats;
  return r;
}

void check_slab(int maxDepth, Vec3 org, Vec3 dir, bool topMirror = true) {
  Scene s = slab_scene(maxDepth, topMirror);
  Traced r = trace_slab(s, org, dir);
  int depth = maxDepth < kMaxTraceDepth ? maxDepth : kMaxTraceDepth;
  Expected e;
  expect_tree(org.y < 0 ? 0 : (org.y < 1 ? 1 : 2), dir.y > 0, 1, depth, topMirror, e);
  SCOPED_TRACE(testing::Message() << "maxDepth " << maxDepth << " from y = " << org.y);
  // Every node shaded once (small integers: the float sums are exact).
  EXPECT_EQ(r.color.x, float(e.glass));
  EXPECT_EQ(r.color.y, float(e.mirror));
  EXPECT_EQ(r.color.z, float(e.misses));
  EXPECT_EQ(r.stats.secondary, u64(e.glass + e.mirror + e.misses - 1));
  EXPECT_EQ(r.stats.shadow, 0u);
  ASSERT_EQ(r.record.count, e.record.size());
  for (int i = 0; i < r.record.count; ++i)
    EXPECT_EQ(r.record.node[i], e.record[i]) << i;
}

TEST(RayTree, EveryNodeOfTheDeepestTreeIsShadedOnceDepthFirst) {
  // From the middle gap upwards: the reflections alone stay between the two
  // glass planes, so at depth d every depth 2 .. d holds a waiting refracted
  // ray: the slots fill to the bound. 2^(maxDepth - 1) leaves at most.
  for (int maxDepth = 1; maxDepth <= kMaxTraceDepth; ++maxDepth) {
    check_slab(maxDepth, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f));
    check_slab(maxDepth, v3(0, 0.5f, 0), v3(-0.2f, -1, 0.4f));
    check_slab(maxDepth, v3(0, 1.5f, 0), v3(0.1f, 1, 0));   // from the top gap
    check_slab(maxDepth, v3(0, -0.5f, 0), v3(0, -1, 0.7f)); // from the bottom gap
  }
  // At kMaxTraceDepth from the middle gap, a ray of every depth 2 ..
  // kMaxTraceDepth waits at once (the slots are full) while the deepest
  // reflection is shaded; 87 nodes.
  Expected e;
  expect_tree(1, true, 1, kMaxTraceDepth, true, e);
  EXPECT_EQ(e.maxWaiting, kMaxTraceDepth - 1);
  EXPECT_EQ(e.glass + e.mirror, 87);
}

TEST(RayTree, ASceneDeeperThanTheBoundIsTracedToTheBound) {
  // Scene::maxDepth above kMaxTraceDepth: no ray deeper than the bound (the
  // slots of waiting rays are sized by it), the same tree as at the bound.
  for (int maxDepth : {kMaxTraceDepth + 1, kMaxTraceDepth + 5, 30, 1000}) {
    check_slab(maxDepth, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f));
    Scene deep = slab_scene(maxDepth), bound = slab_scene(kMaxTraceDepth);
    Traced a = trace_slab(deep, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f));
    Traced b = trace_slab(bound, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f));
    EXPECT_EQ(a.stats.secondary, b.stats.secondary);
    EXPECT_TRUE(same_path(a.record, b.record));
  }
}

TEST(RayTree, RecordListsTheReflectionSubtreeBeforeTheRefraction) {
  // From the middle gap upwards, to depth 3: glass 2 (primary), then its
  // reflected ray's subtree (glass 1, whose reflected ray meets glass 2 and
  // refracted ray the mirror 0), then its refracted ray's (mirror 3, whose
  // reflected ray meets glass 2 from above). Breadth first would put mirror
  // 3 second; refraction first, fourth.
  Scene s = slab_scene(3);
  Traced r = trace_slab(s, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f));
  const u32 expected[] = {3, 2, 3, 1, 4, 3};
  ASSERT_EQ(r.record.count, 6);
  for (int i = 0; i < 6; ++i)
    EXPECT_EQ(r.record.node[i], expected[i]) << i;
}

TEST(RayTree, ColourIsRelativeToTheRootWeight) {
  // Roots of weight 1/2 and 1/8 (all products exact): the same colour as
  // weight 1, each node's share being its weight over the root's, and the
  // same rays (no weight falls below kMinRayWeight); at 1/8 no node reaches
  // kRecordWeight, so nothing is recorded.
  Scene s = slab_scene(5);
  Traced one = trace_slab(s, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f));
  Traced half = trace_slab(s, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f), 0.5f);
  Traced eighth = trace_slab(s, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f), 0.125f);
  for (const Traced* t : {&half, &eighth}) {
    EXPECT_EQ(t->color.x, one.color.x);
    EXPECT_EQ(t->color.y, one.color.y);
    EXPECT_EQ(t->stats.secondary, one.stats.secondary);
  }
  EXPECT_TRUE(same_path(half.record, one.record));
  EXPECT_EQ(eighth.record.count, 0);
}

TEST(RayTree, MissesInsideTheTreeAddTheBackgroundAndRecordZero) {
  // Without the top mirror, every ray leaving upwards through glass 2 sees
  // the background (blue, weight 1 each) and records node 0.
  for (int maxDepth = 1; maxDepth <= kMaxTraceDepth; ++maxDepth) {
    check_slab(maxDepth, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f), false);
    check_slab(maxDepth, v3(0, 1.5f, 0), v3(0.1f, -1, 0), false);
  }
}

// Round nine (trace.h, kRecordWeightGlass): a ray under a refraction is
// recorded at any depth while its weight is at least kRecordWeightGlass; a
// ray that never passed through glass only to kRecordDepth, at weight
// kRecordWeight. Glass planes that transmit t = 0.45 and reflect nothing,
// mirrors that reflect all. Seeded directions: each tree is the same for
// every ray of its direction's sign.
TEST(RayTree, RaysThroughGlassAreRecordedPastTheRecordDepth) {
  Scene s = slab_scene(5);
  for (int k : {1, 2}) {
    s.objects[k].mat.reflect = 0.0f;
    s.objects[k].mat.transmit = 0.45f;
  }
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> tilt(-0.6f, 0.6f);
  for (int i = 0; i < 50; ++i) {
    Vec3 dir = v3(tilt(rng), 1, tilt(rng));
    Traced r = trace_slab(s, v3(0, -0.5f, 0), dir);
    // Up from the bottom gap: glass 1, glass 2 (depth 2, weight t), the top
    // mirror (depth 3, t^2 = 0.2025: below kRecordWeight, recorded as past
    // glass), glass 2 again (depth 4, t^2); not glass 1 at depth 5 (t^3).
    const u32 up[] = {2, 3, 4, 3};
    ASSERT_EQ(r.record.count, 4) << i;
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(r.record.node[k], up[k]) << i << " node " << k;
    EXPECT_EQ(r.stats.secondary, 4u); // depths 2 .. 5
    // Down from the middle gap: glass 1, the bottom mirror (depth 2, t),
    // glass 1 (3, t), glass 2 (4, t^2: recorded past kRecordDepth); not the
    // top mirror (5, t^3).
    Traced d = trace_slab(s, v3(0, 0.5f, 0), v3(dir.x, -1, dir.z));
    const u32 down[] = {2, 1, 2, 3};
    ASSERT_EQ(d.record.count, 4) << i;
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(d.record.node[k], down[k]) << i << " node " << k;
    EXPECT_EQ(d.stats.secondary, 4u);
  }
  // The same planes all opaque mirrors seen from the middle gap: no ray
  // passes through glass, so nothing past kRecordDepth is recorded.
  Scene m = slab_scene(5);
  for (int k : {1, 2})
    m.objects[k].mat.transmit = 0.0f;
  Traced r = trace_slab(m, v3(0, 0.5f, 0), v3(0.3f, 1, 0.1f));
  EXPECT_EQ(r.record.count, kRecordDepth);
  EXPECT_EQ(r.stats.secondary, 4u);
}

} // namespace
