// test_nearest4.cpp - nearest4() (packet/nearest4.h) against find_hit(),
// trace_tree's kFindHit step (trace.h), lane by lane: the object, and for a
// hit t, piece and local, bit for bit; lanes outside the mask untouched
// (id -1) whatever they hold.
//
// The rays are those the tracer spawns: from hits on both scenes' objects
// at frames of the timeline, the reflected and refracted rays with
// trace_tree's origin, direction and skip (the object left for good, or the
// lone solid entered), followed down to depth 4 so that rays inside glass
// and reflected inside it come in. Beside them the hard cases: grazing rays
// from surfaces (tangent, and 1e-7 .. 1e-3 off), rays parallel to the floor
// and to the stage (y exactly 0, and within kPlaneCosFloat of it), rays
// aimed at cylinder and cone cap rims and at cone apexes, lone-solid rays
// whose named solid the ray misses (so the search runs after the named
// test), and random rays with random object skips. Each packet mixes
// classes, lane masks and skips.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "packet/nearest4.h"
#include "scenes.h"
#include "trace.h"

namespace {

bool same_bits(float a, float b) {
  u32 x, y;
  std::memcpy(&x, &a, 4);
  std::memcpy(&y, &b, 4);
  return x == y;
}

Vec3 random_dir(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  for (;;) {
    Vec3 v = v3(n(rng), n(rng), n(rng));
    if (dot(v, v) > 1e-6f) return normalize(v);
  }
}

// A secondary ray as trace_tree queues it.
struct Query {
  Ray ray;
  u32 skip;
  int cls;
};

enum Class {
  kSpawned,
  kInside,
  kGrazing,
  kFloorParallel,
  kRim,
  kApex,
  kOnlyMiss,
  kRandom,
  kClasses
};
const char* const kClassName[kClasses] = {"spawned", "inside glass", "grazing",   "floor-parallel",
                                          "cap rim", "cone apex",    "only-miss", "random"};

// trace_tree's spawn at a hit of `ray` on object id: the reflected (k = 0)
// or refracted (k = 1) ray with its origin and skip. False when the
// material casts no such ray.
bool spawn(const Scene& s, const Ray& ray, int id, Hit hit, int k, Query& q) {
  const Object& obj = s.objects[id];
  const Material& m = obj.mat;
  hit_normal(obj.shape, ray, hit);
  Vec3 N = hit.normal;
  Vec3 p = ray.org + ray.dir * hit.t;
  float off = spawn_offset(p, spawn_scale(obj.shape, hit));
  float eta = 1, cosI = 1, sin2T = 0;
  bool tir = false;
  if (k) {
    if (!(m.transmit > 0)) return false;
    eta = hit.front ? 1.0f / m.ior : m.ior;
    cosI = dot(N, -ray.dir);
    sin2T = eta * eta * (1.0f - cosI * cosI);
    tir = sin2T > 1.0f;
    if (tir) return false;
  }
  Vec3 D = k ? normalize(ray.dir * eta + N * (eta * cosI - rt_sqrt(1.0f - sin2T)), ray.dir)
             : ray.dir - N * (2.0f * dot(N, ray.dir));
  float d = dot(D, N);
  u32 self = 1u << id;
  q.skip = leaves_for_good_dot(obj.shape, hit, d) ? self
           : (s.aloneMask & self) && off <= 0.5f * kAloneSlack * obj.shape.size
               ? (u32)(id + 1) << kOnlyShift
               : 0;
  q.ray = Ray{spawn_origin_dot(p, N, d, off), D};
  q.cls = (!hit.front && closed_convex(obj.shape)) || (k && hit.front) ? kInside : kSpawned;
  return true;
}

// A point on object id's surface seen from `from` (a hit of a ray towards
// the object's bound), or false.
bool surface_hit(const Scene& s, std::mt19937& rng, int id, Ray& ray, Hit& hit) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Vec3 c = v3(s.boundX[id], s.boundY[id], s.boundZ[id]);
  float r = s.unboundedMask >> id & 1 ? 6.0f : s.boundR[id];
  Vec3 from = c + random_dir(rng) * (r * 1.5f + 4.0f);
  if (s.unboundedMask >> id & 1) from.y = 0.5f + 6.0f * (u(rng) + 1.0f);
  Vec3 to = c + v3(u(rng), u(rng), u(rng)) * r;
  ray = Ray{from, normalize(to - from)};
  return find_hit(s, ray, 0, hit) == id;
}

struct Tally {
  long lanes = 0, masked = 0, hits = 0, bad = 0, badMasked = 0, onlyMisses = 0;
  long cls[kClasses] = {}, pieces[3] = {};
  long kind[kEmpty + 1] = {};
};

// One packet: the lanes of `mask` hold q[0..3]; the others random junk.
void check_packet(const Scene& s, const Query q[4], u32 mask, std::mt19937& rng, Tally& t) {
  f4 org[3], dir[3];
  u32 skip[4];
  std::uniform_real_distribution<float> junk(-1e3f, 1e3f);
  for (int k = 0; k < 4; ++k) {
    bool in = mask >> k & 1;
    Ray r = in ? q[k].ray : Ray{v3(junk(rng), junk(rng), junk(rng)), v3(junk(rng), 0.0f, -1.0f)};
    if (!in && (rng() & 1)) r.dir.x = __builtin_nanf("");
    org[0][k] = r.org.x, org[1][k] = r.org.y, org[2][k] = r.org.z;
    dir[0][k] = r.dir.x, dir[1][k] = r.dir.y, dir[2][k] = r.dir.z;
    skip[k] = in ? q[k].skip : (u32)rng();
  }
  Hits4 out;
  nearest4(s, org, dir, skip, mask, out);
  for (int k = 0; k < 4; ++k) {
    if (!(mask >> k & 1)) {
      ++t.masked;
      if (out.id[k] != -1) ++t.badMasked;
      continue;
    }
    ++t.lanes;
    ++t.cls[q[k].cls];
    Hit ref;
    int id = find_hit(s, q[k].ray, q[k].skip, ref);
    u32 only = q[k].skip >> kOnlyShift;
    if (only && id != (int)only - 1) ++t.onlyMisses;
    bool ok = out.id[k] == id;
    if (ok && id >= 0) {
      ++t.hits;
      ++t.kind[s.objects[id].shape.kind];
      if (s.objects[id].shape.kind == kCylinder || s.objects[id].shape.kind == kCone)
        ++t.pieces[ref.piece];
      ok = same_bits(out.t[k], ref.t) && out.piece[k] == ref.piece &&
           same_bits(out.local[k], ref.local);
    }
    if (!ok) {
      if (t.bad < 5)
        ADD_FAILURE() << "class " << kClassName[q[k].cls] << " lane " << k << ": id " << out.id[k]
                      << " vs " << id << ", t " << out.t[k] << " vs " << ref.t << ", piece "
                      << out.piece[k] << " vs " << (int)ref.piece;
      ++t.bad;
    }
  }
}

// Queries of every class for the scene at one time, checked in packets.
void check_frame(double time, int rays, std::mt19937& rng, Tally& t) {
  Scene s;
  build_timeline_scene(s, time);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  std::vector<Query> qs;
  while ((int)qs.size() < rays) {
    int id = (int)(rng() % (u32)s.numObjects);
    const Shape& sh = s.objects[id].shape;
    Ray ray;
    Hit hit;
    int cls = (int)(rng() % 8);
    if (cls <= 2) {
      // The spawned rays of a chain from a surface hit, down to depth 4.
      if (!surface_hit(s, rng, id, ray, hit)) continue;
      int at = id;
      for (int depth = 0; depth < 4 && at >= 0; ++depth) {
        Query q;
        int k = (int)(rng() & 1);
        if (!spawn(s, ray, at, hit, k, q) && !spawn(s, ray, at, hit, 1 - k, q)) break;
        qs.push_back(q);
        ray = q.ray;
        at = find_hit(s, ray, q.skip, hit);
      }
    } else if (cls == 3) {
      // Grazing: from a surface hit along the tangent plane, tilted by 0 or 1e-7 .. 1e-3.
      if (!surface_hit(s, rng, id, ray, hit)) continue;
      hit_normal(sh, ray, hit);
      Vec3 N = hit.normal, T = normalize(cross(N, random_dir(rng)));
      const float tilt[5] = {0.0f, 1e-7f, -1e-7f, 1e-5f, 1e-3f};
      Vec3 D = normalize(T + N * tilt[rng() % 5]);
      Vec3 p = ray.org + ray.dir * hit.t;
      float off = spawn_offset(p, spawn_scale(sh, hit));
      float d = dot(D, N);
      u32 skip = rng() & 1 ? (leaves_for_good_dot(sh, hit, d) ? 1u << id : 0) : 0;
      qs.push_back(Query{Ray{spawn_origin_dot(p, N, d, off), D}, skip, kGrazing});
    } else if (cls == 4) {
      // Parallel to the ground (y = 0 exactly) and within kPlaneCosFloat of it.
      Vec3 o = v3(7.0f * u(rng), 0.001f + 5.0f * u01(rng), 7.0f * u(rng));
      float a = 6.2831853f * u01(rng);
      const float dy[6] = {0.0f, 0.0f, 1e-9f, -3e-6f, kPlaneCosFloat * 0.999f, -kPlaneCosFloat};
      Vec3 D = normalize(v3(rt_cos(a), dy[rng() % 6], rt_sin(a)));
      qs.push_back(Query{Ray{o, D}, rng() % 4 == 0 ? (u32)(rng() & 0xff) : 0u, kFloorParallel});
    } else if (cls == 5 || cls == 6) {
      // A cap's rim (cylinders, cones' base) or a cone's apex, nudged by 0 .. 1e-5.
      int fr = -1;
      for (int i = 0; i < s.numObjects; ++i)
        if ((s.objects[i].shape.kind == kCylinder || s.objects[i].shape.kind == kCone) &&
            (fr < 0 || rng() % 2))
          fr = i;
      if (fr < 0) continue;
      const Shape& f = s.objects[fr].shape;
      Vec3 axis = f.b, side = normalize(cross(axis, random_dir(rng)));
      Vec3 target;
      bool apex = cls == 6 && (f.r1 == 0 || f.r0 == 0);
      if (apex)
        target = f.r1 == 0 ? f.a + axis * f.h : f.a;
      else {
        bool top = rng() & 1;
        target = f.a + axis * (top ? f.h : 0.0f) + side * (top ? f.r1 : f.r0);
      }
      const float nudge[4] = {0.0f, 1e-7f, 1e-6f, 1e-5f};
      target = target + random_dir(rng) * nudge[rng() % 4];
      // From another object's surface (a spawned origin) or from open space.
      Vec3 o;
      if (rng() & 1 && surface_hit(s, rng, id, ray, hit) && id != fr)
        o = ray.org + ray.dir * hit.t + v3(0.0f, 1e-3f, 0.0f);
      else
        o = target + random_dir(rng) * (0.5f + 6.0f * u01(rng));
      qs.push_back(Query{Ray{o, normalize(target - o)}, 0u, apex ? kApex : kRim});
    } else {
      // A lone solid named but missed (a ray from near it pointing past or
      // away), or a random ray with random object skips.
      bool only = rng() & 1;
      int lone = -1;
      for (int i = 0; i < s.numForeground; ++i)
        if (s.aloneMask >> i & 1 && (lone < 0 || rng() % 2)) lone = i;
      if (only && lone >= 0) {
        Vec3 c = v3(s.boundX[lone], s.boundY[lone], s.boundZ[lone]);
        Vec3 o = c + random_dir(rng) * (s.boundR[lone] * (1.0f + 0.2f * u01(rng)));
        Vec3 D = random_dir(rng);
        if (dot(D, o - c) < 0) D = -D; // away from the centre: mostly misses
        qs.push_back(Query{Ray{o, D}, (u32)(lone + 1) << kOnlyShift, kOnlyMiss});
      } else {
        Vec3 o = v3(9.0f * u(rng), 0.01f + 8.0f * u01(rng), 9.0f * u(rng));
        qs.push_back(Query{Ray{o, random_dir(rng)}, (u32)(rng() & rng() & 0xff), kRandom});
      }
    }
  }
  // Packets of four shuffled queries, random masks (at least one lane).
  std::shuffle(qs.begin(), qs.end(), rng);
  for (size_t i = 0; i + 4 <= qs.size(); i += 4) {
    u32 mask = rng() % 3 ? 15u : 1u + (u32)(rng() % 15);
    check_packet(s, &qs[i], mask, rng, t);
  }
}

TEST(Nearest4, SecondaryRaysOfBothScenesMatchFindHitBitForBit) {
  std::mt19937 rng(1812);
  Tally t;
  const double times[] = {1.0,  1.5,  9.0,  12.0, 12.75, 13.0,  20.0,
                          29.0, 34.0, 38.5, 44.0, 50.0,  58.75, 63.0};
  for (double time : times)
    check_frame(time, 10000, rng, t);
  EXPECT_EQ(t.bad, 0);
  EXPECT_EQ(t.badMasked, 0);
  long total = 0;
  for (int c = 0; c < kClasses; ++c) {
    total += t.cls[c];
    EXPECT_GT(t.cls[c], 2000) << kClassName[c];
  }
  EXPECT_GE(total, 100000);
  EXPECT_EQ(total, t.lanes);
  // Enough of each shape and piece, and of named solids missed.
  EXPECT_GT(t.kind[kSphere], 10000);
  EXPECT_GT(t.kind[kPlane], 3000);
  EXPECT_GT(t.kind[kTriangle], 3000);
  EXPECT_GT(t.kind[kCone], 2000);
  EXPECT_GT(t.kind[kCylinder], 2000);
  EXPECT_GT(t.pieces[kPieceSide], 2000);
  EXPECT_GT(t.pieces[kPieceBase], 300);
  EXPECT_GT(t.pieces[kPieceTop], 300);
  EXPECT_GT(t.onlyMisses, 2000);
  EXPECT_GT(t.masked, 10000);
  std::printf("lanes %ld (masked %ld), hits %ld: sphere %ld plane %ld cylinder %ld cone %ld "
              "triangle %ld; pieces %ld/%ld/%ld; only missed %ld\n",
              t.lanes, t.masked, t.hits, t.kind[kSphere], t.kind[kPlane], t.kind[kCylinder],
              t.kind[kCone], t.kind[kTriangle], t.pieces[0], t.pieces[1], t.pieces[2],
              t.onlyMisses);
  for (int c = 0; c < kClasses; ++c)
    std::printf("  %s: %ld\n", kClassName[c], t.cls[c]);
}

} // namespace
