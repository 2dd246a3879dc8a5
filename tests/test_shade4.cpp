// test_shade4.cpp - the four-lane shading point (packet/shade.h) and its
// maths (packet/pow4.h) against the scalar code, bit for bit.
//
// rt_pow4, rt_log2_4, rt_exp2_4 and rt_exp_nonpositive4 against rt_pow,
// rt_log2, rt_exp2 and rt_exp_nonpositive over
// millions of seeded inputs and the edge cases (zeros of both signs,
// denormals, 1, NaN, Inf, the range ends of exp2, the kSpecExp cut of
// Phong's power, exp's underflow); trace_primary4() against trace_primary() per lane (colour
// bits, records, ray counts) on packets of 1 to 4 pixels that mix objects,
// misses and silhouette pixels (grazing rays) over frames of both scenes;
// shadow_mask4() against shadow_mask() per lane at the edges of its tests
// (rays ending at a bound, grazing it, lights inside bounds), and the
// shading point with lights moved into and beside the objects' bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "packet/packet.h"
#include "packet/pow4.h"
#include "packet/shade.h"
#include "scenes.h"
#include "shade4_check.h"

namespace {

// Counts of lanes of the three functions that differ from the scalar.
struct PowMismatch {
  long log2 = 0, exp2 = 0, pow = 0, lanes = 0;
};

void compare4(const float x[4], const float y[4], PowMismatch& m) {
  f4 x4 = {x[0], x[1], x[2], x[3]}, y4 = {y[0], y[1], y[2], y[3]};
  f4 l = rt_log2_4(x4), e = rt_exp2_4(y4), p = rt_pow4(x4, y4);
  for (int k = 0; k < 4; ++k) {
    m.log2 += !same_bits(l[k], rt_log2(x[k]));
    m.exp2 += !same_bits(e[k], rt_exp2(y[k]));
    m.pow += !same_bits(p[k], rt_pow(x[k], y[k]));
    ++m.lanes;
  }
}

// lanes_of() (packet/lanes.h, one compare since round thirteen) against its
// definition: lane k all ones where bit k of the argument is set, else zero,
// for every nibble and with bits above the fourth set; lane_bits() inverts it.
TEST(Shade4, LanesOfSetsLaneKExactlyWhereBitKIs) {
  int wrong = 0;
  for (u32 bits = 0; bits < 64; ++bits) {
    i4 m = lanes_of(bits);
    for (int k = 0; k < 4; ++k)
      wrong += m[k] != ((bits >> k & 1) ? -1 : 0);
    wrong += lane_bits(m) != (bits & 15);
  }
  EXPECT_EQ(wrong, 0);
}

TEST(Shade4, PowLog2Exp2MatchTheScalarBitForBitOnSeededInputs) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), expo(1.0f, 400.0f);
  std::uniform_real_distribution<float> wide(-140.0f, 140.0f);
  std::uniform_int_distribution<u32> bits(0, 0xffffffffu);
  PowMismatch m;
  for (int i = 0; i < 1000000; ++i) {
    float x[4], y[4];
    for (int k = 0; k < 4; ++k) {
      switch ((i + k) % 4) {
      case 0: // Phong's V.R and exponent
        x[k] = unit(rng);
        y[k] = expo(rng);
        break;
      case 1: // V.R near 1, where the power is computed
        x[k] = 1.0f - unit(rng) * 0.05f;
        y[k] = expo(rng);
        break;
      case 2: // any float bits (NaN, Inf, denormals, negatives)
        x[k] = rt_from_bits(bits(rng));
        y[k] = rt_from_bits(bits(rng));
        break;
      default: // exp2 across its range and beyond
        x[k] = unit(rng) * 1e3f;
        y[k] = wide(rng);
        break;
      }
    }
    compare4(x, y, m);
  }
  EXPECT_EQ(m.log2, 0);
  EXPECT_EQ(m.exp2, 0);
  EXPECT_EQ(m.pow, 0);
  EXPECT_EQ(m.lanes, 4000000);
}

// Cook-Torrance's D: rt_exp_nonpositive() of x <= 0 (and of anything
// else, whose lanes must match too), seeded and at the edges.
TEST(Shade4, ExpNonpositiveMatchesTheScalarBitForBit) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> neg(-100.0f, 0.0f), small(-1.0f, 0.0f);
  std::uniform_int_distribution<u32> bits(0, 0xffffffffu);
  const float inf = rt_from_bits(0x7f800000u), nan = rt_from_bits(0x7fc00000u);
  const float edges[] = {0.0f,     -0.0f,     -1e-45f,  -1e-38f,  -87.3365f, -87.33655f,
                         -87.336f, -87.34f,   -88.0f,   -1e9f,    -inf,      nan,
                         -0.5f,    -0.34657f, -0.3466f, -0.6931f, -1.0f,     -16.0f};
  long differ = 0, lanes = 0;
  for (int i = 0; i < 1000000; ++i) {
    f4 x;
    for (int k = 0; k < 4; ++k) {
      int r = (i + k) % 8;
      x[k] = r < 4 ? neg(rng)
                   : (r < 6 ? small(rng)
                            : (r < 7 ? rt_from_bits(bits(rng)) : edges[(i / 8 + k) % 18]));
    }
    f4 e = rt_exp_nonpositive4(x);
    for (int k = 0; k < 4; ++k) {
      differ += !same_bits(e[k], rt_exp_nonpositive(x[k]));
      ++lanes;
    }
  }
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(lanes, 4000000);
}

TEST(Shade4, PowLog2Exp2MatchTheScalarOnEdgeInputs) {
  const float inf = rt_from_bits(0x7f800000u), nan = rt_from_bits(0x7fc00000u);
  std::vector<float> xs = {
      0.0f,          -0.0f,      1e-45f,      -1e-45f,    1.17549435e-38f, 1.1754942e-38f, 1.0f,
      0.99999994f,   1.0000001f, 1.41421356f, 1.4142135f, 1.4142137f,      0.5f,           2.0f,
      3.4028235e38f, inf,        -inf,        nan,        -1.0f,           0.9f,           0.92f,
      0.95f,         0.98f,      0.999f,      1e-20f};
  std::vector<float> ys = {0.0f,    -0.0f,   1.0f,   40.0f,  60.0f,  120.0f,  200.0f, -126.0f,
                           -125.5f, -126.5f, 127.0f, 127.5f, 128.0f, -1e9f,   1e9f,   inf,
                           -inf,    nan,     0.5f,   -0.5f,  1e-45f, -1e-45f, 1.5f,   -1.5f};
  // The kSpecExp cut: h (1 - V.R) = 16 at V.R = 1 - 16 / h, and a few ulps
  // either side, for the scenes' exponents.
  for (float h : {40.0f, 60.0f, 120.0f, 200.0f}) {
    float v = 1.0f - kSpecExp / h;
    for (int s = -3; s <= 3; ++s) {
      float w = v;
      for (int i = 0; i < (s < 0 ? -s : s); ++i)
        w = std::nextafter(w, s < 0 ? 0.0f : 2.0f);
      xs.push_back(w);
    }
    ys.push_back(h);
  }
  PowMismatch m;
  for (size_t i = 0; i < xs.size(); ++i)
    for (size_t j = 0; j < ys.size(); j += 4) {
      float x[4], y[4];
      for (int k = 0; k < 4; ++k) {
        x[k] = xs[(i + k) % xs.size()];
        y[k] = ys[(j + k) % ys.size()];
      }
      compare4(x, y, m);
    }
  EXPECT_EQ(m.log2, 0);
  EXPECT_EQ(m.exp2, 0);
  EXPECT_EQ(m.pow, 0);
  EXPECT_GT(m.lanes, 1000);
}

// trace_primary4 of up to four pixels against trace_primary() of each.
struct Counts : LaneCounts {
  long misses = 0, mixed = 0;
  long backs = 0; // lanes whose primary ray hits a surface from behind (inside a solid)
};

void compare_lanes(const Scene& s, const CameraRays& cam, const float* x, const float* y, int n,
                   Counts& c) {
  LaneCheck r = c.check(s, cam, x, y, n);
  bool mixed = false;
  for (int k = 0; k < n; ++k) {
    c.misses += r.id[k] < 0;
    c.backs += r.id[k] >= 0 && !r.front[k];
    mixed |= r.id[k] != r.id[0];
  }
  c.mixed += mixed;
}

// Every lane compared had the per-lane colour bits, record and ray counts.
void expect_all_match(const Counts& c) {
  EXPECT_EQ(c.color, 0) << "colours differ on " << c.color << " of " << c.lanes;
  EXPECT_EQ(c.path, 0) << "records differ on " << c.path;
  EXPECT_EQ(c.stats, 0) << "ray counts differ in " << c.stats << " packets";
}

TEST(Shade4, PacketsOfMixedObjectsMissesAndSilhouettesMatchPerLane) {
  std::mt19937 rng(1414);
  std::uniform_real_distribution<float> t1(0.0f, 32.0f), t2(32.0f, 64.0f);
  std::uniform_int_distribution<int> lanes(1, 4);
  const int w = 160, h = 120;
  Counts c;
  long silhouettes = 0;
  for (int frame = 0; frame < 24; ++frame) {
    Scene s;
    build_timeline_scene(s, frame < 12 ? t1(rng) : t2(rng)); // Phong, then Cook-Torrance
    CameraRays cam = camera_rays(s, w, h);
    std::vector<int> ids(w * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        ids[y * w + x] = first_hit_object(s, primary_ray(cam, (float)x, (float)y));
    // Pixels on an object's silhouette (a neighbour sees another object or
    // nothing): grazing rays, and packets across the edge.
    std::vector<int> edge;
    for (int y = 1; y + 1 < h; ++y)
      for (int x = 1; x + 1 < w; ++x) {
        int i = ids[y * w + x];
        if (i != ids[y * w + x + 1] || i != ids[(y + 1) * w + x] || i != ids[y * w + x - 1])
          edge.push_back(y * w + x);
      }
    silhouettes += (long)edge.size();
    std::uniform_int_distribution<int> anyPx(0, w * h - 1);
    for (size_t e = 0; e < edge.size(); e += 3) {
      int n = lanes(rng);
      float xs[4], ys[4];
      for (int k = 0; k < n; ++k) {
        // Edge pixels, their right neighbours and random ones, mixed.
        int p = k == 0 ? edge[e] : (k == 1 ? edge[e] + 1 : anyPx(rng));
        xs[k] = (float)(p % w);
        ys[k] = (float)(p / w);
      }
      compare_lanes(s, cam, xs, ys, n, c);
    }
  }
  expect_all_match(c);
  EXPECT_GT(c.lanes, 10000);
  EXPECT_GT(silhouettes, 5000);
  EXPECT_GT(c.misses, 100); // lanes that see nothing
  EXPECT_GT(c.mixed, 1000); // packets whose lanes see different objects
}

// Cameras anywhere around (and inside) the objects of both scenes, at
// fractional pixel positions: primary hits from inside a glass sphere or
// cylinder (the root's `inside` and `exits` cases), from below the floor
// and the stage, at every angle; packets of 1 to 4 lanes.
TEST(Shade4, RandomCamerasAndFractionalPixelsMatchPerLane) {
  std::mt19937 rng(31337);
  std::uniform_real_distribution<float> tt(0.0f, 64.0f), pos(-6.0f, 6.0f);
  std::uniform_real_distribution<float> px(0.0f, 63.0f), py(0.0f, 47.0f);
  std::uniform_int_distribution<int> lanes(1, 4);
  Counts c;
  long insideCams = 0;
  for (int frame = 0; frame < 60; ++frame) {
    Scene s;
    build_timeline_scene(s, tt(rng));
    for (int cam = 0; cam < 8; ++cam) {
      if (cam < 3) {
        // Inside a sphere or cylinder of the scene: at its centre, off by a
        // fraction of its size.
        const Shape& sh = s.objects[(frame + cam) % s.numForeground].shape;
        Vec3 centre = sh.kind == kSphere ? sh.a : sh.a + sh.b * (0.5f * sh.h);
        float r = sh.kind == kSphere ? sh.r0 : 0.5f * sh.r0;
        s.camera.pos = centre + v3(pos(rng), pos(rng), pos(rng)) * (0.1f * r);
        s.camera.target = s.camera.pos + v3(pos(rng), pos(rng), pos(rng));
        insideCams +=
            first_hit_object(s, Ray{s.camera.pos, normalize(s.camera.target - s.camera.pos)}) >= 0;
      } else {
        s.camera.pos = v3(pos(rng), pos(rng) * 0.5f + 2.0f, pos(rng));
        s.camera.target = v3(pos(rng) * 0.3f, 1.5f, pos(rng) * 0.3f);
      }
      CameraRays cr = camera_rays(s, 64, 48);
      for (int p = 0; p < 40; ++p) {
        float xs[4], ys[4];
        for (int k = 0; k < 4; ++k) {
          xs[k] = px(rng);
          ys[k] = py(rng);
        }
        compare_lanes(s, cr, xs, ys, lanes(rng), c);
      }
    }
  }
  expect_all_match(c);
  EXPECT_GT(c.lanes, 30000);
  EXPECT_GT(insideCams, 100);
  EXPECT_GT(c.backs, 5000); // primary hits from inside a solid
  EXPECT_GT(c.misses, 100);
  EXPECT_GT(c.mixed, 1000);
}

// Packets whose lanes all see one cylinder or cone (shade15: their normals
// in lanes, frustum_outward()'s steps): sides and both caps, from outside
// and from inside the solid, at cameras around both scenes' frustums.
TEST(Shade4, OneFrustumPacketsMatchPerLaneOnSidesAndCaps) {
  std::mt19937 rng(1515);
  std::uniform_real_distribution<float> tt(0.0f, 64.0f), pos(-1.0f, 1.0f), frac(0.0f, 1.0f);
  std::uniform_int_distribution<int> lanes(1, 4);
  const int w = 64, h = 48;
  Counts c;
  long piece[3] = {0, 0, 0}, packets = 0;
  for (int frame = 0; frame < 48; ++frame) {
    Scene s;
    build_timeline_scene(s, tt(rng));
    int frustums[kMaxObjects], nf = 0;
    for (int i = 0; i < s.numForeground; ++i)
      if (s.objects[i].shape.kind == kCylinder || s.objects[i].shape.kind == kCone)
        frustums[nf++] = i;
    ASSERT_GT(nf, 0);
    for (int cam = 0; cam < 4; ++cam) {
      // Looking at a frustum's middle from around it (a quarter of the
      // cameras inside it, near its axis), above and below its caps.
      const Shape& sh = s.objects[frustums[(frame + cam) % nf]].shape;
      Vec3 mid = sh.a + sh.b * (0.5f * sh.h);
      float d = cam == 0 ? 0.2f * rt_max(sh.r0, sh.r1) : 2.0f + 4.0f * frac(rng);
      s.camera.pos = mid + normalize(v3(pos(rng), pos(rng), pos(rng))) * d;
      s.camera.target = mid + v3(pos(rng), pos(rng), pos(rng)) * (0.5f * sh.h);
      CameraRays cr = camera_rays(s, w, h);
      float ox = frac(rng), oy = frac(rng);
      std::vector<int> ids(w * h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          ids[y * w + x] = first_hit_object(s, primary_ray(cr, (float)x + ox, (float)y + oy));
      for (int y = 0; y + 1 < h; y += 2)
        for (int x = 0; x + 1 < w; x += 2) {
          int i = ids[y * w + x];
          if (i < 0 || (s.objects[i].shape.kind != kCylinder && s.objects[i].shape.kind != kCone))
            continue;
          if (ids[y * w + x + 1] != i || ids[(y + 1) * w + x] != i || ids[(y + 1) * w + x + 1] != i)
            continue;
          float xs[4], ys[4];
          for (int k = 0; k < 4; ++k) {
            xs[k] = (float)(x + (k & 1)) + ox;
            ys[k] = (float)(y + (k >> 1)) + oy;
            Hit hk;
            first_hit(s, primary_ray(cr, xs[k], ys[k]), hk);
            ++piece[hk.piece < 3 ? hk.piece : 0];
          }
          compare_lanes(s, cr, xs, ys, lanes(rng), c);
          ++packets;
        }
    }
  }
  expect_all_match(c);
  EXPECT_EQ(c.mixed, 0);
  EXPECT_GT(packets, 50000);
  // Hit::piece of a frustum (shapes.cpp): 0 the side, 1 the base, 2 the top cap.
  EXPECT_GT(piece[0], 150000);
  EXPECT_GT(piece[1], 30000);
  EXPECT_GT(piece[2], 3000);
  EXPECT_GT(c.backs, 50000); // from inside the solid
}

// A float n ulps from x (n may be negative), towards +-Inf.
float ulps(float x, int n) {
  for (; n > 0; --n)
    x = std::nextafter(x, 1e30f);
  for (; n < 0; ++n)
    x = std::nextafter(x, -1e30f);
  return x;
}

// A scene of random spheres (some around a light), a foreground plane (an
// unbounded object), an empty shape (no ray passes its bound) and up to four
// lights, some inside a sphere's bound: what shadow_mask() handles that the
// bench scenes may not hold.
void random_bounds_scene(Scene& s, std::mt19937& rng) {
  std::uniform_real_distribution<float> pos(-5.0f, 5.0f), rad(0.2f, 2.0f), u(0.0f, 1.0f);
  const Material m = {{0.5f, 0.5f, 0.5f}, 0.5f, 0.5f, 40.0f, 0.2f, 0.3f, 1.5f, 0.3f, 0.04f};
  scene_clear(s);
  int n = 3 + (int)(rng() % 6); // 3..8 objects
  Vec3 lights[kMaxLights];
  int numLights = 1 + (int)(rng() % kMaxLights);
  for (int l = 0; l < numLights; ++l)
    lights[l] = v3(pos(rng), pos(rng), pos(rng));
  for (int i = 0; i < n; ++i) {
    int kind = (int)(rng() % 8);
    if (kind == 0)
      scene_add(s, make_plane(normalize(v3(pos(rng), pos(rng), pos(rng)), v3(0, 1, 0)), pos(rng)),
                m);
    else if (kind == 1)
      scene_add(s, make_triangle(v3(0, 0, 0), v3(1, 1, 1), v3(2, 2, 2)), m); // kEmpty
    else if (kind < 4) {
      // A sphere around a light: the light inside the bound (lightC <= 0).
      Vec3 c = lights[rng() % numLights] + v3(pos(rng), pos(rng), pos(rng)) * 0.1f;
      scene_add(s, make_sphere(c, rad(rng)), m);
    } else
      scene_add(s, make_sphere(v3(pos(rng), pos(rng), pos(rng)), rad(rng)), m);
  }
  for (int l = 0; l < numLights; ++l)
    scene_add_light(s, lights[l], v3(1, 1, 1));
}

// shadow_mask4() against shadow_mask() lane by lane, bit for bit: seeded
// rays to every light of timeline frames of both scenes and of random
// scenes, at the edges of each of its tests: segments that end at a bound
// (dist = beta - R +- a few ulps), lines that graze it (beta^2 = c), lights
// inside a bound (c <= 0), unbounded and empty objects, and ranges that
// leave objects out.
TEST(Shade4, ShadowMask4MatchesShadowMaskPerLane) {
  std::mt19937 rng(9090);
  std::uniform_real_distribution<float> tt(0.0f, 64.0f), sym(-1.0f, 1.0f), len(0.0f, 25.0f);
  long lanes = 0, differ = 0, none = 0, some = 0, atEnd = 0, grazing = 0, lightInside = 0;
  long unbounded = 0;
  for (int sc = 0; sc < 400; ++sc) {
    Scene s;
    if (sc % 2)
      random_bounds_scene(s, rng);
    else
      build_timeline_scene(s, tt(rng));
    u32 fg = (1u << s.numForeground) - 1;
    unbounded += (s.unboundedMask & fg) != 0;
    for (int l = 0; l < s.numLights; ++l)
      for (int i = 0; i < s.numForeground; ++i)
        lightInside += s.lightC[l][i] <= 0;
    for (int l = 0; l < s.numLights; ++l)
      for (int r = 0; r < 100; ++r) {
        f4 L[3], dist;
        alignas(16) u32 range[4];
        for (int k = 0; k < 4; ++k) {
          int i = (int)(rng() % s.numForeground); // a bound the ray is built about
          Vec3 f = {s.lightFX[l][i], s.lightFY[l][i], s.lightFZ[l][i]};
          Vec3 dir = normalize(v3(sym(rng), sym(rng), sym(rng)), v3(0, 1, 0));
          float d = len(rng);
          int kind = (r + k) % 4;
          if (kind == 1 || kind == 2) {
            // Along -L from the light towards the bound (beta > 0), or
            // grazing it: beta = f.L = sqrt(c).
            Vec3 u = normalize(f, v3(0, 1, 0));
            Vec3 w = normalize(cross(u, dir), v3(1, 0, 0));
            float c = s.lightC[l][i], fl = rt_sqrt(dot(f, f));
            float cosT = kind == 2 && c > 0 && fl > 0 ? rt_sqrt(c) / fl : 1.0f - 0.2f * sym(rng);
            cosT = rt_clamp(cosT, -1.0f, 1.0f);
            dir = normalize(u * cosT + w * rt_sqrt(1.0f - cosT * cosT), u);
            for (float* q : {&dir.x, &dir.y, &dir.z})
              *q = ulps(*q, (int)(rng() % 5) - 2);
          }
          // shadow_mask's beta, in its order.
          float beta = s.lightFX[l][i] * dir.x + s.lightFY[l][i] * dir.y + s.lightFZ[l][i] * dir.z;
          if (kind == 1 || kind == 3) d = ulps(beta - s.boundR[i], (int)(rng() % 7) - 3);
          atEnd += (kind == 1 || kind == 3) && d > 0;
          grazing += kind == 2 && s.lightC[l][i] > 0 &&
                     rt_abs(beta * beta - s.lightC[l][i]) <= 1e-5f * s.lightC[l][i];
          L[0][k] = dir.x;
          L[1][k] = dir.y;
          L[2][k] = dir.z;
          dist[k] = d;
          int rk = (int)(rng() % 3);
          range[k] = rk == 0 ? fg : (rk == 1 ? fg & ~(1u << i) : (u32)rng() & fg);
        }
        alignas(16) u32 got[4];
        *(i4*)got = shadow_mask4(s, l, L[0], L[1], L[2], dist, *(const i4*)range);
        for (int k = 0; k < 4; ++k) {
          u32 want = shadow_mask(s, l, Vec3{L[0][k], L[1][k], L[2][k]}, dist[k], range[k]);
          differ += got[k] != want;
          none += want == 0;
          some += (want & ~s.unboundedMask) != 0;
          ++lanes;
        }
      }
  }
  EXPECT_EQ(differ, 0) << "of " << lanes << " lanes";
  EXPECT_GT(none, 100000);
  EXPECT_GT(some, 50000);
  EXPECT_GT(atEnd, 60000);
  EXPECT_GT(grazing, 30000);
  EXPECT_GT(lightInside, 200);
  EXPECT_GT(unbounded, 50);
}

// The shading point with the lights moved: into a foreground object's bound
// (lightC <= 0), just outside it, and anywhere; packets of random pixels
// against per-lane trace_primary() (colour bits, records, ray counts).
TEST(Shade4, LightsInAndBesideBoundsMatchPerLane) {
  std::mt19937 rng(6161);
  std::uniform_real_distribution<float> tt(0.0f, 64.0f), sym(-1.0f, 1.0f), frac(0.0f, 1.0f);
  std::uniform_real_distribution<float> px(0.0f, 79.0f), py(0.0f, 59.0f);
  std::uniform_int_distribution<int> lanes(1, 4);
  Counts c;
  long inBound = 0;
  for (int frame = 0; frame < 64; ++frame) {
    Scene s;
    build_timeline_scene(s, tt(rng));
    move_lights(s, [&](int l, const Light& old) {
      int i = (int)(rng() % s.numForeground);
      Vec3 centre = {s.boundX[i], s.boundY[i], s.boundZ[i]};
      Vec3 dir = normalize(v3(sym(rng), sym(rng), sym(rng)), v3(0, 1, 0));
      int kind = (frame + l) % 3;
      return kind == 0   ? centre + dir * (0.9f * frac(rng) * s.boundR[i])
             : kind == 1 ? centre + dir * (s.boundR[i] * (1.0f + 0.05f * frac(rng)))
                         : old.pos + v3(sym(rng), sym(rng), sym(rng));
    });
    for (int l = 0; l < s.numLights; ++l)
      for (int i = 0; i < s.numForeground; ++i)
        inBound += s.lightC[l][i] <= 0;
    CameraRays cr = camera_rays(s, 80, 60);
    for (int p = 0; p < 400; ++p) {
      float xs[4], ys[4];
      float x0 = px(rng), y0 = py(rng);
      for (int k = 0; k < 4; ++k) {
        // Mostly 2x2 neighbours (packets of one object), some anywhere.
        bool near = p % 4 != 0;
        xs[k] = near ? x0 + (float)(k & 1) : px(rng);
        ys[k] = near ? y0 + (float)(k >> 1) : py(rng);
      }
      compare_lanes(s, cr, xs, ys, lanes(rng), c);
    }
  }
  expect_all_match(c);
  EXPECT_GT(c.lanes, 50000);
  EXPECT_GT(inBound, 30);
}

} // namespace
