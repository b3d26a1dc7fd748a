/* Scene: CPU arrays of one dataset (points, polylines or triangles) with named
 * per-vertex float attributes, optional RGB, bounds, derived attributes and the
 * optimization elements.
 * Threading: one thread builds and finalizes a scene; after lc_scene_finalize
 * it is read-only and any number of threads may read it until destroy.
 * Ownership: every array in lc_scene is malloc'd and freed by lc_scene_destroy;
 * a loader may assign line_offsets/triangles directly before finalize. */
#ifndef LC_SCENE_H
#define LC_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "elements.h"
#include "lc_base.h"
#include "lc_params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Hard caps on what any loader or generator may produce (curl's "toobig"). */
#define LC_MAX_VERTICES (1u << 28)   /* 268M vertices */
#define LC_MAX_PRIMITIVES (1u << 29) /* lines or triangles */
#define LC_MAX_ATTRIBUTES 32

/* Whether an attribute's name says that smaller values matter more: a word of
 * it (split at anything but letters and digits, any case) is mag, magnitude,
 * vmag, bmag, gmag, absmag, appmag, rank, pvalue or pval, or it has the words
 * p and value (p_value). */
bool lc_attribute_smaller_matters(const char *name);

/* Values that name kinds rather than amounts (a class label, an atom type, a
 * segment number): every finite value an integer, at least two of them, the
 * largest less than LC_CATEGORY_SPAN above the smallest, and the file's
 * vertices at least LC_CATEGORY_REPEATS times the span + 1 (kinds repeat).
 * Such an attribute is never the default importance (docs/GUIDE.md "Default
 * attributes"). */
#define LC_CATEGORY_SPAN 64
#define LC_CATEGORY_REPEATS 4
struct lc_attribute;
bool lc_attribute_categorical(const struct lc_attribute *a, uint32_t n);

typedef struct lc_attribute {
    char name[LC_NAME_LEN];
    float *values;  /* vertex_count values, owned by the scene */
    float min, max; /* over finite values; filled by lc_scene_finalize */
    /* 2nd and 98th percentiles over finite values (lc_scene_finalize). */
    float p02, p98;
    /* The importance range of normalize "auto" when a request gives none
     * (lc_attribute_update_range): [min, max] with only the outliers cut off,
     * so one extreme value cannot squash every other one to zero. */
    float auto_lo, auto_hi;
    /* Smaller values matter more (a magnitude, a rank, a p-value: named so;
     * lc_attribute_smaller_matters): the importance maps it inverted unless
     * the request's importance.invert flips it back. Set by lc_scene_finalize. */
    bool smaller_matters;
    /* Names kinds, not amounts (lc_attribute_categorical, agreed by every
     * process of a collective load). Set by lc_scene_finalize. */
    bool categorical;
} lc_attribute;

/* Lines that are air-parcel trajectories (a reader sets it; at finalize
 * lc_scene_derive_trajectories adds their derived attributes): x, y are
 * longitude and latitude in degrees, z the log-pressure height
 * 10 ln(1013.25 hPa / p); step_hours between time steps, 0 = unknown. */
typedef struct lc_trajectory_info {
    int geographic;
    double step_hours;
    /* Timed lines (scene_motion.h): 1 = no A_delta / A_rate, for attributes
     * that are no data along a line (a tracer's seed parameter and normals). */
    int no_rates;
} lc_trajectory_info;

typedef struct lc_scene {
    char name[LC_NAME_LEN];
    lc_prim_type type;
    uint32_t vertex_count;
    float *positions; /* 3 per vertex */
    float *rgb;       /* 3 per vertex in [0,1], or NULL */
    float *normals;   /* triangles: 3 per vertex (area-weighted); NULL otherwise */
    float *tangents;  /* lines: 3 per vertex (unit, central difference); NULL otherwise */

    uint32_t line_count;
    uint32_t *line_offsets; /* line_count + 1: vertices of line i are [off[i], off[i+1]) */
    uint32_t triangle_count;
    uint32_t *triangles; /* 3 per triangle */

    int attribute_count;
    lc_attribute attributes[LC_MAX_ATTRIBUTES];

    double bounds[6];                     /* xmin, ymin, zmin, xmax, ymax, zmax */
    char default_importance[LC_NAME_LEN]; /* attribute used when a request names none */
    char default_color[LC_NAME_LEN];      /* "importance", "rgb" or an attribute */
    /* Suggested initial view when a request has no camera (e.g. the tornado is
     * seen from the side with +Z up); has_view = 0: ParaView's -Z, +Y up. */
    int has_view;
    double view_direction[3]; /* from the camera toward the data */
    double view_up[3];

    lc_elements elements;
    /* A part read by one of several processes (scene_part.h): the whole
     * scene's totals, and the collectives that rebuild its elements
     * (lc_scene_set_element_budget; borrowed, valid while the processes run). */
    int part_of; /* processes; 0: not a part */
    /* A shard or part: the whole scene's index of its first vertex (the
     * compact GPU layout aligns its position chunks to the whole's); 0
     * otherwise, and for surface shards, whose vertices are not contiguous. */
    uint64_t vertex_base;
    /* A line shard or part: the threshold ladder steps (bit j, lod.h) the whole
     * scene's levels of detail use, so that every rank picks the same
     * simplification; with LC_LOD_STEPS_GIVEN set. 0: the scene decides. */
    uint32_t lod_steps;
    const struct lc_scene_collective *collective;
    uint64_t whole_vertices, whole_primitives, whole_lines;
    double whole_line_length;
    int finalized;
    /* lc_scene_release_vertex_arrays ran: counts, bounds, attribute names and
     * ranges, line offsets and element counts remain; the arrays are NULL. */
    int released;
    int released_rgb; /* it had per-vertex RGB */
    lc_trajectory_info trajectory;
    /* Levels of detail built before, with their indices (a scene cache's,
     * scene_cache.h): lc_lod_build copies them instead of building. Owned,
     * freed with the vertex arrays by lod_free (set by whoever set lod, so
     * that the scene core need not call into lod.c, which includes it).
     * NULL: built on demand. */
    struct lc_lod *lod;
    void (*lod_free)(struct lc_lod *lod);
} lc_scene;

/* CPU bytes of a scene's arrays by kind. */
typedef struct lc_scene_memory {
    size_t positions;
    size_t colors;     /* rgb */
    size_t frames;     /* tangents or normals */
    size_t topology;   /* line offsets, triangles */
    size_t attributes; /* named attributes */
    size_t elements;   /* vertex blends and adjacency */
    size_t total;
} lc_scene_memory;

/* Creates an empty scene named `name` (copied, truncated). Returns NULL on OOM. */
lc_scene *lc_scene_create(const char *name, lc_prim_type type);
void lc_scene_destroy(lc_scene *s);

/* Allocates positions (and rgb if with_rgb) for n vertices (uninitialized).
 * Any earlier per-vertex data (attributes, normals, elements) is freed. */
int lc_scene_alloc_vertices(lc_scene *s, uint32_t n, int with_rgb, lc_error *err);
/* Adds an attribute; the scene takes ownership of values (malloc'd, vertex_count
 * floats) in every case: on failure they are freed, so callers never free them.
 * Replaces an attribute of the same name. Returns its index or < 0. */
int lc_scene_add_attribute(lc_scene *s, const char *name, float *values, lc_error *err);
/* Value of rank p * (finite count - 1) among the finite values of v (n of
 * them, all finite ones within [lo, hi]); lo when there are none. */
float lc_scene_percentile(const float *v, uint32_t n, float lo, float hi, double p);
/* Fills a's min, max, percentiles and auto range from its n values (NaN and
 * infinities ignored). The auto range cuts off only values that are both rare
 * (beyond the 2nd/98th percentile) and far out (beyond Tukey's far-out fence,
 * a quartile -/+ 3 interquartile ranges): each end is the farther of its
 * percentile and the last value inside the fence. Data without such outliers
 * keeps [min, max]; one extreme value is cut off. */
void lc_attribute_update_range(lc_attribute *a, uint32_t n);
/* Index of the attribute named name, or -1. */
int lc_scene_find_attribute(const lc_scene *s, const char *name);
/* The time of time windows and markers: the attribute named name, else
 * (name empty) the first of time, t, frame and timestep; -1 = none. */
int lc_scene_time_attribute(const lc_scene *s, const char *name);
/* A name for a new attribute that no attribute of s has: want itself when
 * free, else want_2, want_3, ... (shortened to fit LC_NAME_LEN). Readers use it
 * for names from a file, which may repeat: lc_scene_add_attribute replaces an
 * attribute of the same name and frees its values. */
void lc_scene_unique_attribute_name(const lc_scene *s, const char *want, char out[LC_NAME_LEN]);

/* Validates indices, computes bounds, normals/tangents, attribute ranges, the
 * derived attributes (lines: arc_length, curvature, line_length; triangles:
 * mean_curvature) and the elements. Call once after loading or generating. */
int lc_scene_finalize(lc_scene *s, const lc_elements_desc *desc, lc_error *err);
/* Rebuilds only the elements of a finalized scene with `budget` line elements
 * or surface patches (points keep one element per point); 0 = the default
 * derived from the data. LC_ERR_INVALID if budget exceeds the scene's
 * segments or vertices or 2^24. On a part (part_of > 0) it is collective:
 * every process calls it with the same budget. */
int lc_scene_set_element_budget(lc_scene *s, uint32_t budget, lc_error *err);

/* Bytes of CPU memory the scene's arrays hold (positions, colours, normals,
 * tangents, topology, attributes, elements). */
size_t lc_scene_bytes(const lc_scene *s);
void lc_scene_memory_of(const lc_scene *s, lc_scene_memory *out);

/* Frees the per-vertex arrays once a GPU copy holds them (positions, rgb,
 * normals, tangents, triangles, attribute values, element blends and
 * adjacency), keeping what describing and rendering the scene reads: counts,
 * bounds, attribute names, ranges and percentiles, defaults, line offsets,
 * element and adjacency counts. Afterwards lc_scene_set_element_budget and a
 * new GPU upload fail with LC_ERR_INVALID: a dataset that must be uploaded
 * again is loaded again. */
void lc_scene_release_vertex_arrays(lc_scene *s);
/* The scene has per-vertex RGB (also after the release). */
int lc_scene_has_rgb(const lc_scene *s);

const char *lc_prim_type_name(lc_prim_type t);
/* Number of primitives: points, line segments or triangles. */
uint64_t lc_scene_primitive_count(const lc_scene *s);

#ifdef __cplusplus
}
#endif
#endif
