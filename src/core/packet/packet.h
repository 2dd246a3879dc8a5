// packet.h - primary rays, one at a time or four at once (SSE2 packets).
//
// Every function here takes a CameraRays made by camera_rays(scene, ...)
// (its terms are those of `scene`) and traces primary rays from cam.org.
// Each gives exactly what the general tracer gives for the same ray: the
// same first hit (object, t, piece, local: bit for bit) and so the same
// colour, the same PathRecord and the same ray counts as trace() and
// first_hit() (tests/test_packet.cpp checks it over the timeline and on
// random and grazing rays). Only the cost differs: the bound and shape
// tests start from the per-frame terms (packet/primary.h), and a packet
// tests the bounds, spheres, planes, triangles, cylinders and cones for four
// rays in one SSE2 pass; the rare cases the kernels leave out (frustum.h,
// packet.cpp) are tested per lane by the scalar intersect_t(). The primary
// hits are shaded in lanes too (packet/shade.h: the same float operations
// per lane as trace_hit's); the secondary rays of each lane, and the shadow
// rays' object tests, are the scalar tracer's.
#pragma once
#include "abi.h"
#include "trace.h"

// First hit of the ray from cam.org along unit `dir`: as first_hit().
int first_hit_primary(const Scene& scene, const CameraRays& cam, Vec3 dir, Hit& hit);

// First hits of up to four rays from cam.org along unit dir[k], k < count
// (1..4), as first_hit() for each: id[k] and hit[k] (t, piece, local).
// Lanes k >= count are left alone.
void first_hit_primary4(const Scene& scene, const CameraRays& cam, const Vec3 dir[4], int count,
                        int id[4], Hit hit[4]);

// Colour of the primary ray through pixel (x, y): trace(ctx, primary_ray(cam,
// x, y), 1) (and its record into *ctx.record, when set), without counting
// the primary ray in ctx.stats.
Vec3 trace_primary(TraceContext& ctx, const CameraRays& cam, float x, float y);

// Up to four primary samples at once: for lanes k < count (1..4), the
// pixel (x[k], y[k]) gets color[k] = trace_primary() of it. When `paths` is
// not null (four records), paths[k] is reset and receives the sample's
// PathRecord, and the records of lanes k >= count may be overwritten. The
// shadow and secondary rays cast are added to *stats, and `count` primary
// rays. The colours of lanes k >= count are left alone. x and y hold four
// readable floats each: all four are loaded, those of lanes k >= count not
// used.
RT64K_HOT_ABI void trace_primary4(const Scene& scene, const CameraRays& cam, const float x[4],
                                  const float y[4], int count, Vec3 color[4], PathRecord* paths,
                                  RayStats* stats);

// trace_primary4() packed for a framebuffer (pack_color()).
inline void trace_primary4_packed(const Scene& scene, const CameraRays& cam, const float x[4],
                                  const float y[4], int count, u32 packed[4], PathRecord* paths,
                                  RayStats* stats) {
  Vec3 color[4];
  trace_primary4(scene, cam, x, y, count, color, paths, stats);
  for (int k = 0; k < count; ++k)
    packed[k] = pack_color(color[k]);
}

// Full trace of rows [rowBegin, rowEnd) of a `width`-pixel-wide image into
// fb (`stride` pixels per row), in packets of four pixels of a row:
// render_full_rows() (trace.h) with cam = camera_rays(scene, width, height).
// (2x2 packets measured 0.4-0.6 % fewer instructions per frame, and only
// for work items of two rows or more; the tool's are one row.)
void render_rows4(const Scene& scene, const CameraRays& cam, u32* fb, int width, int stride,
                  int rowBegin, int rowEnd, RayStats* stats);
