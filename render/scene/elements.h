/* Optimization elements, the unknowns of the opacity optimization
 * (docs/ALGORITHM.md "Elements"): one per point, equal-arc-length segments for
 * lines, geodesic patches for surfaces, with each vertex's blend of up to three
 * element opacities and the element adjacency that smoothing follows.
 * Works on a plain view of the geometry, so it knows nothing of scenes.
 * Threading: reentrant; the result is plain memory owned by the caller. */
#ifndef LC_ELEMENTS_H
#define LC_ELEMENTS_H

#include <stddef.h>
#include <stdint.h>

#include "lc_base.h"
#include "lc_params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Every vertex blends up to three element opacities; its primary element
 * receives the fragments' atomic-min. */
typedef struct lc_elements {
    uint32_t count;
    uint32_t *vertex_elements;   /* 4 per vertex: e0, e1, e2, primary (unused slots repeat e0, weight 0) */
    float *vertex_weights;       /* 4 per vertex: w0, w1, w2, 0; w0 + w1 + w2 = 1 */
    uint32_t *adjacency_offsets; /* count + 1, CSR over adjacency */
    uint32_t *adjacency;         /* neighbour element ids, symmetric */
    uint32_t adjacency_count;    /* adjacency_offsets[count] */
} lc_elements;

/* How surface patch centres are picked: farthest-point sampling over geodesic
 * distances (the most even), or the vertex nearest the middle of each occupied
 * cell of a grid (O(n log n); farthest-point sampling took minutes at tens of
 * millions of vertices). AUTO: farthest-point up to LC_GRID_SAMPLING_VERTICES. */
typedef enum { LC_PATCH_SAMPLING_AUTO = 0, LC_PATCH_SAMPLING_FARTHEST, LC_PATCH_SAMPLING_GRID } lc_patch_sampling;
#define LC_GRID_SAMPLING_VERTICES (1u << 22)

/* Options of the element build; zero means default. */
typedef struct lc_elements_desc {
    uint32_t line_budget; /* total line segment-elements (at least one per line); 0 = derived from the data */
    uint32_t patch_count; /* surface patches; 0 = derived from the data */
    lc_patch_sampling patch_sampling;
} lc_elements_desc;

/* The geometry elements are built on (borrowed arrays, validated indices). */
typedef struct lc_element_geometry {
    const char *name; /* for messages */
    lc_prim_type type;
    uint32_t vertex_count;
    const float *positions; /* 3 per vertex */
    uint32_t line_count;
    const uint32_t *line_offsets; /* line_count + 1 */
    uint32_t triangle_count;
    const uint32_t *triangles; /* 3 per triangle */
} lc_element_geometry;

/* The element count a zero desc gives g: points one per point; lines at least
 * 10,000, 4 per line and one per 32 segments; surfaces one patch per 8
 * vertices, at most max(4000, vertices / 64); lines and patches capped at 2^20. */
uint32_t lc_elements_default_count(const lc_element_geometry *g);

/* Builds *out (freed first) from g. On error *out is empty. */
int lc_elements_build(const lc_element_geometry *g, const lc_elements_desc *desc, lc_elements *out, lc_error *err);
void lc_elements_free(lc_elements *e);

/* ---- Building blocks of the builders in this folder (elements.c,
 * elements_lines.c, elements_build.c); not for other callers. */

/* Allocates the per-vertex arrays and count + 1 offsets (zeroed). Buffers are
 * never empty so that GPU uploads never see a zero size. */
int lc_elements_alloc(lc_elements *e, uint32_t vertices, uint32_t count, const char *name, lc_error *err);
/* Writes a vertex's blend: up to three (element, weight) pairs; unused slots
 * repeat e0 with weight 0 so the shader can always read all three. */
void lc_elements_set_vertex(lc_elements *e, uint32_t v, int n, const uint32_t *ids, const float *w, uint32_t primary);
/* Builds the CSR adjacency from directed pairs (a << 32 | b), both directions
 * present; sorts, removes duplicates and self loops. Frees pairs. */
int lc_elements_adjacency_from_pairs(lc_elements *e, uint64_t *pairs, size_t n, const char *name, lc_error *err);
/* The line elements of s with `budget` elements over all lines (elements_lines.c). */
int lc_elements_build_lines(const lc_element_geometry *s, lc_elements *e, uint32_t budget, lc_error *err);
/* The surface patches of s: `want` geodesic patches around centres picked by
 * `sampling` (elements.c). */
int lc_elements_build_patches(const lc_element_geometry *s, lc_elements *e, uint32_t want, lc_patch_sampling sampling,
                              lc_error *err);

/* ---- Parts: one process's share of a scene split over several
 * (render/scene/scene_part.h), numbered as the whole scene is. */

/* Arc length of each line of g (line_count floats), as the build uses it. */
int lc_elements_line_lengths(const lc_element_geometry *g, float *out);

/* Every line of the whole scene: its vertex count and arc length, and where
 * the part's lines start among them. */
typedef struct lc_line_census {
    uint32_t line_count;
    const uint32_t *vertex_counts;
    const float *lengths;
    uint64_t vertex_count; /* the whole scene's */
    uint32_t first_line;   /* the part's first line */
} lc_line_census;

/* The elements of part, whole lines [first_line, first_line +
 * part->line_count) of the whole: the budget split over all lines exactly as
 * lc_elements_build splits it for the whole scene, the part's vertex blends
 * in the whole's numbering, and the whole's adjacency. */
int lc_elements_build_lines_part(const lc_element_geometry *part, const lc_elements_desc *desc,
                                 const lc_line_census *whole, lc_elements *out, lc_error *err);
/* Points [first_point, first_point + part->vertex_count) of total_points:
 * element first_point + v for vertex v, no adjacency. */
int lc_elements_build_points_part(const lc_element_geometry *part, uint64_t first_point, uint64_t total_points,
                                  lc_elements *out, lc_error *err);

/* Distance weights of the adjacency (params.smoothingWeights "distance",
 * OOS §4.3): out[k] for CSR entry k from element e to neighbour j is
 * a_ej = d_ej^-2 / sum_i d_ei^-2, d the distance between the element centres
 * (the mean position of the vertices whose primary element it is: a patch's
 * centre, a line segment-element's middle). A row with a neighbour whose
 * centre is unknown (no vertex here, e.g. on another MPI shard) or at zero
 * distance is uniform, 1/degree. out holds e->adjacency_count floats,
 * rounded to multiples of 1/65535 (the GPU stores them as 16-bit unorm). */
void lc_elements_adjacency_weights(const lc_elements *e, const float *positions, uint32_t vertex_count, float *out);

#ifdef __cplusplus
}
#endif
#endif
