// scenes.cpp - choreography of the two scenes (SPEC "The intro", thesis 5.6).
// World: y up, the ground at y = 0, units are roughly metres.
#include "scenes.h"

namespace {

// Each scene fades in over its first kFadeSeconds and out over its last, so
// the cuts at 32 s and 64 s pass through black instead of popping. Every
// light term is linear in the lights, ambient and background, so scaling
// those three fades the whole picture exactly.
constexpr float kFadeSeconds = 0.8f;

void apply_fade(Scene& s, float t) {
  float f = smooth01(t / kFadeSeconds) * smooth01((kSceneSeconds - t) / kFadeSeconds);
  for (int i = 0; i < s.numLights; ++i)
    s.lights[i].color = s.lights[i].color * f;
  s.ambient = s.ambient * f;
  s.background = s.background * f;
}

// What a scene starts from: its look (shading model, background, ambient,
// lights) and its materials, as constant tables (STYLE.md 8: data
// compresses better than the code that would store each float; docs/win32.md
// gives the bytes). Phong materials have roughness 1 and f0 0,
// Cook-Torrance ones shininess 1.
struct SceneLook {
  ShadingModel model;
  Vec3 background, ambient;
  Light lights[2];
};

void begin_scene(Scene& s, const SceneLook& look) {
  scene_clear(s);
  s.model = look.model;
  s.background = look.background;
  s.ambient = look.ambient;
  s.maxDepth = 5;
  for (const Light& l : look.lights)
    scene_add_light(s, l.pos, l.color);
}

// Unit vector tilted `tilt` radians from +y towards azimuth `azimuth`.
Vec3 tilted_up(float tilt, float azimuth) {
  float st = rt_sin(tilt);
  return v3(st * rt_cos(azimuth), rt_cos(tilt), st * rt_sin(azimuth));
}

// Scene 1: two cones one above the other; a red mirror sphere sways between
// them and, on its rising swing, knocks the upper (inverted) cone, which
// rocks with a damped swing and then sinks slowly towards the lower one. Two
// glass spheres orbit around them in opposite directions, one above the
// other, over a dark mirror floor. A warm key light high at the front left,
// a cool rim light behind right.
const SceneLook kLook1 = {
    kPhong,
    {0.01f, 0.012f, 0.03f},
    {0.04f, 0.04f, 0.07f},
    {{{-6.0f, 9.0f, -6.0f}, {1.0f, 0.86f, 0.7f}}, {{5.0f, 6.0f, 6.0f}, {0.35f, 0.45f, 0.95f}}}};
// Phong: colour, diffuse, specular, shininess, reflect, transmit, ior, 1, 0.
const Material kLowerConeMat = {{0.15f, 0.3f, 1.0f}, 0.7f, 0.8f, 60.0f, 0.2f, 0, 1, 1, 0};
const Material kUpperConeMat = {{1.0f, 0.62f, 0.12f}, 0.7f, 0.8f, 60.0f, 0.2f, 0, 1, 1, 0};
const Material kBallMat = {{1.0f, 0.12f, 0.1f}, 0.3f, 1.0f, 120.0f, 0.7f, 0, 1, 1, 0};
const Material kGlass1 = {{0.9f, 0.96f, 1.0f}, 0.03f, 1.0f, 200.0f, 0.1f, 0.88f, 1.5f, 1, 0};
const Material kFloorMat = {{0.3f, 0.32f, 0.45f}, 0.5f, 0.4f, 40.0f, 0.55f, 0, 1, 1, 0};

} // namespace

// The objects that never move, as the Shapes their builders return (hex
// floats, bit for bit; tests/test_scenes.cpp checks each against its
// builder, so a changed builder or argument fails there).
// make_cone(v3(0, 0, 0), v3(0, 1, 0), 1.5f, 0.32f, 1.75f, kCapBase):
// scene 1's lower cone, a frustum open at its top, standing on the floor.
const Shape kLowerCone = {
    kCone, kCapBase,  {0, 0, 0}, {0, 1, 0},     {-0x1.593bfcp-1f, 0x1.ap+1f, 0x1p-1f}, 1.5f, 0.32f,
    1.75f, {0, 0, 0}, 0,         0x1.bc8ee6p+0f};
// make_plane(v3(0, 1, 0), 0.0f): scene 1's floor, flagged kInlinePlane
// (shapes.h: the resumed tree tests it without a call).
const Shape kFloor = {kPlane, kInlinePlane, {0, 1, 0}, {0, 0, 0}, {0, 0, 0}, 0, 0,
                      0,      {0, 0, 0},    0,         0};
// make_triangle(a, c, b) and make_triangle(a, d, c) with a, b, c, d =
// (-7, 0, -7), (7, 0, -7), (7, 0, 7), (-7, 0, 7): scene 2's stage, a square,
// the first flagged kPairNext (shapes.h: a triangle pair, the two halves
// tested by one intersect_pair() call in the resumed tree).
const Shape kStage[2] = {{kTriangle,
                          kPairNext,
                          {-7, 0, -7},
                          {7, 0, 7},
                          {7, 0, -7},
                          0,
                          1,
                          0,
                          {0, 0x1.88p+0f, 0},
                          0x1.88p-16f,
                          0x1.4deb64p+3f},
                         {kTriangle,
                          0,
                          {-7, 0, -7},
                          {-7, 0, 7},
                          {7, 0, 7},
                          0,
                          1,
                          0,
                          {0, 0x1.88p+0f, 0},
                          0x1.88p-16f,
                          0x1.4deb64p+3f}};

// The stage's two triangles share one bound, a large sphere below the stage
// whose top is just above it (y = 1/16), instead of each triangle's own
// (radius 10.4 about its centroid, which holds every object of the scene,
// so every ray passed it): a ray from above y = 1/16 that goes up is then
// culled by its bound test (bound_mask, the packets' terms), as the
// triangles' side test would have turned it away, without that test
// (~38,500 sky-bound secondary rays a frame at 44 s; docs/tracer-speed.md,
// round nine). The corners (+-7, 0, +-7) lie 1024.0479 from the centre,
// 0.0146 inside the radius 1024.0625 (16385/16): that margin moves c = |f|^2
// - R^2 of the bound test by 2 R 0.0146 = 30, where the float terms (|f|^2
// ~ 2^20, ulp 1/16) carry under 1 of rounding: no ray that meets the stage
// is culled (tests/test_scenes.cpp: StageBoundHoldsTheStage).
const Bound kStageBound = {{0, -1024, 0}, 1024.0625f};

void build_scene1(Scene& s, float t) {
  begin_scene(s, kLook1);

  // The mirror sphere swings along x through the gap, rising a little each
  // pass, and its top meets the upper cone's apex at x = 0 at kKnock. From
  // then on its path opens from a line into a widening ellipse around the
  // cones, so it clears the cone as that sinks.
  constexpr float kKnock = 9.0f;  // seconds: the contact
  constexpr float kSwing = 0.55f; // rad/s of the swing phase
  constexpr float kBallR = 0.55f;
  constexpr float kApexY = 3.55f; // the upper cone's apex before it sinks
  float since = t - kKnock;
  float phase = kSwing * since; // x = 0 at the knock
  float open = smooth01(since / 6.0f);
  float ballY = kApexY - kBallR - 0.5f * smooth01(1.0f - t / kKnock) - 0.4f * open;
  Vec3 ball = v3((1.9f + 0.5f * open) * rt_sin(phase), ballY + 0.06f * rt_sin(2.1f * since),
                 -2.2f * open * rt_cos(phase));

  // Upper cone: apex down, hanging from its base. The knock sets it rocking
  // about the base with a damped swing; then it sinks slowly by itself until
  // its apex rests inside the lower cone's open top.
  constexpr float kUpperH = 1.9f;
  constexpr float kSink = 2.2f; // final apex height kApexY - kSink = 1.35
  float rock = 0, sink = 0;
  if (since > 0) {
    rock = 0.3f * rt_exp(-since / 4.0f) * rt_sin(1.9f * since);
    sink = kSink * smooth01(since / 21.0f);
  }
  Vec3 down = tilted_up(kPi - rock, 0.0f); // unit axis from base to apex
  Vec3 coneBase = v3(0, kApexY + kUpperH - sink, 0);

  scene_add(s, kLowerCone, kLowerConeMat);
  scene_add(s, make_cone(coneBase, down, 1.25f, 0.0f, kUpperH, kCapBase), kUpperConeMat);
  scene_add(s, make_sphere(ball, kBallR), kBallMat);
  // Glass spheres: the upper one passes behind the cones at the knock.
  float orbit = 0.38f * t;
  scene_add(s, make_sphere(v3(3.4f * rt_cos(orbit), 1.0f, 3.4f * rt_sin(orbit)), 0.75f), kGlass1);
  float upper = 0.5f * kPi + 0.38f * kKnock - orbit;
  scene_add(s, make_sphere(v3(3.4f * rt_cos(upper), 4.1f, 3.4f * rt_sin(upper)), 0.65f), kGlass1);
  scene_add_background(s, kFloor, kFloorMat);

  float sway = 0.35f * rt_sin(kTwoPi * t / kSceneSeconds);
  s.camera = Camera{v3(8.6f * rt_sin(sway), 3.0f, -8.6f * rt_cos(sway)), v3(0, 2.55f, 0),
                    v3(0, 1, 0), 50.0f * kPi / 180.0f};
  apply_fade(s, t);
}

namespace {

// Scene 2: three overlapping gold spheres flow around each other between two
// rotating glass cylinders, on a two-triangle stage, under a bright sky; the
// camera circles and rises.
const SceneLook kLook2 = {
    kCookTorrance,
    {0.62f, 0.76f, 0.95f},
    {0.22f, 0.24f, 0.28f},
    {{{-5.0f, 8.0f, -6.0f}, {1.0f, 0.95f, 0.88f}}, {{6.0f, 5.0f, -2.0f}, {0.55f, 0.6f, 0.75f}}}};
// Cook-Torrance: colour, diffuse, specular, 1, reflect, transmit, ior,
// roughness, f0.
const Material kGold = {{1.0f, 0.66f, 0.18f}, 0.5f, 0.9f, 1, 0.42f, 0, 1, 0.22f, 0.85f};
const Material kGlass2[2] = {
    {{1.0f, 0.45f, 0.75f}, 0.08f, 0.8f, 1, 0.12f, 0.8f, 1.45f, 0.12f, 0.05f},
    {{0.35f, 0.95f, 0.85f}, 0.08f, 0.8f, 1, 0.12f, 0.8f, 1.45f, 0.12f, 0.05f}};
const Material kStageMat = {{0.95f, 0.55f, 0.3f}, 0.8f, 0.35f, 1, 0.25f, 0, 1, 0.35f, 0.1f};

} // namespace

void build_scene2(Scene& s, float t) {
  begin_scene(s, kLook2);

  // The "flowing mass": three spheres on interleaved Lissajous paths about a
  // common centre, close enough that they always overlap.
  for (int i = 0; i < 3; ++i) {
    float ph = t * 0.55f + (float)i * (kTwoPi / 3.0f);
    Vec3 c = v3(0.75f * rt_sin(ph) + 0.25f * rt_sin(1.7f * t + (float)i),
                1.2f + 0.3f * rt_sin(1.3f * ph + 0.8f * (float)i), 0.6f * rt_cos(ph * 1.15f));
    scene_add(s, make_sphere(c, 0.95f - 0.08f * (float)i), kGold);
  }
  // Two glass cylinders bounding the motion left and right, each tilted and
  // precessing about the vertical, in opposite senses.
  for (int side = 0; side < 2; ++side) {
    float sign = side ? 1.0f : -1.0f;
    Vec3 axis = tilted_up(0.38f, sign * 0.7f * t + (float)side * kPi);
    Vec3 centre = v3(3.05f * sign, 1.8f, 0.0f);
    scene_add(s, make_cylinder(centre - axis * 1.5f, axis, 0.55f, 3.0f, kCapBase | kCapTop),
              kGlass2[side]);
  }
  scene_add_background(s, kStage[0], kStageMat, &kStageBound);
  scene_add_background(s, kStage[1], kStageMat, &kStageBound);

  float orbit = -0.9f + 1.8f * smooth01(t / kSceneSeconds);
  float height = 2.0f + 1.5f * rt_sin(kPi * t / kSceneSeconds);
  s.camera = Camera{v3(8.6f * rt_sin(orbit), height, -8.6f * rt_cos(orbit)), v3(0, 1.35f, 0),
                    v3(0, 1, 0), 48.0f * kPi / 180.0f};
  apply_fade(s, t);
}

float timeline_wrap(double t) {
  if (!(t - t == 0.0)) return 0.0f; // NaN or Inf
  constexpr double kLoop = kTimelineSeconds;
  // Beyond 2^52 a double is an integer multiple of 64 s only when large
  // enough; such times carry no sub-loop information anyway.
  if (t >= 4503599627370496.0 || t <= -4503599627370496.0) return 0.0f;
  double q = t / kLoop;
  long long n = (long long)q;
  if ((double)n > q) --n; // floor for negatives
  double w = t - (double)n * kLoop;
  if (w < 0) w = 0;
  float wf = (float)w;
  return wf >= kTimelineSeconds ? 0.0f : wf;
}

TimelineState timeline_state(double t) {
  float w = timeline_wrap(t);
  TimelineState st;
  st.scene = w < kSceneSeconds ? 1 : 2;
  st.sceneTime = st.scene == 1 ? w : w - kSceneSeconds;
  st.showBlocks = st.scene == 2 && st.sceneTime >= kBlocksViewStart &&
                  st.sceneTime < kBlocksViewStart + kBlocksViewSeconds;
  return st;
}

TimelineState build_timeline_scene(Scene& s, double t) {
  TimelineState st = timeline_state(t);
  if (st.scene == 1)
    build_scene1(s, st.sceneTime);
  else
    build_scene2(s, st.sceneTime);
  return st;
}
