/* Streamline-set datasets: "streamlines:FIELD?seeding=...&seeds=...&count=N
 * &direction=...&separation=D&step=H&length=L" names the set of curves that
 * seeding.h traces through a field source (lc_field_is_source), turned into
 * a line scene that every path loads like a file: lucent render --dataset,
 * lucent serve --data (docs/ALGORITHM.md §22). */
#ifndef LC_IO_STREAMLINES_H
#define LC_IO_STREAMLINES_H

#include <stdint.h>

#include "lc_base.h"
#include "scene.h"
#include "seeding.h"
#include "trace.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_STREAMLINES_PREFIX "streamlines:"
/* The trace budget of one set: vertices all its curves may hold (32 bytes
 * each while traced), so a set costs at most about 0.5 GiB to trace. */
#define LC_STREAMLINES_MAX_VERTICES (1u << 24)

/* 1 when spec starts with "streamlines:". */
int lc_streamlines_is_spec(const char *spec);

/* Traces the set spec names on `threads` CPU threads and returns it as a
 * finalized line scene named "streamlines:FIELD". Keys: seeding (points,
 * rake, box, density; default density), seeds (x,y,z;x,y,z...: the points, a
 * rake's two ends or a box's two corners; default the field's box), count
 * (curves, default 64), direction (forward, backward, both), separation
 * (density's d_sep), step, length (the tracer's). A set whose estimated
 * vertices exceed LC_STREAMLINES_MAX_VERTICES is refused naming
 * "streamlines.count"; the tracer's step cap keeps any set within it.
 * Errors name "streamlines.KEY" or the field. */
int lc_streamlines_load(const char *spec, int threads, lc_scene **out, lc_error *err);

/* Traces the set spec names through the open field f (the spec's own field
 * name is not looked up: the daemon passes the field it loaded), as
 * lc_streamlines_load does. */
int lc_streamlines_load_field(const char *spec, const lc_field *f, int threads, lc_scene **out, lc_error *err);
/* Checks spec against f without tracing: its keys, the seeding (a box of
 * positive extent, finite points) and the trace budget; *vertices and *steps
 * (each may be NULL) get lc_streamlines_estimate's figures. Errors name
 * "streamlines.KEY" as lc_streamlines_load's do. */
int lc_streamlines_check(const char *spec, const lc_field *f, double *vertices, double *steps, lc_error *err);

/* Traces the set desc describes through f into a finalized line scene named
 * name (lc_streamlines_scene): the one code path of sets named at load time
 * (lc_streamlines_load) and sets a render request asks for (the daemon's
 * streamlines section). A set whose estimated vertices exceed
 * LC_STREAMLINES_MAX_VERTICES is refused naming "streamlines.count"; each
 * curve's steps are capped so that no set exceeds it. */
int lc_streamlines_trace(const lc_field *f, const lc_seeding_desc *desc, int threads, const char *name, lc_scene **out,
                         lc_error *err);
/* The estimated vertices of the set desc describes through f (curves times
 * the steps of each, both halves of two-way curves), and in *steps (may be
 * NULL) the RK4 steps of one curve: what pricing a set needs. */
double lc_streamlines_estimate(const lc_field *f, const lc_seeding_desc *desc, double *steps);

/* Moves count curves into a finalized line scene named name with their time,
 * speed, seed parameter and ghost normal as attributes (time, speed, seed_u,
 * normal_x/y/z; default importance speed) and, given the field f they were
 * traced in, the vorticity |curl v| at each vertex (lc_field_curl); curves of
 * one vertex are left out. The curves keep their arrays (free them with
 * lc_trace_curves_free). */
int lc_streamlines_scene(const char *name, const lc_trace_curve *curves, uint32_t count, const lc_field *f,
                         lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
