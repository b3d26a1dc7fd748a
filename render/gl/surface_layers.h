/* Progressive transparent integral surfaces (PRT, docs/ALGORITHM.md §23):
 * traced curves drawn as lines into per-batch fragment lists, merged per
 * pixel into a persistent, depth-sorted list of at most K surface layers
 * (fragments within epsilon of a layer's view depth are averaged into it),
 * composited front to back with a fixed layer opacity.
 * Threading: one thread at a time, with a GL 4.5 context current that is
 * the creating one or shares its objects: the object holds buffers only (the
 * programs are the current context's, kept per thread; the vertex array and
 * framebuffer are made per batch), and lc_surface_layers_read finishes the
 * context's work, so that another context of the share group may continue. */
#ifndef LC_GL_SURFACE_LAYERS_H
#define LC_GL_SURFACE_LAYERS_H

#include <stdint.h>

#include "lc_base.h"
#include "trace.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_SURFACE_LAYERS_MAX_K 64 /* largest K (layers per pixel) */

typedef struct lc_surface_layers lc_surface_layers;

typedef struct lc_surface_layers_desc {
    int width, height; /* image size in pixels (1 .. 8192) */
    int max_layers;    /* K, 0 = 16; at most LC_SURFACE_LAYERS_MAX_K */
    /* A fragment joins a layer when |its view depth - the layer's mean depth|
     * < epsilon (view-space units; 0 = never merge). Negative or non-finite is an error. */
    double epsilon;
    double opacity;       /* alpha of every layer in [0, 1]; 0 = 0.5 */
    double background[3]; /* composited behind the layers */
    /* world -> view and view -> clip, column-major (as OpenGL). View depth is
     * -z in view space (the camera looks down -z). */
    float view[16];
    float projection[16];
    uint64_t pool_fragments; /* fragment pool of one batch, 0 = 4 Mi fragments */
    /* How composite blends: LC_SURFACE_COMPOSITE_LAYERS (PRT Alg. 2), or the
     * count-based OIT baselines over the same fragments (PRT Fig. 5). */
    int composite;
} lc_surface_layers_desc;

enum { LC_SURFACE_COMPOSITE_LAYERS = 0, LC_SURFACE_COMPOSITE_WEIGHTED_AVERAGE, LC_SURFACE_COMPOSITE_WEIGHTED_SUM };

typedef struct lc_surface_layers_stats {
    uint64_t fragments;      /* fragments rasterized, all batches */
    uint64_t merged;         /* ... averaged into an existing layer */
    uint64_t overflow;       /* ... dropped: a new layer in a pixel that already had K */
    uint64_t pool_dropped;   /* ... dropped: a batch's fragment pool was full */
    uint64_t curves;         /* curves added, all batches */
    uint32_t covered_pixels; /* pixels with at least one layer */
    uint32_t max_layers;     /* most layers of a pixel */
    double mean_layers;      /* layers per covered pixel */
} lc_surface_layers_stats;

/* Builds programs and buffers on the current context. Errors name the field
 * of desc ("epsilon", "max_layers", ...). */
int lc_surface_layers_create(const lc_surface_layers_desc *desc, lc_surface_layers **out, lc_error *err);
/* The largest storage block the current context's driver addresses (bytes;
 * 0 = not known): a frame's layers must fit one. */
long long lc_surface_layers_block_bytes(void);
void lc_surface_layers_destroy(lc_surface_layers *sl);

/* Empties the layers and statistics (a new seed or camera). */
void lc_surface_layers_reset(lc_surface_layers *sl);

/* Draws count curves as line strips (base colour rgb in [0, 1], normals from
 * the curves' ghost particles) and merges their fragments into the layers. */
int lc_surface_layers_add(lc_surface_layers *sl, const lc_trace_curve *curves, uint32_t count, const float rgb[3],
                          lc_error *err);

/* Composites the layers front to back into rgba (width * height * 4 bytes,
 * top row first). */
int lc_surface_layers_composite(lc_surface_layers *sl, uint8_t *rgba, lc_error *err);

/* Layer count of every pixel (width * height, top row first); may be NULL.
 * Also fills *stats when not NULL. */
int lc_surface_layers_read(lc_surface_layers *sl, uint32_t *layer_counts, lc_surface_layers_stats *stats,
                           lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
