/* The render request as a value: lc_request and its surface and streamlines
 * sections, the types request.c parses into and the field table
 * (request_table.c) describes. Plain data; the operations are request.h's. */
#ifndef LC_PROTOCOL_REQUEST_TYPES_H
#define LC_PROTOCOL_REQUEST_TYPES_H

#include <stdbool.h>

#include "lc_params.h"
#include "request_layers.h" /* lc_request_layers */

#ifdef __cplusplus
extern "C" {
#endif

#define LC_PROTO_VERSION 1
#define LC_PROTO_DATASET_LEN 512
#define LC_PROTO_DEFAULT_QUALITY 90

#define LC_SURFACE_SEED_MAX 64 /* points of surface.seed */

typedef enum { LC_SURFACE_LAYERS = 0, LC_SURFACE_WEIGHTED_AVERAGE, LC_SURFACE_WEIGHTED_SUM } lc_surface_composite;

/* The surface object of method "surface-layers" (docs/ALGORITHM.md §23): a
 * vector field's integral surface, traced from a seed polyline and drawn as
 * surface layers. Zero step/length mean the tracer's defaults. */
typedef struct lc_surface_request {
    char field[128]; /* a loaded field's name ("demo:abc-flow"); required by the method */
    int seed_count;  /* 2 .. LC_SURFACE_SEED_MAX points (0 = not given) */
    double seed[LC_SURFACE_SEED_MAX][3];
    int particles;                  /* curves traced along the seed (default 2000) */
    double step;                    /* RK4 time step, 0 = 1/200 of the diagonal over the largest |v| */
    double length;                  /* arc length of a curve, 0 = 2 field diagonals */
    double epsilon;                 /* merge distance as a fraction of the field's diagonal (default 1e-2) */
    double opacity;                 /* every layer's alpha (default 0.3) */
    int max_layers;                 /* K, layers a pixel keeps (default 8) */
    lc_surface_composite composite; /* layers (default), or a count-based OIT baseline */
    double color[3];                /* the surface's base colour */
    int curves_per_frame;           /* WebSocket sessions: curves traced and added per frame (default 200) */
    int direction;                  /* lc_trace_direction: forward (default), backward, or both from the seed */
} lc_surface_request;

#define LC_STREAMLINES_SEEDS_MAX 64 /* points of streamlines.seeds */

/* A streamline set asked for by a request whose dataset names a vector field
 * (docs/ALGORITHM.md §22): traced by the daemon with the load-time tracer and
 * drawn as the request's line dataset. Zero step/length/separation mean the
 * tracer's defaults. */
typedef struct lc_streamlines_request {
    int seeding;    /* lc_seeding_kind: points, rake, box, density (default) */
    int seed_count; /* points: 1 .. LC_STREAMLINES_SEEDS_MAX; rake: its 2 ends; box, density: 2 corners or 0 */
    double seeds[LC_STREAMLINES_SEEDS_MAX][3];
    int count;         /* curves of a rake, box or density set (default 64) */
    bool has_count;    /* count was given (seeding points takes none) */
    double step;       /* RK4 time step, 0 = 1/200 of the diagonal over the largest |v| */
    double length;     /* arc length of a curve (each half of a two-way one), 0 = 2 field diagonals */
    double separation; /* density's d_sep, 0 = from the box and the count */
    int direction;     /* lc_trace_direction: forward (default), backward, both */
} lc_streamlines_request;

/* One render: which data, how big, which camera and parameters, which image.
 * A request owns a reference to its layers' snapshot: copy one with
 * lc_request_copy (not `=`), drop it with lc_request_release. */
typedef struct lc_request {
    char dataset[LC_PROTO_DATASET_LEN]; /* "demo:NAME", a path (CLI only) or a loaded
                                           dataset's name; "" = the server's default */
    lc_render_params render;            /* width, height, method, camera, foo, importance, color, style */
    lc_image_format format;             /* png | jpeg ("jpg" accepted on input) */
    int quality;                        /* JPEG quality 1..100, default 90 */
    double dt;                          /* sessions: seconds since the previous frame */
    bool has_dt;
    /* layers[]: NULL = the one dataset above; else these datasets in one
     * view, each with its own mapping and style (the request's own importance
     * and colour then apply to none of them). Shared and immutable: a change
     * of layers makes a new snapshot (request_layers.h). */
    const lc_request_layers *layers;
    lc_surface_request surface;         /* method "surface-layers" only */
    lc_streamlines_request streamlines; /* a dataset that names a vector field only */
} lc_request;

#ifdef __cplusplus
}
#endif

#endif
