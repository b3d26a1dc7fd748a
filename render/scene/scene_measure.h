/* A scene's measures for estimating what drawing it costs: primitive and
 * vertex counts, total line length and surface area, the bounding sphere.
 * Taken once per dataset (the daemon's cost model, server/daemon/cost.h, reads
 * them for every request). */
#ifndef LC_SCENE_MEASURE_H
#define LC_SCENE_MEASURE_H

#include "scene.h"

#define LC_MEASURE_LEVELS 12 /* LC_LOD_MAX_LEVELS (lod.h) */

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_scene_measures {
    lc_prim_type type;
    double primitives; /* points, line segments or triangles */
    double vertices;
    double elements;
    double line_length; /* world units, all segments */
    double area;        /* world units^2, all triangles */
    double center[3];
    double radius; /* half the bounds diagonal (> 0) */
    double lines;  /* polylines (lines.clusters draws a share of them) */
    /* Levels of detail once uploaded (0 = not known: every frame is priced at
     * full detail): each level's simplification error in world units and the
     * share of the primitives it draws (level 0: 0 and 1). */
    int levels;
    double level_error[LC_MEASURE_LEVELS];
    double level_share[LC_MEASURE_LEVELS];
} lc_scene_measures;

/* Measures s; a part read by one process (s->part_of) measures as the whole. */
void lc_scene_measure(const lc_scene *s, lc_scene_measures *out);

#ifdef __cplusplus
}
#endif
#endif
