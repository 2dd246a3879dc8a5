// scenes.h - the intro's two scenes and the timeline that loops them.
// Every function here is a pure function of time in seconds: no state, no
// frame counter, so motion is the same at any frame rate.
#pragma once
#include "../src/core/scene.h"

constexpr float kSceneSeconds = 32.0f;
constexpr float kTimelineSeconds = 2 * kSceneSeconds;

// Scene 1 (Phong, dark) and scene 2 (Cook-Torrance, bright) at scene time
// t in [0, kSceneSeconds).
void build_scene1(Scene& s, float t);
void build_scene2(Scene& s, float t);

// The objects that never move, stored as the Shapes their builders give
// (scenes.cpp names each builder call; tests/test_scenes.cpp checks them
// bit for bit): intro.exe then needs no plane or triangle builder.
extern const Shape kLowerCone;  // scene 1's lower cone
extern const Shape kFloor;      // scene 1's floor
extern const Shape kStage[2];   // scene 2's two triangles
extern const Bound kStageBound; // their shared bound (scenes.cpp)

// Maps any finite time onto [0, kTimelineSeconds): the timeline loops forever
// (negative times count back from the loop's end). Non-finite input gives 0.
float timeline_wrap(double t);

struct TimelineState {
  int scene;       // 1 or 2
  float sceneTime; // [0, kSceneSeconds)
  bool showBlocks; // the renderer-visualisation segment of scene 2
};
TimelineState timeline_state(double t);

// Scene 2's segment that shows the adaptive renderer's own work (thesis 5.6):
// blocks filled by colour copy in red, interpolated blocks in blue. The
// adaptive renderer reads TimelineState::showBlocks to draw it.
constexpr float kBlocksViewStart = 18.0f;
constexpr float kBlocksViewSeconds = 4.0f;

// The scene at timeline time t; returns its state.
TimelineState build_timeline_scene(Scene& s, double t);
