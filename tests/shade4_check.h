// shade4_check.h - the packet tracer's samples against the scalar tracer lane
// by lane (test_shade4.cpp: the primary shading point; test_shade4_second.cpp:
// the second level).
#pragma once
#include "packet/packet.h"

inline bool same_bits(float a, float b) { return rt_bits(a) == rt_bits(b); }
inline bool same_bits(Vec3 a, Vec3 b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

// trace_primary4() of the n pixels (x[k], y[k]) against trace_primary() of
// each: the lanes whose colour bits or PathRecord differ, whether the
// packet's ray counts differ from the lanes' sum, and each lane's first hit
// (id[k], -1 for none; front[k] from hit_normal() where it hits).
struct LaneCheck {
  long color = 0, path = 0;
  bool statsDiffer = false;
  int id[4];
  bool front[4];
};

inline LaneCheck check_lanes4(const Scene& s, const CameraRays& cam, const float* x, const float* y,
                              int n) {
  LaneCheck out;
  Vec3 color[4];
  PathRecord path[4];
  RayStats stats{0, 0, 0};
  trace_primary4(s, cam, x, y, n, color, path, &stats);
  RayStats ref{0, 0, 0};
  for (int k = 0; k < n; ++k) {
    PathRecord rec;
    rec.count = 0;
    TraceContext ctx{&s, {0, 0, 0}, &rec};
    Vec3 col = trace_primary(ctx, cam, x[k], y[k]);
    ref.primary += 1;
    ref.secondary += ctx.stats.secondary;
    ref.shadow += ctx.stats.shadow;
    out.color += !same_bits(col, color[k]);
    out.path += !same_path(rec, path[k]);
    Ray ray = primary_ray(cam, x[k], y[k]);
    Hit h;
    out.id[k] = first_hit(s, ray, h);
    out.front[k] = true;
    if (out.id[k] >= 0) {
      hit_normal(s.objects[out.id[k]].shape, ray, h);
      out.front[k] = h.front;
    }
  }
  out.statsDiffer = stats.primary != ref.primary || stats.secondary != ref.secondary ||
                    stats.shadow != ref.shadow;
  return out;
}

// The scene's lights moved: light l to place(l, its old light), with its colour
// (scene_add_light() recomputes the per-light terms).
template <class Place> void move_lights(Scene& s, Place place) {
  int n = s.numLights;
  Light old[kMaxLights];
  for (int l = 0; l < n; ++l)
    old[l] = s.lights[l];
  s.numLights = 0;
  for (int l = 0; l < n; ++l)
    scene_add_light(s, place(l, old[l]), old[l].color);
}

// Running counts of check_lanes4(): lanes compared, lanes whose colour bits or
// record differ, packets whose ray counts differ.
struct LaneCounts {
  long lanes = 0, color = 0, path = 0, stats = 0;
  LaneCheck check(const Scene& s, const CameraRays& cam, const float* x, const float* y, int n) {
    LaneCheck r = check_lanes4(s, cam, x, y, n);
    lanes += n;
    color += r.color;
    path += r.path;
    stats += r.statsDiffer;
    return r;
  }
};
