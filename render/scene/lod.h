/* Level of detail for polylines and surfaces: simplified primitive sets built
 * once per scene, from which a frame picks the coarsest level whose error,
 * projected to the screen, stays under a pixel bound (docs/ALGORITHM.md
 * "Level of detail").
 *
 * Lines:
 * Every vertex gets the error at which it may be dropped: a hierarchical
 * Douglas-Peucker split of each line, made monotone (a vertex's error is at
 * least that of every vertex split below it), so the vertices kept at a
 * threshold are nested across thresholds and each dropped vertex lies within
 * its threshold of the simplified polyline. Line end points are always kept.
 * Surfaces: the mesh is simplified by meshoptimizer, each level from the one
 * before; the error is the sum of meshoptimizer's targets along the way (its
 * estimate of the surface deviation).
 * Levels are thresholds of a ladder in steps of sqrt(2) (relative to the
 * bounds' diagonal) that cut the primitive count to at most LC_LOD_SHRINK of
 * the level before; level 0 is the scene's own primitives. Points have one
 * level (interactive frames thin them with a stride instead).
 * Threading: pure functions of a finalized scene; no shared state. */
#ifndef LC_LOD_H
#define LC_LOD_H

#include <stdint.h>

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_LOD_MAX_LEVELS 12
/* A level keeps at most this fraction of the previous one's segments, so all
 * coarse levels together cost at most what level 0's index buffers cost. */
#define LC_LOD_SHRINK 0.5
/* GPU bytes of a coarse level: per segment, the two strip indices of its end
 * vertex's ribbon sides; per line, its first vertex's two and the two restarts
 * before it (a line is one run at every level); per triangle, 3 indices. Level
 * 0 is the scene's own index buffers. */
#define LC_LOD_BYTES_PER_SEGMENT 8
#define LC_LOD_BYTES_PER_LINE 16
#define LC_LOD_BYTES_PER_TRIANGLE 12

typedef struct lc_lod_level {
    double error;        /* world units: how far the level may stray from the full geometry */
    uint64_t primitives; /* segments or triangles drawn at this level */
    uint32_t *indices;   /* 2 vertex indices per segment, 3 per triangle (lc_lod_build only) */
} lc_lod_level;

typedef struct lc_lod {
    int count; /* levels, 1 (full detail only) .. LC_LOD_MAX_LEVELS */
    lc_lod_level levels[LC_LOD_MAX_LEVELS];
} lc_lod;

/* The monotone drop error of every vertex of a line scene (err: vertex_count
 * floats; end points get INFINITY). LC_ERR_NOMEM. */
int lc_lod_vertex_errors(const lc_scene *s, float *err, lc_error *err_out);

/* The levels of s, counts and errors only (indices NULL): what lc_lod_build
 * makes. Points get one level. */
int lc_lod_plan(const lc_scene *s, lc_lod *out, lc_error *err);
/* The levels with their indices (lines: level 0 too; triangles: NULL at
 * level 0, which is s->triangles); free with lc_lod_free. */
int lc_lod_build(const lc_scene *s, lc_lod *out, lc_error *err);
/* GPU bytes of the levels beyond 0. */
uint64_t lc_lod_extra_bytes(const lc_scene *s, const lc_lod *lod);

/* The threshold ladder: step j of LC_LOD_LADDER_STEPS is diag * 2^(-(32 - j)/2)
 * (diag: the bounds' diagonal), finest first, in steps of sqrt(2). */
#define LC_LOD_LADDER_FINEST 32
#define LC_LOD_LADDER_STEPS 25
double lc_lod_threshold(const lc_scene *s, int step);
/* What decides a line scene's levels, in a form that sums over the parts of a
 * scene split across processes: [j] for each ladder step j the vertices whose
 * drop error exceeds its threshold, then the non-empty lines, then the
 * segments. LC_ERR_NOMEM. */
#define LC_LOD_COUNTS (LC_LOD_LADDER_STEPS + 2)
int lc_lod_line_counts(const lc_scene *s, uint64_t counts[LC_LOD_COUNTS], lc_error *err);
/* The ladder steps that become levels (bit j): a step becomes a level when it
 * keeps at most LC_LOD_SHRINK of the previous level's segments. With
 * LC_LOD_STEPS_GIVEN set, so that it is never 0. A shard takes the whole
 * scene's (scene.h lod_steps). */
#define LC_LOD_STEPS_GIVEN (1u << 31)
uint32_t lc_lod_line_steps(const uint64_t counts[LC_LOD_COUNTS]);
/* lod.c: adds the coarse levels of a line scene to out (level 0 set), at the
 * ladder steps s->lod_steps names or its own; with_indices fills each level's
 * pairs. */
int lc_lod_line_levels(const lc_scene *s, lc_lod *out, int with_indices, lc_error *err);
/* lod_surface.c: adds the coarse levels of a triangle scene to out (level 0
 * set); with_indices keeps their triangles. */
int lc_lod_surface_levels(const lc_scene *s, lc_lod *out, int with_indices, lc_error *err);
void lc_lod_free(lc_lod *lod);

#ifdef __cplusplus
}
#endif
#endif
