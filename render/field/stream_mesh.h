/* The meshed reference of an integral surface: a triangle mesh integrated
 * with front refinement after Hultquist (docs/ALGORITHM.md §23 "The meshed
 * reference"): particles along the seed advance front by front (the RK4 steps
 * of trace.c), a particle is inserted between two neighbours wherever they
 * drift apart beyond a distance, and consecutive fronts are joined by
 * triangles. The baseline that surface layers are compared against.
 * Threading: runs on the caller's thread; reads the field and seed only. */
#ifndef LC_FIELD_STREAM_MESH_H
#define LC_FIELD_STREAM_MESH_H

#include <stdint.h>

#include "trace.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_stream_mesh_desc {
    lc_trace_desc trace; /* step, length, ... as the curves of surface layers (zero = defaults) */
    int initial;         /* particles on the seed at the start, 0 = 33 */
    /* Insert a particle between neighbours farther apart than this (world
     * units) on any front; 0 = 1/200 of the field's diagonal. */
    double split;
    uint32_t max_particles; /* 0 = 20000; reaching it is an error naming "split" */
} lc_stream_mesh_desc;

typedef struct lc_stream_mesh {
    uint32_t vertex_count, triangle_count, particles;
    float *xyz;          /* 3 per vertex */
    float *normal;       /* 3 per vertex, the particles' ghost normals (unit, side arbitrary) */
    uint32_t *triangles; /* 3 per triangle */
} lc_stream_mesh;

/* Builds the mesh of field's stream (path) surface from seed (checked). */
int lc_stream_mesh_build(const lc_field *field, const lc_seed *seed, const lc_stream_mesh_desc *desc,
                         lc_stream_mesh *out, lc_error *err);
void lc_stream_mesh_free(lc_stream_mesh *m);

#ifdef __cplusplus
}
#endif
#endif
