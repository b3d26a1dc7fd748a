/* Level of detail for polylines: a simplification hierarchy built once per
 * scene, from which a frame picks the coarsest level whose error, projected
 * to the screen, stays under a pixel bound (docs/ALGORITHM.md "Level of detail").
 *
 * Every vertex gets the error at which it may be dropped: a hierarchical
 * Douglas-Peucker split of each line, made monotone (a vertex's error is at
 * least that of every vertex split below it), so the vertices kept at a
 * threshold are nested across thresholds and each dropped vertex lies within
 * its threshold of the simplified polyline. Line end points are always kept.
 * Levels are thresholds of a ladder in steps of sqrt(2) (relative to the
 * bounds' diagonal) that cut the segment count to at most LC_LOD_SHRINK of the level
 * before; level 0 is the full line set.
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
/* GPU bytes of a coarse level per segment: its vertex pairs (2 x 4) and its
 * ribbon quads (6 x 4 indices). Level 0 is the scene's own index buffers. */
#define LC_LOD_BYTES_PER_SEGMENT 32

typedef struct lc_lod_level {
    double error;      /* world units: every vertex dropped lies within this of the level's polyline */
    uint64_t segments; /* segments drawn at this level */
    uint32_t *pairs;   /* 2 vertex indices per segment (lc_lod_build only; NULL in a plan) */
} lc_lod_level;

typedef struct lc_lod {
    int count; /* levels, 1 (full detail only) .. LC_LOD_MAX_LEVELS */
    lc_lod_level levels[LC_LOD_MAX_LEVELS];
} lc_lod;

/* The monotone drop error of every vertex of a line scene (err: vertex_count
 * floats; end points get INFINITY). LC_ERR_NOMEM. */
int lc_lod_vertex_errors(const lc_scene *s, float *err, lc_error *err_out);

/* Plans the levels of s (counts and errors only, pairs NULL): what
 * lc_lod_build would make. Scenes other than lines get one level. */
int lc_lod_plan(const lc_scene *s, lc_lod *out, lc_error *err);
/* Plans and fills each level's segment pairs (level 0 too); free with
 * lc_lod_free. */
int lc_lod_build(const lc_scene *s, lc_lod *out, lc_error *err);
void lc_lod_free(lc_lod *lod);

#ifdef __cplusplus
}
#endif
#endif
