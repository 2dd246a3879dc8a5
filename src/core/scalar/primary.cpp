// scalar/primary.cpp - the primary-ray API of packet/packet.h and
// packet/primary.h, one ray at a time through the general tracer. Built
// instead of src/core/packet/*.cpp when the RT64K_PACKETS switch is OFF
// (CMakeLists.txt, src/win32/CMakeLists.txt): intro.exe ships this way
// (docs/win32.md "Ray packets in intro.exe": the packets save about 3 % of
// the adaptive renderer's instructions and cost 4,336 bytes unpacked, 2,288
// packed).
//
// The contract is packet.h's: each function gives what trace() and
// first_hit() give for the same ray, which is what it calls, so the pixels,
// path records and ray counts are those of the packet tracer
// (tests/test_packet.cpp checks the packet tracer against exactly these
// calls; the Wine screenshot tests compare intro.exe with `rt64k render`).
// The per-frame terms are not needed: primary_terms() only records the
// origin.
#include "packet/packet.h"

void primary_terms(const Scene&, Vec3 org, PrimaryTerms& out) { out.org = org; }

int first_hit_primary(const Scene& scene, const CameraRays& cam, Vec3 dir, Hit& hit) {
  return first_hit(scene, Ray{cam.org, dir}, hit);
}

void first_hit_primary4(const Scene& scene, const CameraRays& cam, const Vec3 dir[4], int count,
                        int id[4], Hit hit[4]) {
  for (int k = 0; k < count; ++k)
    id[k] = first_hit_primary(scene, cam, dir[k], hit[k]);
}

Vec3 trace_primary(TraceContext& ctx, const CameraRays& cam, float x, float y) {
  return trace(ctx, primary_ray(cam, x, y), 1);
}

void trace_primary4(const Scene& scene, const CameraRays& cam, const float x[4], const float y[4],
                    int count, Vec3 color[4], PathRecord* paths, RayStats* stats) {
  TraceContext ctx{&scene, {(u64)count, 0, 0}, nullptr};
  for (int k = 0; k < count; ++k) {
    if (paths) {
      paths[k].count = 0;
      ctx.record = &paths[k];
    }
    color[k] = trace(ctx, primary_ray(cam, x[k], y[k]), 1); // trace_primary(), inline
  }
  stats->primary += ctx.stats.primary;
  stats->secondary += ctx.stats.secondary;
  stats->shadow += ctx.stats.shadow;
}

void render_rows4(const Scene& scene, const CameraRays& cam, u32* fb, int width, int stride,
                  int rowBegin, int rowEnd, RayStats* stats) {
  TraceContext ctx{&scene, {0, 0, 0}, nullptr};
  for (int y = rowBegin; y < rowEnd; ++y)
    for (int x = 0; x < width; ++x) {
      ++ctx.stats.primary;
      fb[y * stride + x] = pack_color(trace_primary(ctx, cam, (float)x, (float)y));
    }
  stats->primary += ctx.stats.primary;
  stats->secondary += ctx.stats.secondary;
  stats->shadow += ctx.stats.shadow;
}
