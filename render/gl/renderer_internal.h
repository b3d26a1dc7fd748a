/* Internals shared by the renderer's modules: the renderer and GPU scene
 * objects, render targets, shader binding points, and the pass helpers that
 * frame.c, fourier.c, baselines.c and exact.c build on. Not public.
 * Threading: everything here runs on the thread that holds the renderer's GL
 * context, one frame at a time. */
#ifndef LC_RENDERER_INTERNAL_H
#define LC_RENDERER_INTERNAL_H

#include <epoxy/gl.h>

#include "camera.h"
#include "lod.h"
#include "renderer.h"
#include "vertex_pack.h"

#define LC_MAX_COEF_TARGETS 5 /* (2 * 8 + 1 + 3) / 4 */
/* The binning baseline's depth bins (FOO §5.3): with the total they fill the
 * 12 channels of the three targets that 5 bands' 11 coefficients take. */
#define LC_TAU_BINS 11
#define LC_TAU_BINS_TEXT "11"
#define LC_TAU_BINS_BANDS 5

/* Binding points of shader storage buffers (SSBO), texture units and image
 * units. Shaders name them (BIND_POSITIONS, TEX_COLORMAP, ...): programs.c
 * prepends a #define for each entry, so the numbers live only here. */
#define LC_GL_BINDINGS(X)                                                                                              \
    X(BIND_POSITIONS, 0)                                                                                               \
    X(BIND_FRAMES, 1)                                                                                                  \
    X(BIND_ATTRIBUTES, 2)                                                                                              \
    X(BIND_COLORS, 3)                                                                                                  \
    X(BIND_VERTEX_ELEMENTS, 4)                                                                                         \
    X(BIND_VERTEX_WEIGHTS, 5)                                                                                          \
    X(BIND_INDICES, 6)                                                                                                 \
    X(BIND_ELEMENT_ALPHA_MIN, 7)                                                                                       \
    X(BIND_ELEMENT_ALPHA, 8)                                                                                           \
    X(BIND_SMOOTH_SRC, 9)                                                                                              \
    X(BIND_SMOOTH_DST, 10)                                                                                             \
    X(BIND_ADJ_OFFSETS, 11)                                                                                            \
    X(BIND_ADJ, 12)                                                                                                    \
    X(BIND_STATS, 13)                                                                                                  \
    X(BIND_EXACT_NODES, 14)                                                                                            \
    X(BIND_EXACT_COUNTERS, 15)                                                                                         \
    X(BIND_MASS_HISTOGRAM, 16)                                                                                         \
    X(BIND_ELEMENT_IMPORTANCE, 17)                                                                                     \
    X(BIND_POSITION_CHUNKS, 18)                                                                                        \
    X(BIND_POINT_HISTOGRAM, 19)                                                                                        \
    X(BIND_POINT_LIST, 20)                                                                                             \
    X(BIND_VISIBLE, 21)         /* filter.c: one visibility bit per vertex, read by the geometry passes */             \
    X(BIND_LINE_OFFSETS, 22)    /* filter.c: the lines' first vertices */                                              \
    X(BIND_VISIBLE_OUT, 23)     /* filter.c: the mask being written */                                                 \
    X(BIND_ADJ_WEIGHTS, 24)     /* params.smoothingWeights "distance" */                                               \
    X(BIND_LINE_MASK, 25)       /* line_clusters.c: one bit per vertex, 1 = drawn */                                   \
    X(BIND_ELEMENT_BEHIND, 26)  /* importance mass behind each element's fragments (occluders.glsl) */                 \
    X(BIND_COLOR_HISTOGRAM, 27) /* color_equalize.c: visibility-weighted colour bins */                                \
    X(BIND_SURFACE_NODES, 28)   /* surface_layers.c: the batch's fragment lists */                                     \
    X(BIND_SURFACE_PIXELS, 29)  /* surface_layers.c: counters, list heads, layer counts, output */                     \
    X(BIND_SURFACE_LAYERS, 30)  /* surface_layers.c: the persistent per-pixel layers */                                \
    X(BIND_ELEMENT_G, 31)       /* visibility.c: each element's mean importance, read by P2's emphasis on patches */   \
    X(BIND_IMPORTANT_OCCLUDED, 28) /* visibility.c: importantOccluded's two counts (P2, exact opacity; never with      \
                                      surface_layers.c's nodes) */                                                     \
    X(BIND_TOP_REACH, 26)          /* fourier.c: topDecileReach's sums in P5 (element_behind is P2's) */               \
    X(BIND_FRAGMENT_LIST, 14)   /* fragment_list.c: P1's fragments for P2 (never in a program of the exact method) */  \
    X(BIND_FRAGMENT_CHAINS, 15) /* fragment_list.c: P0's per-pixel chains for P1 (never in the exact method's) */      \
    X(BIND_LINE_RUNS, 9)        /* line_subset.c (a compute pass; P3's bindings are free there): a level's runs */     \
    X(BIND_LINE_SELECT, 10)     /* line_subset.c: the kept strip's two counts and each run's importance bin */         \
    X(BIND_LINE_KEPT, 20)       /* line_subset.c: the kept strip (lines never bind the point list) */                  \
    X(BIND_RASTER_SUMS, 9) /* compute_raster.c: per-pixel sums, a plane per channel (P3's bindings are free there) */  \
    X(BIND_RASTER_LARGE, 10) /* compute_raster.c: the primitives left to the second dispatch */                        \
    X(TEX_COLORMAP, 0)       /* geometry passes */                                                                     \
    X(TEX_COEF_FIRST, 1)     /* first coefficient target sampled by the mass histogram */                              \
    X(TEX_PIXEL_RANGE, 6)    /* P0 output read by later passes */                                                      \
    X(TEX_DEPTH_MOMENTS, 7)  /* P0 "moments" output read by P1, P2, P4 and P5 */                                       \
    X(TEX_EQUALIZE_ACCUM, 3) /* color_equalize.c: P5's sums read by the colour histogram */                            \
    X(TEX_RESOLVE_A, 0)      /* full-screen resolves: accumulation */                                                  \
    X(TEX_RESOLVE_B, 1)      /* ... and optical depth (P6) or revealage (WBOIT) */                                     \
    X(TEX_CONTEXT_DEPTH, 8)  /* context.c: the opaque context's depth, tested by every transparent pass */             \
    X(TEX_CONTEXT_COLOR, 9)  /* context.c: its colour, under P6 and the exact blend */                                 \
    X(TEX_KANZLER_MAPS, 10)  /* kanzler.c: (C, M, D, V) per pixel, read by the kanzler P4/P5 */                        \
    X(TEX_KANZLER_SUMS, 11)  /* kanzler.c: tangent sums and counts, read by the blur */                                \
    X(TEX_REACH_SUMS, 3)     /* visibility.c: P5's per-pixel topDecileReach sums, read by their reduction */           \
    X(IMG_KANZLER_MAX, 7)    /* kanzler.c: packed maximum importance and depth (R32UI) */                              \
    X(IMG_KANZLER_MAPS, 1)   /* kanzler.c: the blur's output (the exact method's output unit is free there) */         \
    X(TEX_SHADOW_COLOR, 10)  /* shadow.c: the light's optical-depth-weighted colour */                                 \
    X(IMG_SMART_SRC, 7)      /* smart.c: silhouette and halo intensities being diffused */                             \
    X(IMG_SMART_DST, 8)                                                                                                \
    X(IMG_SMART_OUTPUT, 9)  /* smart.c: the image they modulate */                                                     \
    X(IMG_SMART_INJECT, 10) /* smart.c: the injected intensities and each pixel's optical depth */                     \
    X(IMG_EXACT_HEADS, 0)   /* exact method: per-pixel list heads */                                                   \
    X(IMG_P5_REACH, 0)      /* P5 over P4's fragments: the per-pixel topDecileReach sums */                            \
    X(IMG_EXACT_OUTPUT, 1)  /* exact method: blended image */                                                          \
    X(IMG_EXACT_REDUCED, 1) /* exact list pass 1: per-pixel opacity left out (never with the blend's output) */        \
    X(IMG_EXACT_STATE, 2) /* exact sort passes: a pixel's sums between chunks (no coefficient targets bound there) */  \
    X(IMG_EXACT_BOUND, 3) /* exact blend: the last fragment blended, where the next chunk starts */                    \
    X(IMG_COEF_FIRST, 2)  /* 2..1+LC_MAX_COEF_TARGETS: coefficient targets read by P2 and P5 */

/* Constants that the host and the shaders must agree on, injected the same
 * way: the mass histogram's layout (mass_common.glsl), the attribute table size. */
#define LC_GL_CONSTANTS(X)                                                                                             \
    X(MASS_BINS, 1024)                                                                                                 \
    X(MASS_BINS_PER_OCTAVE, 16)                                                                                        \
    X(MASS_LOG2_MIN, -24)                                                                                              \
    X(POINT_BINS, 1024)        /* importance bins of the point subsets (point_subset.c) */                             \
    X(MAX_ATTRIBUTES, 32)      /* LC_MAX_ATTRIBUTES: the compact layout's per-attribute uniforms */                    \
    X(MAX_IMPORTANCE_TERMS, 4) /* LC_MAX_IMPORTANCE_TERMS (common.glsl vertex_importance) */                           \
    X(MAX_FILTERS, 8)          /* LC_MAX_FILTERS (filter_mask.comp.glsl) */                                            \
    X(MAX_CURVE_POINTS, 64)    /* LC_MAX_CURVE_POINTS (common.glsl curve_eval) */

#define LC_GL_BINDING_ENUM(name, value) name = value,
enum { LC_GL_CONSTANTS(LC_GL_BINDING_ENUM) };
enum { LC_GL_BINDINGS(LC_GL_BINDING_ENUM) };
#undef LC_GL_BINDING_ENUM
_Static_assert(MAX_ATTRIBUTES == LC_MAX_ATTRIBUTES, "shader attribute tables");
_Static_assert(MAX_IMPORTANCE_TERMS == LC_MAX_IMPORTANCE_TERMS, "shader importance terms");
_Static_assert(MAX_FILTERS == LC_MAX_FILTERS, "shader filters");
_Static_assert(MAX_CURVE_POINTS == LC_MAX_CURVE_POINTS, "shader curves");

/* The weighted importance terms of a frame (frame.c resolves them), compared
 * with memcmp by the caches keyed by the importance mapping: zero-filled. */
typedef struct lc_importance_terms {
    double range[LC_MAX_IMPORTANCE_TERMS][2];
    double weight[LC_MAX_IMPORTANCE_TERMS];
    double norm;                         /* 1 / sum |w| */
    uint64_t mask_serial;                /* the filter mask the caches saw (filter.c); 0: none */
    float curve[LC_MAX_CURVE_POINTS][2]; /* importance.curve */
    int curve_count;
    int count; /* 0: the single form */
    int attr[LC_MAX_IMPORTANCE_TERMS];
    int invert[LC_MAX_IMPORTANCE_TERMS];
    int penalty; /* sum w < 0 */
    int unused;  /* no tail padding: memcmp sees every byte */
} lc_importance_terms;

/* One level of detail: the primitives a pass draws. Level 0 is the whole
 * scene; lines have coarser levels (render/scene/lod.h). */
/* Lines draw their ribbons as indexed triangle strips, one per run of
 * consecutive segments: sides 2v, 2v+1 of each line vertex v, runs separated by
 * two restart indices so that every run starts at an even offset (the subset
 * path reads ribbon slot q from indices 2q and 2q + 2). */
#define LC_STRIP_RESTART 0xFFFFFFFFu

typedef struct lc_gpu_level {
    GLuint indices;           /* ribbon strips (lines) or the triangles: the element buffer of indexed
                                 draws, and the SSBO that subset draws pull from */
    uint64_t primitive_count; /* points, segments or triangles */
    double error;             /* world units (0 for level 0) */
    /* Lines: the same runs as line strips, one index a line vertex (every
     * other index of the ribbon strip, halved; line_primitive.c). */
    GLuint line_indices;
    /* Lines: the strip's length in indices, and offsets of run starts at least
     * STRIP_BREAK_SPACING indices apart where a batched draw may split it. */
    uint64_t index_count;
    uint64_t *breaks;
    uint32_t break_count;
    /* Lines: (first index, indices) of each run of the strip, for the
     * importance-aware line subsets of moving frames (line_subset.c). */
    GLuint runs;
    uint32_t run_count;
} lc_gpu_level;

struct lc_gpu_scene {
    const lc_scene *scene;
    /* Unique for the life of the process: caches key on it, never on the
     * address, which a later scene may reuse. */
    uint64_t serial;
    GLuint positions, frames, attributes, colors, vertex_elements, vertex_weights;
    GLuint adj_offsets, adj;
    GLuint adj_weights; /* per adjacency entry (lc_elements_adjacency_weights) */
    int level_count;
    lc_gpu_level levels[LC_LOD_MAX_LEVELS];
    uint64_t bytes;
    uint64_t lod_bytes; /* the levels beyond 0 (included in bytes) */
    /* Layout (vertex_pack.h): exact = float buffers; otherwise compact, with
     * position_chunks holding each chunk's bounds. */
    int exact;
    GLuint position_chunks;
    lc_blend_layout blend;
    uint32_t attr_offset[LC_MAX_ATTRIBUTES]; /* in 32-bit words */
    int attr_format[LC_MAX_ATTRIBUTES];      /* 0 float, 1 unorm16 */
    float attr_decode[LC_MAX_ATTRIBUTES][2]; /* unorm16: value = [0] + [1] * code */
    uint64_t attribute_bytes;
    lc_gpu_memory memory;
    struct lc_line_clusters *clusters; /* lines: line_clusters.c; NULL otherwise */
};

/* A colour target set at one resolution. */
typedef struct lc_targets {
    int width, height, count;
    GLuint fbo;
    GLuint tex[LC_MAX_COEF_TARGETS];
    GLenum format;
} lc_targets;

typedef enum {
    PROG_P1 = 0,
    PROG_P2,
    PROG_P4,
    PROG_P5,
    PROG_P4_DIRECT,
    PROG_P5_DIRECT,
    PROG_OPAQUE,
    PROG_WBOIT,
    PROG_DEPTH_RANGE,
    PROG_DEPTH_MOMENTS,
    PROG_COLOR_HISTOGRAM, /* color_equalize.c, after P5 */
    PROG_COLOR_HISTOGRAM_DIRECT,
    PROG_P1_LIST,            /* P1 that also records its fragments (fragment_list.c) */
    PROG_DEPTH_MOMENTS_LIST, /* P0 "moments" that also records its fragments and chains (fragment_list.c) */
    PROG_P4_LIST,            /* P4 that also records what P5 needs of its fragments, chained (fragment_list.c) */
    PROG_P4_BINS,            /* P4 and P5 of the binning baseline (tau in depth bins, baselines.c) */
    PROG_P5_BINS,
    PROG_WEIGHTED_AVERAGE, /* the weighted average baseline's accumulation (baselines.c) */
    PROG_KANZLER_MAPS,     /* kanzler.c: the per-pixel maps */
    PROG_P4_KANZLER,       /* P4 with alpha = g^k times Kanzler's penalty */
    PROG_P5_KANZLER,
    PROG_SHADOW, /* P4 from the light, with the optical-depth-weighted colour (shadow.c) */
    PROG_SHADOW_DIRECT,
    PROG_GEOMETRY_KINDS, /* per primitive type and band count */
    PROG_P3 = PROG_GEOMETRY_KINDS,
    PROG_RESOLVE,
    PROG_WBOIT_RESOLVE,
    PROG_WEIGHTED_AVERAGE_RESOLVE,
    PROG_MASS_HISTOGRAM,
    PROG_ELEMENT_IMPORTANCE,
    PROG_POINT_SELECT,
    PROG_LINE_SELECT,
    PROG_FILTER_MASK,
    PROG_KANZLER_BLUR,  /* kanzler.c: C, V and the 5x5 mean of M and D */
    PROG_REACH_REDUCE,  /* visibility.c: the per-pixel topDecileReach sums into their 64 slots */
    PROG_P0_CHAINS,     /* P0's moments over its fragments (fragment_list.c) */
    PROG_P2_LIST_FIRST, /* P2 over P1's fragment list, per band count 1..LC_MAX_BANDS (fragment_list.c) */
    PROG_P1_CHAINS_FIRST = PROG_P2_LIST_FIRST + LC_MAX_BANDS,    /* P1 over P0's fragments, per band count */
    PROG_P5_CHAINS_FIRST = PROG_P1_CHAINS_FIRST + LC_MAX_BANDS,  /* P5 over P4's fragments, per band count */
    PROG_P4_CHAINS_FIRST = PROG_P5_CHAINS_FIRST + LC_MAX_BANDS,  /* P4's sums over its fragments, per band count */
    PROG_P45_CHAINS_FIRST = PROG_P4_CHAINS_FIRST + LC_MAX_BANDS, /* P4's sums and P5 in one walk, per band count */
    PROG_FIXED_KINDS = PROG_P45_CHAINS_FIRST + LC_MAX_BANDS
} lc_program_kind;

#define LC_SPEC_PROGRAMS 48
typedef struct lc_spec_program {
    uint64_t key;
    lc_program_kind kind;
    GLuint prog;
    uint64_t used;
} lc_spec_program;

typedef struct lc_heads_target {
    GLuint tex, fbo;
    int width, height;
} lc_heads_target;

struct lc_renderer {
    lc_renderer_desc desc;
    GLuint vao;
    GLuint colormap_tex[16];
    int colormap_count;
    /* [kind][primitive][bands][variant][context]: lines and triangles 1 =
     * pulled (the unindexed subset variant), points 1 = GL point sprites,
     * lines 2 = one GL_LINES primitive a segment (r->line_primitive); context
     * 1 = with the opaque context's depth test (r->context_layers) */
    GLuint geometry_programs[PROG_GEOMETRY_KINDS][3][LC_MAX_BANDS + 1][3][2];
    /* lc_renderer_set_floor: the mode, and the FLOOR_EMPTY variants of the
     * geometry programs ([kind][primitive][bands][variant]), built on use. */
    lc_floor_mode floor;
    GLuint floor_programs[PROG_GEOMETRY_KINDS][3][LC_MAX_BANDS + 1][3];
    /* Specialized geometry programs (programs.c), by key: the slots above
     * and the frame values compiled in; the least recently used is replaced. */
    lc_spec_program spec_programs[LC_SPEC_PROGRAMS];
    uint64_t spec_clock;
    int specialize; /* lc_renderer_set_specialize: 1 (the default) or 0 */
    /* fragment_list.c: P1's fragments (16 bytes each after a 16-byte count),
     * the capacity allocated, the largest count seen, and whether this
     * frame's P1 filled it (fragment_count of them). */
    GLuint fragment_list;
    uint64_t fragment_capacity, fragment_seen;
    uint32_t fragment_count;
    int fragments_ready;
    /* P0's recording (FRAGMENT_CHAINS): the chains' buffer (a pixel's first
     * and last entry, 2 words a pixel of the optimization resolution), its size in
     * words, the pixels and width of the frame's chains, and whether this
     * frame's P0 recorded every fragment for P1 (fragment_list.c). */
    GLuint fragment_chains;
    uint64_t chain_words;
    uint32_t chain_pixels, chain_width;
    int fragments_chained;
    /* P4's list for its sums and P5 (COMPOSITE_LIST; 16 bytes an entry after
     * a 16-byte count); its per-pixel heads share fragment_chains. */
    GLuint composite_list;
    GLuint record_fbo; /* no attachment: the recording P0 and P4 without framebuffer fetch (fragment_list.c) */
    /* With framebuffer fetch (heads_fetch): the recording P0's and P4's
     * chain heads as an R32UI target each (fragment_list.c). */
    bool heads_fetch;
    lc_heads_target heads[2];
    uint64_t composite_limit;                      /* tests: the most entries a list may hold (0: the guess's) */
    uint64_t fragment_limit;                       /* tests: the same for P0's and P1's list */
    int composite_limit_once, fragment_limit_once; /* tests: the limit holds for the next list made only */
    uint64_t composite_capacity, composite_seen;
    uint64_t composite_offered; /* the last recording P4's fragments, stored or not */
    /* P4's fragments over P0's in the last recording frame of this scene and
     * size: the next frame's estimate of its list (fragment_list.c). */
    double composite_ratio;
    const void *composite_ratio_scene;
    int composite_ratio_width, composite_ratio_height;
    /* A drawn P4's fragments, counted by an occlusion query (lc_fragment_hint_*):
     * counting from the frame's first drawn P4 until the frame stores the count. */
    GLuint fragment_query;
    bool fragment_counting;
    GLuint fixed_programs[PROG_FIXED_KINDS];
    lc_targets coef_low;   /* P1 at optimization resolution */
    lc_targets coef_full;  /* P4 */
    lc_targets accum;      /* P5 (and WBOIT accum + revealage) */
    lc_targets output;     /* RGBA8 + depth */
    lc_targets range_full; /* P0 per-pixel depth ranges (RG32F), output resolution */
    lc_targets range_low;  /* the same at the optimization resolution */
    lc_targets moments;    /* P0 "moments": per-pixel importance mass moments (RGBA32F), optimization resolution */
    GLuint output_depth;   /* opaque baseline only */
    int depth_width, depth_height;
    GLuint nofb; /* framebuffer without attachments for P2 */
    int nofb_w, nofb_h;
    /* per-element buffers, grown to the largest scene */
    GLuint element_alpha_min, element_alpha, smooth_a, smooth_b, stats;
    GLuint element_behind;     /* per element: importance mass behind its fragments (visibility report) */
    GLuint important_occluded; /* 2 uints: important fragments, and those with important mass in front */
    GLuint top_reach;          /* topDecileReach's P5 sums: 64 slots of four 64-bit sums (visibility.c) */
    /* A drawn P5 blends the sums per pixel into reach_sums (RGBA32F, the
     * pass's size) beside the accumulation, through reach_fbo, and a compute
     * pass adds them into top_reach; reach_drawn says this P5 does. */
    lc_targets reach_sums;
    GLuint reach_fbo;
    int reach_drawn;
    float reach_g; /* the importance P5 counts from (the top decile's lowest bin); > 1: none */
    uint32_t element_capacity;
    GLuint mass_histogram;     /* MASS_BINS counts (visibility.c) */
    GLuint element_importance; /* 2 uints per element: fixed-point sum, count */
    GLuint element_g;          /* importance_cache on the GPU (BIND_ELEMENT_G), valid while element_g_serial matches */
    uint64_t importance_serial, element_g_serial; /* bumped per importance_cache fill; element_g's copy of it */
    uint32_t element_g_count;
    /* CPU copy of the elements' mean importance for the mapping in the key. */
    float *importance_cache;
    uint32_t importance_cache_count;
    struct {
        uint64_t scene;   /* lc_gpu_scene.serial */
        uint64_t layered; /* a layered frame's layers and mappings, hashed (0: one dataset) */
        int attr;
        double range[2], exponent;
        lc_importance_terms terms;
    } importance_key;
    /* point_subset.c: the importance histogram of the points under the
     * mapping in its key, and the list of the points at or above keep_bin. */
    GLuint point_histogram, point_list;
    uint32_t point_list_capacity;
    struct {
        const lc_gpu_scene *gs;
        int attr;
        double range[2], exponent;
        lc_importance_terms terms;
        int valid;
        uint32_t bins[POINT_BINS];
    } point_hist;
    struct {
        int keep_bin;
        uint32_t count;
    } point_kept;
    /* line_subset.c: each run's importance bin and the counts (line_select),
     * the kept strip (line_kept), and what they were built for. */
    GLuint line_select, line_kept;
    uint64_t line_select_bytes, line_kept_bytes;
    struct {
        uint64_t scene; /* lc_gpu_scene.serial */
        int level, attr;
        double range[2], exponent;
        lc_importance_terms terms;
        int bins_valid;
        uint32_t bins[POINT_BINS];
        int keep_bin, stride;   /* the kept strip's cut; keep_bin -1: none built */
        uint32_t full, strided; /* its indices: full runs from 0, strided ones ending at total */
        uint64_t total;
    } line_sel;
    /* filter.c: per-vertex visibility masks, one per scene and filter list a
     * frame draws (a layered frame's layers each have their own), kept while
     * they match: the line offsets of the scene each was built for, the mask
     * of the filters in its key. */
    struct lc_filter_mask {
        uint64_t scene; /* lc_gpu_scene.serial of the scene it was built for; 0: none */
        GLuint offsets, mask;
        uint32_t mask_words, offset_words;
        lc_filter filters[LC_MAX_FILTERS];
        int attr[LC_MAX_FILTERS];
        int count;       /* -1: no mask built */
        uint64_t serial; /* of the mask's contents (fs->terms.mask_serial) */
        uint64_t used;   /* the frame that last drew with it (r->filter_frame) */
    } filter[LC_MAX_LAYERS];
    uint64_t filter_frame, filter_serial;
    /* filter.c: this frame's lines draw as pulled segments (a time window hides
     * single segments, which shared ribbon strip vertices cannot). */
    int pull_lines;
    /* progressive.c: the batch the next frame of the progressive still may
     * add (0: none under way) and the request it belongs to. */
    int progressive_next;
    int progressive_listed; /* P1's fragment list holds every fragment of the batches so far (fourier.c) */
    lc_render_params *progressive_params;
    const lc_gpu_scene *progressive_scene;
    /* line_primitive.c: this frame's line segments draw as wide GL_LINES
     * (pulled, so pull_lines is set too); the driver's widest line; the path
     * lc_renderer_set_line_path forces (-1: the rule). */
    int line_primitive;
    float line_width_max;
    int line_path;
    /* This frame has an opaque context layer whose depth the transparent
     * passes test (context.c): their programs are the CONTEXT_DEPTH variants. */
    int context_layers;
    /* This frame's points draw as GL point sprites (lc_frame_point_sprites),
     * and the limits that decide it (read at creation). */
    int point_sprites;
    /* Yield points inside a pass (pipeline.c batch_yield): fourier.c allows
     * them around the draws of P0, P1, P2, P4 and P5, each followed by a
     * yield point before anything keeps the pass's result; yield_cut says a
     * draw ended early, so the frame's other draws are skipped and the next
     * yield point ends the frame. */
    int draw_yields, yield_cut;
    /* Vertices the frame's draws issued (pipeline.c), and by pass from the
     * timestamps (lc_renderer_timestamp): lc_frame_info.pass_vertices. */
    uint64_t vertices_issued, vertices_mark, pass_vertices[LC_PASS_COUNT];
    /* The frame's work budget (lc_renderer_set_work; NULL = none): elapsed
     * time charged at every yield point and between batches. */
    lc_work_budget *work;
    float point_size_max;
    int max_viewport[2];
    GLuint timer_queries[LC_PASS_COUNT + 1];
    /* Pass progress of the current frame (desc.progress): its planned passes in order. */
    int progress_order[LC_PASS_COUNT];
    int progress_planned, progress_done;
    double progress_t0; /* lc_now() at the frame's start */
    GLuint dummy_buffer;
    void *exact;                 /* exact.c's state */
    void *context;               /* context.c's state */
    void *kanzler;               /* kanzler.c's state */
    GLuint marker_program;       /* markers.c's (lines, pulled), built on first use */
    struct shadow_state *shadow; /* shadow.c's targets and programs (NULL until a frame has shadows or a ground) */
    struct smart_state *smart;   /* smart.c's */
    /* reduce.c: host copy of a target or buffer being reduced, capacity in floats */
    float *reduce_buf;
    size_t reduce_cap;
    uint64_t bytes_targets, bytes_elements;
    /* compute_raster.c: its programs ([P4, P5, P4 direct, P5 direct][points,
     * lines][bands]), the store program, the per-pixel sums (bytes allocated)
     * and the large-primitive list; the pass's size and planes; the path
     * lc_renderer_set_raster_path forces (-1: the rule). */
    GLuint raster_programs[4][2][LC_MAX_BANDS + 1], raster_store_program;
    GLuint raster_add_programs[2]; /* the store adding to RGBA32F / RGBA16F targets (params.progressive) */
    GLuint raster_sums, raster_large;
    uint64_t raster_sums_bytes;
    int raster_width, raster_height, raster_planes, raster_path;
    /* line_clusters.c: the uploaded masks (one per clustered layer a frame
     * draws), whose cut each holds and the frame that last drew with it. */
    struct lc_line_mask {
        GLuint buffer;
        uint64_t bytes, stamp, used;
        const lc_gpu_scene *scene;
    } line_masks[LC_MAX_LAYERS];
    /* color_equalize.c: the histogram buffer, the equalized colormap, and the
     * last equalized frame's histogram and transfer (lc_renderer_color_histogram). */
    GLuint color_histogram, equalized_tex[LC_MAX_LAYERS]; /* a texture per layer's mapping ([0]: one dataset's) */
    double eq_hist[256];
    float eq_knots[257];
    int eq_valid;
    /* The exact method's sum over pixels of 1 - T and the halos' part of it,
     * in the histogram's units (lc_renderer_color_coverage); -1: not measured. */
    double eq_cover, eq_halo;
};

struct lc_frame_state {
    uint32_t count;
    int fresh;
    float *alpha;      /* full precision, or NULL when compact */
    uint16_t *alpha16; /* compact: unorm16 */
    /* color.equalize: the transfer F the session's frames use (DLS Eq. 10),
     * one per colour mapping: [0] a dataset's or layer 0's, [i] layer i's. */
    struct {
        int valid;
        float knots[257];
    } eq[LC_MAX_LAYERS];
    lc_clarity_strength clarity; /* params.clarity: the factors the next frame starts from (clarity.c) */
    /* The fragments a frame of this camera drew in P4, per pixel of its view
     * and scaled to every primitive of its level (a stride's frame counts
     * one in n): the next frame of the same camera sizes P0's list by it
     * (fragment_list.c), as a still after a drag is denser than the view the
     * renderer last recorded. per_pixel 0: none. */
    struct {
        const void *scene;
        lc_camera camera;
        double per_pixel;
    } fragment_hint;
};

/* ---- frame_state.c: the state's opacities to and from a float GPU buffer; a
 * colour mapping's transfer by slot (lc_frame_setup.eq_slot). */
void lc_frame_state_equalize_slot(lc_frame_state *st, int slot, const float *target, double dt, double half_life);
const float *lc_frame_state_equalize_knots_slot(const lc_frame_state *st, int slot);
void lc_frame_state_upload(const lc_frame_state *st, GLuint buffer);
void lc_frame_state_download(lc_frame_state *st, GLuint buffer);

/* Everything a geometry pass needs from the frame's parameters. */
typedef struct lc_frame_setup {
    const lc_render_params *params;
    const lc_gpu_scene *gs;
    lc_view view;
    int importance_attr, color_mode, color_attr, colormap;
    double importance_range[2], color_range[2], importance_exponent;
    lc_importance_terms terms;
    double line_half_width; /* world */
    int width, height;      /* output */
    int low_width, low_height;
    int pixel_depth_range; /* P0 ran: geometry passes normalize by range_full / range_low */
    int depth_moments;     /* P0 "moments" ran: P1, P2, P4 and P5 warp depth by r->moments */
    int moments_guard[2];  /* params.guardBand: texels of r->moments beyond the view on each side */
    int level;             /* level of detail of every geometry pass (gs->levels) */
    int point_stride;      /* points: every n-th in every pass */
    /* Importance-aware point subsets (point_subset.c): with a stride, the
     * points in importance bin keep_bin or above are drawn in full from the
     * renderer's point list (point_kept of them), the rest every n-th;
     * keep_bin > POINT_BINS when the stride is uniform. */
    int keep_bin;
    uint32_t kept_points;
    /* Importance-aware line subsets (line_subset.c): frames that reuse the
     * opacities draw the renderer's kept strip instead of the level's when
     * line_stride > 1: kept_line_indices[0] indices of full runs from its
     * start, [1] of every line_stride-th other run ending at kept_line_total. */
    int line_stride;
    uint64_t kept_line_indices[2], kept_line_total;
    GLuint kept_line_buffer;
    /* filter.c: the visibility mask filter_mask applies (0: every vertex draws). */
    int filtered;
    GLuint filter_mask;
    int pull_lines;        /* filter.c: a time window; lines draw segment by segment (r->pull_lines) */
    int line_primitive;    /* segments draw as wide GL_LINES (line_primitive.c; r->line_primitive) */
    int point_sprites;     /* points draw as GL points this frame (lc_frame_point_sprites; r->point_sprites) */
    int p1_subset;         /* P1's stride: params.subset, or params.autoSubset's choice after P0 (fourier.c) */
    int p1_done;           /* P1's sums of this frame are in r->coef_low: the clarity loop's later tries, which
                              change only the strength P2 applies, keep them (lc_fourier_optimize) */
    lc_frame_state *state; /* the session's state (NULL: a one-shot frame) */
    int p0_chained;        /* this frame's P0 recorded its fragments for P1 (fragment_list.c) */
    uint64_t p0_fragments; /* how many (0: not recorded; the composite list's guess, fragment_list.c) */
    /* The frame's report (reduce.c adds its cost). */
    lc_frame_info *info;
    int line_mask; /* line_clusters.c: geometry passes skip the vertices whose bit is clear */
    GLuint line_mask_buffer;
    GLuint colormap_texture; /* color_equalize.c: the equalized colormap; 0 = fs->colormap's */
    /* Tiled stills (frame.c): while tiled, width x height is the tile, whose
     * lower-left pixel sits at tile_origin (GL's bottom-up pixels) of the
     * frame_width x frame_height frame; full-resolution passes project the
     * whole frame through a viewport offset by -tile_origin. */
    int tiled, tile_origin[2], frame_width, frame_height;
    /* Layers (layers.c): 0 for a frame of one dataset; otherwise every
     * geometry pass draws each visible layer with lc_frame_layer's setup. */
    int layer_count;
    int eq_slot; /* color.equalize: the mapping's slot in the state and the textures (a layer's index, else 0) */
    const struct lc_layer_setup *layers;
    uint32_t element_offset; /* this setup's first element id (u_element_offset) */
    uint32_t element_total;  /* elements of the frame: of every layer, or of gs */
    /* context.c: the opaque context's depth at the output [0] and the
     * optimization [1] resolution and its colour (0: no context layer). */
    GLuint context_depth[2], context_color;
    lc_renderer *renderer; /* the frame's renderer: a draw's yield points between batches (pipeline.c) */
    double bounds[6];      /* the frame's bounds (of every layer): the camera's, the ground's and the light's */
    /* params.progressive (progressive.c): the pass under way draws batches
     * [batch_first, batch_end) of batch_count (0: every primitive), and with
     * keep_sums adds to its targets as the frame before left them. */
    int batch_count, batch_first, batch_end, keep_sums;
} lc_frame_setup;

/* ---- progressive.c (params.progressive): whether the frame may run as batch
 * k of its still (the previous batch ran last on this renderer, same request),
 * and the batches and kept sums of each pass (P0, P1, P2, P4; P5 as P4). */
int lc_progressive_begin(lc_renderer *r, const lc_frame_setup *fs, lc_error *err);
void lc_progressive_pass(lc_frame_setup *fs, lc_pass pass);
/* Primitives [*lo, *hi) of n that the setup's batches cover. */
void lc_progressive_range(const lc_frame_setup *fs, uint64_t n, uint64_t *lo, uint64_t *hi);

/* ---- layers.c (docs/ALGORITHM.md "Layers"): what differs per layer. */
typedef struct lc_layer_setup {
    const lc_gpu_scene *gs;
    lc_render_params params; /* the frame's, with the layer's importance, colour and style */
    int visible;
    int importance_attr, color_mode, color_attr, colormap;
    double importance_range[2], color_range[2], importance_exponent;
    lc_importance_terms terms;
    double line_half_width;
    int level;
    uint32_t element_offset;
    int context;              /* role "context": drawn opaque by context.c, in no transparent pass */
    int filtered, pull_lines; /* the layer's filters and time window (lc_filter_prepare) */
    GLuint filter_mask;
    int line_mask; /* the layer's lines.clusters (lc_line_clusters_prepare) */
    GLuint line_mask_buffer;
    GLuint colormap_texture; /* the layer's equalized colormap this frame (color_equalize.c); 0: its colormap */
} lc_layer_setup;
/* Geometry passes loop i over 0..lc_frame_layer_count(fs)-1: lc_frame_layer
 * returns the setup to draw layer i with (fs itself for a frame of one
 * dataset; else a copy of fs in *tmp with the layer's scene, mapping, level
 * and element offset), or NULL for a hidden layer. */
int lc_frame_layer_count(const lc_frame_setup *fs);
const lc_frame_setup *lc_frame_layer(const lc_frame_setup *fs, int i, lc_frame_setup *tmp);
/* Layer i's set-up itself, for the passes that keep per-layer results in it (color_equalize.c). */
lc_layer_setup *lc_frame_layer_setup(lc_frame_setup *fs, int i);
/* The same for the visible context layers (NULL for the others), and whether there is one. */
const lc_frame_setup *lc_frame_context_layer(const lc_frame_setup *fs, int i, lc_frame_setup *tmp);
int lc_frame_has_context(const lc_frame_setup *fs);
/* ---- context.c: draws the context layers' depth at the output (LC_CONTEXT_FULL,
 * with their colour) and the optimization resolution (LC_CONTEXT_LOW), for fs's
 * view and size (a tile's, a jittered sample's), and sets fs->context_* of
 * those; nothing without a context layer. */
enum { LC_CONTEXT_FULL = 1, LC_CONTEXT_LOW = 2 };
int lc_context_draw(lc_renderer *r, lc_frame_setup *fs, int which, lc_error *err);
void lc_context_destroy(lc_renderer *r);
/* ---- shadow.c (docs/ALGORITHM.md §29): whether the frame draws the ground
 * plane, which context.c draws into the context at w x h; the light's
 * Fourier opacity map and the shadowed context colour (after the opacities,
 * before P6: sets fs->context_color to it; nothing when style.shadow is 0). */
int lc_shadow_ground(const lc_frame_setup *fs);
/* Widens the clip planes of fs->view (fs->bounds, params, gs set) to hold the
 * ground; the depth range of the series stays the data's. */
void lc_shadow_clip_ground(const lc_frame_setup *fs, lc_view *view);
int lc_shadow_draw_ground(lc_renderer *r, const lc_frame_setup *fs, int w, int h, lc_error *err);
int lc_shadow_apply(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
void lc_shadow_destroy(lc_renderer *r);
/* ---- smart.c (docs/ALGORITHM.md §29): silhouettes and halos from P4's sums,
 * diffused, over the resolved image (after P6; nothing when style.smartTransparency is 0). */
int lc_smart_apply(lc_renderer *r, const lc_frame_setup *fs, lc_error *err);
void lc_smart_destroy(lc_renderer *r);
/* ---- markers.c: time.markers, drawn opaque over the frame's output (docs/ALGORITHM.md §26); nothing unless the
 * request asks for them on lines under a window. */
int lc_markers_draw(lc_renderer *r, const lc_frame_setup *fs, lc_error *err);
/* Fills out[0..n-1] from the layers' scenes and parameters over the frame's
 * params (fs->params, fs->view set): mappings (errors name layers[i].*),
 * levels, line widths, element offsets; sets fs->layers, fs->layer_count and
 * fs->element_total. */
int lc_frame_layers_prepare(lc_frame_setup *fs, const lc_gpu_scene *const *scenes, const lc_layer_params *layers, int n,
                            lc_layer_setup *out, lc_error *err);
/* The union of the layers' bounds (min xyz, max xyz). */
void lc_layers_bounds(const lc_gpu_scene *const *scenes, int n, double out[6]);
/* ---- mapping.c: the attribute mapping of fs->params over fs->gs (errors
 * name the field), and the level of detail of fs->gs for the frame's view. */
int lc_frame_resolve_mapping(lc_frame_setup *fs, lc_error *err);
int lc_frame_pick_level(const lc_frame_setup *fs);

/* ---- frame_compose.c: P4-P6 (or the baselines' single pass) of the frame's
 * method with its opacities; the output target (RGBA8, a depth buffer for the
 * opaque baseline); the antialias samples a frame's method takes (1: none);
 * samples 1..K-1 after the composite in the output, averaged into rgba; a
 * tiled still's tiles (each possibly antialiased) into rgba. */
int lc_frame_composite(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
void lc_frame_ensure_output(lc_renderer *r, int w, int h, int with_depth);
int lc_frame_antialias_samples(const lc_render_params *p);
int lc_frame_antialias(lc_renderer *r, lc_frame_setup *fs, int samples, uint8_t *rgba, lc_error *err);
int lc_frame_render_tiles(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, int nx, int ny,
                          int samples, int pixel_range, uint8_t *rgba, lc_error *err);
/* ---- filter.c */
/* Resolves the request's filters against the scene and builds (or reuses)
 * the per-vertex visibility mask they define; sets fs->filtered and the mask
 * serial the importance caches key on. Errors name filter[i]. */
int lc_filter_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
/* A new frame: the masks its layers draw with are picked afresh. */
void lc_filter_frame_begin(lc_renderer *r);
void lc_filter_release(lc_renderer *r);
uint64_t lc_filter_bytes(const lc_renderer *r);
/* ---- line_clusters.c */
typedef struct lc_line_clusters lc_line_clusters;
/* Resamples a line scene's lines for clustering (before its vertex arrays
 * are released); *out = NULL for other scenes. */
int lc_line_clusters_create(const lc_scene *s, lc_line_clusters **out, lc_error *err);
void lc_line_clusters_destroy(lc_line_clusters *lc);
uint64_t lc_line_clusters_bytes(const lc_line_clusters *lc);
/* The frame's (or a layer's) lines.clusters: builds the dendrogram on first
 * use (cached with the GPU scene for one linkage, lift and mapping), cuts it,
 * uploads the mask to one of r->line_masks and sets fs->line_mask and
 * fs->line_mask_buffer. Thread-safe across renderers. */
int lc_line_clusters_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err);

/* ---- point_subset.c */
/* Fills fs->keep_bin and fs->kept_points for a frame that thins points with
 * fs->point_stride (first lowered to the LC_POINT_SUBSET_PIXELS floor): the
 * points whose importance lies in the top 1/(4 n) of the points (n the
 * stride) are kept in full, where importance ranks them. */
int lc_point_subset_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
/* The lowest histogram bin whose entries and those above number at least
 * `want` without going over `most`; 0 when none (bin 0 is never kept).
 * *count: how many. Shared with line_subset.c. */
int lc_subset_choose_bin(const uint32_t *bins, uint64_t want, uint64_t most, uint32_t *count);

/* ---- line_subset.c */
/* Fills fs->kept_line_indices for a frame that may thin lines with
 * fs->line_stride (0 when it does not: the level's strip draws); lowers the
 * stride where the level is too sparse to thin that far. */
int lc_line_subset_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err);

static inline void lc_uniform_f(GLuint prog, const char *name, double v)
{
    glProgramUniform1f(prog, glGetUniformLocation(prog, name), (float)v);
}

static inline void lc_uniform_i(GLuint prog, const char *name, int v)
{
    glProgramUniform1i(prog, glGetUniformLocation(prog, name), v);
}

static inline void lc_uniform_u(GLuint prog, const char *name, unsigned v)
{
    glProgramUniform1ui(prog, glGetUniformLocation(prog, name), v);
}

static inline void lc_uniform_v2(GLuint prog, const char *name, double a, double b)
{
    glProgramUniform2f(prog, glGetUniformLocation(prog, name), (float)a, (float)b);
}

static inline void lc_uniform_v3(GLuint prog, const char *name, const double *v)
{
    glProgramUniform3f(prog, glGetUniformLocation(prog, name), (float)v[0], (float)v[1], (float)v[2]);
}

static inline int lc_pulls_primitives(lc_prim_type prim, int subset, int pull_lines)
{
    return prim != LC_PRIM_POINTS && (subset > 1 || (prim == LC_PRIM_LINES && pull_lines));
}

/* ---- programs.c */
/* Returns the program for (kind, primitive, bands) that lc_renderer_draw_geometry
 * draws with the given subset stride, compiling on first use; 0 on error. Lines
 * and triangles draw indexed (shared vertices shaded once) unless subset > 1,
 * which pulls every n-th primitive unindexed (#define PULL_PRIMITIVES); points
 * always draw instanced. Programs built elsewhere from geometry.vert.glsl
 * without PULL_PRIMITIVES match subset 1. */
GLuint lc_renderer_geometry_program(lc_renderer *r, const lc_frame_setup *fs, lc_program_kind kind, lc_prim_type prim,
                                    int bands, int subset, lc_error *err);
/* Specialized programs compile fs's values in (programs.c); the binding
 * checks that the program it binds was built for fs's values. fs NULL: the
 * kind's unspecialized program. */
void lc_programs_configure(const char *gl_renderer);
void lc_renderer_check_spec(const lc_renderer *r, GLuint prog, const lc_frame_setup *fs);
/* The full-screen and compute programs (P3, P6, WBOIT resolve), cached. */
GLuint lc_renderer_fixed_program(lc_renderer *r, lc_program_kind kind, lc_error *err);
/* Compiles a program from embedded shader files; defines is a "#define ..\n"
 * block. The binding #defines of LC_GL_BINDINGS come first. */
GLuint lc_renderer_build_program(const char *defines, const char *const *vertex_files,
                                 const char *const *fragment_files, const char *const *compute_files, const char *label,
                                 lc_error *err);

/* ---- gpu_scene.c */
/* An immutable buffer holding size bytes of data (16 zero bytes when size is
 * 0, so a binding is always valid); adds its size to *bytes. */
GLuint lc_gl_buffer(const void *data, size_t size, uint64_t *bytes);

/* ---- scratch.c: buffers sized by a frame, whose pages a discard gives back
 * where the driver would keep them (llvmpipe's idle scenes; scratch.c says why) */
/* Chooses for the driver named gl_renderer (GL_RENDERER), process-wide. */
void lc_scratch_configure(const char *gl_renderer);
/* An immutable buffer of bytes bytes with the storage flags given (and those
 * the discard needs), its contents undefined. */
GLuint lc_scratch_buffer(uint64_t bytes, GLbitfield flags);
/* Deletes *buf (0 is a no-op) and sets it to 0; on a software rasterizer its
 * pages go back to the system first. Waits for the commands issued so far
 * there: for release paths, not per frame. */
void lc_scratch_discard(GLuint *buf);

/* ---- pipeline.c */
/* Binds the scene's buffers and sets the shared uniforms of a geometry program
 * for a pass rendered at (w, h). */
void lc_renderer_bind_geometry(lc_renderer *r, GLuint prog, const lc_frame_setup *fs, int w, int h, int subset);
/* Sets the importance terms' uniforms (part of lc_renderer_bind_geometry). */
void lc_renderer_bind_terms(GLuint prog, const lc_importance_terms *t);
/* Sets the transfer functions' uniforms (part of lc_renderer_bind_geometry). */
void lc_renderer_bind_curves(GLuint prog, const lc_importance_terms *t, const lc_curve *color);
/* Sets the halo uniforms (style.halo*) of a compositing pass's program (P4,
 * P5, the exact method's full-resolution lists): none unless lines with a
 * halo width. Other passes leave them 0, so halos never reach P0-P2. */
void lc_renderer_bind_halo(GLuint prog, const lc_frame_setup *fs);
/* The colormap texture a frame's geometry passes sample (its equalized one, or its colormap's). */
GLuint lc_renderer_colormap_texture(const lc_renderer *r, const lc_frame_setup *fs);
/* Sets the direct baseline's opacity uniforms (params.directExponent,
 * alphaSource, alphaConstant, gamma) of a DIRECT_ALPHA program. */
void lc_renderer_bind_direct_alpha(GLuint prog, const lc_render_params *p);
/* Chooses how large draws are issued for the driver named gl_renderer
 * (GL_RENDERER): in batches on software rasterizers. Process-wide. */
void lc_pipeline_configure(const char *gl_renderer);
/* Issues the draw of every (subset-th) primitive of the frame's level. */
void lc_renderer_draw_geometry(const lc_frame_setup *fs, int subset);
/* Whether this frame's points draw as GL point sprites (one vertex each, the
 * disc from gl_PointCoord) rather than one 4-vertex quad each: on llvmpipe a
 * quad costs two triangle set-ups, about three times a point's
 * (docs/ALGORITHM.md "Point sprites"). Sprites need a splat no wider than the
 * driver's largest point and a frame that fits the viewport with a guard band
 * of a splat's radius on each side (GL drops a point whose centre is outside
 * the viewport; the guard band keeps the part of such a splat that reaches
 * into the image). LUCENT_POINT_SPRITES=0 in the environment draws quads
 * always. */
int lc_frame_point_sprites(const lc_renderer *r, const lc_render_params *p, int frame_width, int frame_height);
/* Distance from the eye to the focal point along the view direction (world
 * size of a pixel at depth d: pixel_world * d / this). */
double lc_frame_focal_distance(const lc_frame_setup *fs);
/* The primitive stride of a pass drawn with `subset` (points drawn
 * interactively also skip all but every point_stride-th); also the weight
 * of P1/P4's sums. */
unsigned lc_renderer_subset(const lc_frame_setup *fs, int subset);
/* The weight of P0's, P1's and P4's sums for a pass drawn with `subset`
 * (FOO's approximation); a point stride weighs by area instead (lc_point_splat). */
unsigned lc_renderer_weight(int subset);
/* A disc of radius >= sqrt(2)/2 px always covers a pixel centre, so every
 * point reaches P2 even at the reduced optimization resolution. */
#define POINT_RADIUS_FLOOR 0.75
/* The fraction of its view's size a frame of points is drawn at (detail.pixel_scale; 1 for a still). */
double lc_point_scale(const lc_render_params *p);
/* A splat's radius in a pass's pixels (pass_h of out_h rows) and the weight
 * of its fragments in P0, P1 and P4, so that it stands for the view's area
 * that the points it replaces cover in the still. A frame drawn at the view's
 * size draws splats as the still does, the stride's n-th point with weight n
 * (fs->point_stride; `listed`: the kept points, drawn in full, weight 1): its
 * splats lie on the still's, pixel for pixel. A frame drawn at a fraction s
 * of its view's size (a moving frame, stretched by the page) draws a splat s
 * times as wide and, with a stride, up to SPLAT_SPREAD times wider again
 * towards sqrt(n), so that a sparse region keeps some of the coverage the
 * still gives it instead of one splat in n; the weight takes the rest of the
 * area (below 1 where the floor radius is wider than the point). A still
 * (s = 1, no stride) draws as always, with weight 1. */
#define SPLAT_SPREAD 2.0
void lc_point_splat(const lc_frame_setup *fs, int pass_h, int out_h, int listed, double *radius, double *weight);
/* (Re)allocates a target set; format GL_RGBA32F, GL_RGBA16F, GL_RG32F or GL_RGBA8. */
void lc_targets_ensure(lc_targets *t, int w, int h, int count, GLenum format, uint64_t *bytes);
void lc_targets_free(lc_targets *t, uint64_t *bytes);
/* Clears every attachment to value (NULL = zero). */
void lc_targets_clear(const lc_targets *t, const float *value);
/* Binds a coefficient target set to the IMG_COEF_FIRST.. image units (read only). */
void lc_bind_coefficients(const lc_targets *t);
/* Dispatches `groups` work groups of a 1D compute shader (256 wide, indexed by
 * the shader's linear_invocation()), as a 2D grid
 * where they exceed the 65,535 groups a dimension guarantees (17 M items). */
void lc_dispatch_linear(GLuint groups);
/* Additive float blending for the accumulation passes. */
void lc_additive_blending(void);
/* Records a timestamp after pass `pass` (index LC_PASS_COUNT = frame start). */
void lc_renderer_timestamp(lc_renderer *r, int slot);
/* A yield point (desc.yield): 0 to go on, else LC_ERR_CANCELLED with err set;
 * the caller returns it at once. */
int lc_renderer_yield_point(lc_renderer *r, lc_error *err);
/* Full-screen resolve of `kind` into the output from a's first texture and second_tex. */
void lc_renderer_resolve(lc_renderer *r, const lc_frame_setup *fs, lc_program_kind kind, const lc_targets *a,
                         GLuint second_tex, lc_error *err);
/* Readback of the output into rgba (top-down rows). */
void lc_renderer_readback(lc_renderer *r, const lc_frame_setup *fs, uint8_t *rgba);

/* ---- fourier.c */
/* P0: per-pixel depth ranges at full and/or optimization resolution (a tiled
 * frame draws the full one per tile); sets fs->pixel_depth_range. */
int lc_fourier_depth_range(lc_renderer *r, lc_frame_setup *fs, int full, int low, lc_error *err);
/* P0 "moments": per-pixel importance mass moments at the optimization
 * resolution; sets fs->depth_moments. */
int lc_fourier_depth_moments(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
/* P1 + P2 + P3: this frame's element opacities (faded into state when given). */
/* ---- color_equalize.c (color.equalize; frame_check.c refuses what it
 * cannot do): _begin before the compositing passes puts the session's
 * equalized colormap in place; _end after them measures the frame's colour
 * histogram and either moves the session's transfer or (one-shot, first
 * frame) composites again with this view's. */
int lc_color_equalize_begin(lc_renderer *r, lc_frame_setup *fs, const lc_frame_state *state);
int lc_color_equalize_end(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, int direct,
                          lc_error *err);
/* The steps of _end for callers that composite otherwise (tiles, the exact
 * method): _reset empties the histogram; _measure adds the Fourier/direct
 * composite in place (one tile or the frame); _finish turns r->eq_hist into
 * the transfer, moves the session's or (*again = 1, fresh) puts this view's
 * table in place for a second composite; _use_table makes the frame's
 * geometry passes read T(F(.)) for the knots given. */
void lc_color_equalize_reset(lc_renderer *r);
int lc_color_equalize_measure(lc_renderer *r, lc_frame_setup *fs, int direct, int *fresh, lc_error *err);
int lc_color_equalize_finish(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, int fresh,
                             int *again, lc_error *err);
void lc_color_equalize_use_table(lc_renderer *r, lc_frame_setup *fs, const float *knots);

int lc_fourier_optimize(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                        lc_error *err);
/* P3 alone on element_alpha_min -> element_alpha (uploads state first). */
int lc_renderer_smooth_and_fade(lc_renderer *r, const lc_frame_setup *fs, lc_frame_state *state, double dt,
                                lc_frame_info *info, lc_error *err);
/* P4..P6 with the element opacities (or, direct, the opacity of params.alphaSource). */
int lc_fourier_composite(lc_renderer *r, lc_frame_setup *fs, int direct, lc_error *err);
/* P4..P6 of the binning baseline (FOO §5.3): P4 sums -ln(1 - alpha) into
 * LC_TAU_BINS depth bins, P5 weighs by tau(d) interpolated in them. */
int lc_binning_composite(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
/* How P4/P5 take a fragment's alpha: the element opacities, g^k (method
 * "direct"), or g^k times Kanzler's penalty (method "kanzler"). */
enum { LC_ALPHA_ELEMENTS = 0, LC_ALPHA_DIRECT = 1, LC_ALPHA_KANZLER = 2 };
/* P4..P6 with alpha as `direct` (LC_ALPHA_*) says; kanzler first draws its maps. */
int lc_fourier_composite(lc_renderer *r, lc_frame_setup *fs, int direct, lc_error *err);
/* kanzler.c: the maps of the frame at fs's full resolution (a geometry pass
 * and the blur; timed as P0); the maps' binding and weights for a kanzler
 * P4/P5 program; the textures freed (release) or everything (destroy). */
int lc_kanzler_maps(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
void lc_kanzler_bind(lc_renderer *r, GLuint prog, const lc_foo_params *f);
/* The frame's visibility report (docs/ALGORITHM.md §8, §28): _begin clears
 * what P4 records (before the frame's compositing runs, all its samples);
 * lc_kanzler_report measures after them. */
void lc_kanzler_report_begin(lc_renderer *r);
int lc_kanzler_report(lc_renderer *r, const lc_frame_setup *fs, lc_frame_info *info, lc_error *err);
void lc_kanzler_release(lc_renderer *r);
void lc_kanzler_destroy(lc_renderer *r);

/* ---- pipeline.c: pre-emption between two batches of a pass (desc.preempted,
 * where fourier.c allows it): nonzero ends the pass (r->yield_cut). */
int lc_renderer_batch_yield(const lc_frame_setup *fs);

/* ---- compute_raster.c (docs/ALGORITHM.md "Compute rasterization"): P4 and
 * P5 as compute passes, each invocation a point splat or a line segment that
 * covers its pixels itself and adds into per-pixel sums with float atomics. */
/* Reads the device's float atomics and the LUCENT_COMPUTE_RASTER override
 * (0 drawn, 1 compute where supported); at renderer creation. */
void lc_compute_raster_configure(const char *gl_renderer);

/* ---- line_primitive.c: lines as one primitive a segment */
/* Reads the device's line width range and LUCENT_LINE_PRIMITIVE (0 ribbons,
 * 1 lines where they fit); at renderer creation, its context current. */
void lc_line_primitive_configure(lc_renderer *r);
/* Whether frame fs (its view set) draws its line segments as wide lines:
 * the rule or the forced path, and a bounded ribbon width the device's
 * lines reach. */
int lc_frame_line_primitive(const lc_renderer *r, const lc_frame_setup *fs);
/* The GL line width that covers every ribbon of fs in a pass of height h
 * whose output is out_h pixels high; 0 where no bound exists. */
double lc_line_primitive_width(const lc_frame_setup *fs, int h, int out_h);
/* Whether pass `pass` of frame fs runs computed; listable: its P4 could
 * record its fragments instead (lc_composite_list_wanted), which the rule
 * prefers. */
int lc_compute_raster_wanted(const lc_renderer *r, const lc_frame_setup *fs, lc_raster_pass pass, int listable);
/* The program of P4, P5 or their direct variants for points or lines; 0 on error. */
GLuint lc_compute_raster_program(lc_renderer *r, lc_program_kind kind, lc_prim_type prim, int bands, lc_error *err);
/* A pass: begin clears `planes` sums of width x height; per layer, bind sets
 * the geometry's uniforms (then the caller its pass's own) and dispatch adds
 * its primitives; end stores the sums into t's targets (t->count of them). */
int lc_compute_raster_begin(lc_renderer *r, int width, int height, int planes, lc_error *err);
void lc_compute_raster_bind(lc_renderer *r, GLuint prog, const lc_frame_setup *fs, int subset);
void lc_compute_raster_dispatch(lc_renderer *r, GLuint prog, const lc_frame_setup *fs, int subset);
int lc_compute_raster_end(lc_renderer *r, const lc_targets *t, lc_error *err);
/* The same, adding the sums to what t holds (params.progressive's later batches). */
int lc_compute_raster_end_add(lc_renderer *r, const lc_targets *t, lc_error *err);
/* Frees the sums (a large frame's: lc_renderer_release_after), or everything. */
void lc_compute_raster_release_sums(lc_renderer *r);
void lc_compute_raster_release(lc_renderer *r);

/* ---- fragment_list.c (docs/ALGORITHM.md "The geometry path"): P1 records
 * its fragments so that P2 runs as a compute pass over them instead of a
 * second traversal of the geometry (every try of the clarity loop). */
/* Whether this frame's P1, drawn with stride p1_subset, records its
 * fragments: where the driver's choice allows (lc_fragment_list_configure) and P1 draws exactly P2's fragments (no
 * stride). */
int lc_fragment_list_wanted(const lc_renderer *r, int p1_subset);
/* Before P1: makes room, zeroes the count, binds the list for P1's program. */
void lc_fragment_list_begin(lc_renderer *r, const lc_frame_setup *fs);
/* params.progressive: P1 of a later batch appends to the list the batches
 * before it left (not cleared, not resized). */
void lc_fragment_list_resume(lc_renderer *r);
/* After P1: reads the count; r->fragments_ready when every fragment fit
 * (otherwise the list grows for later frames and this frame's P2 draws). */
void lc_fragment_list_end(lc_renderer *r);
/* P2's compute program over the list for m bands (cached; 0 on error), and
 * its dispatch over this frame's fragments once the caller has set the
 * opacity uniforms and bound the minima, coefficients and element buffers. */
GLuint lc_fragment_list_program(lc_renderer *r, int bands, lc_error *err);
void lc_fragment_list_dispatch(lc_renderer *r, GLuint prog);
/* P0 "moments" records its fragments and per-pixel chains when the frame
 * allows (lists on, no stride, one dataset, not a tile's full-resolution
 * optimization) and writes no target; its moments and P1 are then compute
 * passes over them: wanted before P0, begin before it (binds the list and a
 * recording framebuffer of w x h: no target but its chain heads'), end after it (sets
 * r->fragments_chained: every fragment fit, else P0 draws its moments again
 * and P1 draws), then lc_fragment_chains_moments into t (cleared by the caller). */
int lc_fragment_chains_wanted(const lc_renderer *r, const lc_frame_setup *fs);
/* P0's list by the frames before (lc_frame_state.fragment_hint): a drawn P4
 * of a frame with a state counts its fragments (begin before its draw, end
 * after it); lc_fragment_hint_store keeps the count in the state once the
 * frame knows what it drew. */
int lc_fragment_hint_begin(lc_renderer *r, const lc_frame_setup *fs);
void lc_fragment_hint_end(void);
void lc_fragment_hint_store(lc_renderer *r, const lc_frame_setup *fs, uint64_t drawn, uint64_t primitives);
void lc_fragment_chains_begin(lc_renderer *r, const lc_frame_setup *fs, int w, int h);
void lc_fragment_chains_end(lc_renderer *r);
int lc_fragment_chains_moments(lc_renderer *r, const lc_targets *t, lc_error *err);
/* After an end that found the list too small: 1 when a list of every
 * fragment P0 counted can be made, made and bound as by begin (P0 then
 * records again), 0 when it cannot (P0 draws its moments and P1 draws). */
int lc_fragment_chains_retry(lc_renderer *r, const lc_frame_setup *fs, int w, int h);
/* P1 into t (cleared by the caller) from the chains; the list then holds
 * P1's fragments as a recording P1 leaves them (r->fragments_ready). */
int lc_fragment_chains_p1(lc_renderer *r, const lc_frame_setup *fs, const lc_targets *t, int bands, lc_error *err);
/* P4 records what its sums and P5 need of its fragments, chained per pixel,
 * where the frame allows, and writes no target; both are then compute passes
 * over them: wanted before P4, begin before it (binds the list for
 * PROG_P4_LIST and a draw framebuffer of no attachment; the caller binds its
 * own after the draw), end after it (1: every fragment fit, else P4 draws again),
 * then lc_composite_list_p4 into the coefficient targets and
 * lc_composite_list_p5 into t (each cleared by the caller). */
int lc_composite_list_wanted(const lc_frame_setup *fs, int direct);
void lc_composite_list_begin(lc_renderer *r, const lc_frame_setup *fs);
int lc_composite_list_end(lc_renderer *r, const lc_frame_setup *fs);
/* The same for P4's list: 1 when P4 can record again in a list of what it counted. */
int lc_composite_list_retry(lc_renderer *r, const lc_frame_setup *fs);
/* P5 reads the coefficient targets `sums` that P4's walk wrote (and MPI
 * summed); with one process P5's walk makes them itself, writing `sums`, and
 * lc_composite_list_p4 does nothing (LUCENT_SUMS_IN_WALK=0: two walks). */
int lc_composite_list_p4(lc_renderer *r, const lc_frame_setup *fs, const lc_targets *t, lc_error *err);
int lc_composite_list_p5(lc_renderer *r, const lc_frame_setup *fs, const lc_targets *sums, const lc_targets *t,
                         lc_error *err);
/* Tests: caps P4's list, or P0's and P1's, at `entries` (0: as guessed), so
 * that a frame overflows it; once: only the next list made (the frame that
 * overflows it then records again in a list of what it counted). */
void lc_composite_list_limit(lc_renderer *r, uint64_t entries, int once);
void lc_fragment_list_limit(lc_renderer *r, uint64_t entries, int once);
/* Bytes the lists hold (lc_renderer_bytes). */
uint64_t lc_fragment_list_bytes(const lc_renderer *r);
/* Frees the list (lc_renderer_release_after, destroy). */
void lc_fragment_list_release(lc_renderer *r);
/* Chooses for the driver named gl_renderer (GL_RENDERER), process-wide:
 * lists on software rasterizers; LUCENT_FRAGMENT_LISTS=0/1 overrides. */
void lc_fragment_list_configure(const char *gl_renderer);
/* Whether this context's recording passes keep their chain heads through
 * framebuffer fetch (GL_EXT_shader_framebuffer_fetch; LUCENT_HEADS_FETCH=0: no). */
void lc_fragment_heads_configure(lc_renderer *r);
int lc_fragment_list_enabled(void);

/* ---- reduce.c (a no-op returning 0 without a reducer or with one process) */
/* Combines every texture of t over the processes (op; root_only as in lc_reducer). */
int lc_reduce_targets(lc_renderer *r, const lc_targets *t, lc_reduce_op op, int root_only, lc_frame_info *info,
                      lc_error *err);
/* MIN of the P2 element minima (count floats of element_alpha_min) into every process. */
int lc_reduce_element_minima(lc_renderer *r, uint32_t count, lc_frame_info *info, lc_error *err);
/* SUM of n counters into every process (through floats: exact below 2^24). */
/* Sums n floats over the processes, every process receiving the sums (color_equalize.c). */
int lc_reduce_sums(lc_renderer *r, float *values, size_t n, lc_frame_info *info, lc_error *err);
int lc_reduce_counts(lc_renderer *r, uint32_t *values, size_t n, lc_error *err);
/* Opaque context layers drawn from each process's shard (context.c): the
 * nearest depth over the processes into every process's depth[k] (w[k] x
 * h[k], k = 0, 1), and into color (depth[0]'s size) on process 0 the colour
 * of the process holding that nearest depth (the mean where several tie). */
int lc_reduce_context(lc_renderer *r, const GLuint depth[2], const int w[2], const int h[2], GLuint color,
                      lc_frame_info *info, lc_error *err);
/* LC_ERR_INVALID when the method cannot be combined over processes. */
int lc_reduce_check_method(const lc_renderer *r, lc_method method, lc_error *err);

/* ---- visibility.c */
/* Clears the mass histogram; the passes that know each pixel's total sum of
 * g^2 fill it (lc_mass_histogram_fourier, the exact opacity pass). */
void lc_mass_clear(lc_renderer *r);
/* Zeroes the occluder weights and importantOccluded's counts and binds them
 * for P2 or the exact opacity pass (occluders.glsl). */
void lc_occluders_clear(lc_renderer *r);
/* topDecileReach (docs/ALGORITHM.md §8) around the Fourier path's P5:
 * begin zeroes and binds the sums and sets r->reach_g from this frame's
 * visibility report (none: P5 counts nothing); a drawn P5 (drawn nonzero)
 * then draws into a framebuffer of the accumulation and the per-pixel sums,
 * which begin binds. end adds those up (drawn), reads the sums back into
 * fs->info (added over a frame's tiles) and leaves the accumulation bound. */
void lc_reach_begin(lc_renderer *r, const lc_frame_setup *fs, int drawn);
int lc_reach_end(lc_renderer *r, const lc_frame_setup *fs, lc_error *err);
/* The share of the w x h pixels of tex whose red channel is positive (the
 * mass histogram's count; method kanzler's coverage map). -1: GL error. */
double lc_covered_fraction(lc_renderer *r, GLuint tex, int w, int h, lc_error *err);
/* Counts the P1 zeroth coefficients of coef_low into the histogram. */
int lc_mass_histogram_fourier(lc_renderer *r, const lc_frame_setup *fs, lc_error *err);
/* Reads the histogram back into the mass fields of info. */
void lc_mass_report(lc_renderer *r, const lc_frame_setup *fs, lc_frame_info *info);
/* The median over covered pixels of P0's moments tex (w x h) of the
 * effective fragment count (sum g^2)^2 / sum g^4; 0 when nothing is covered,
 * -1 on error. */
double lc_moments_effective_median(lc_renderer *r, GLuint tex, int w, int h, lc_error *err);
/* Whether the opacity passes weigh a fragment's emphasis by its element's
 * importance instead of its own (docs/ALGORITHM.md §6, "Patches"): surfaces
 * under density normalization. */
int lc_element_emphasis(const lc_frame_setup *fs);
/* Binds BIND_ELEMENT_G for P2 or the exact opacity pass: the elements' mean
 * importance when lc_element_emphasis, else a dummy; sets u_element_emphasis. */
int lc_element_emphasis_bind(lc_renderer *r, const lc_frame_setup *fs, GLuint prog, lc_error *err);
/* The visibility report of info from the element opacities after P3 (alphas:
 * the state's copy, or NULL to read them back). */
int lc_visibility_measure(lc_renderer *r, const lc_frame_setup *fs, const float *alphas, lc_frame_info *info,
                          lc_error *err);

/* ---- clarity.c (params.clarity, docs/ALGORITHM.md §25) */
#define LC_CLARITY_MAX_STRENGTH 16.0 /* largest factor on λ (on q and r: its square) */
/* One optimization of the frame (frame.c's optimize_frame). */
typedef int (*lc_clarity_step)(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt,
                               lc_frame_info *info, int moments, lc_error *err);
/* How far the frame's report is from the goal at target (0: met). */
double lc_clarity_miss(double target, const lc_frame_info *info);
/* The strength after a frame measured at st, each factor moving by at most
 * max_step (q and r: its square). */
void lc_clarity_next(lc_clarity_strength *st, double target, const lc_frame_info *info, double max_step);
/* optimize under the loop (or once, as it is, when the loop is not active). */
int lc_clarity_optimize(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                        int moments, lc_clarity_step optimize, lc_error *err);

/* ---- baselines.c */
int lc_render_opaque(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
int lc_render_wboit(lc_renderer *r, lc_frame_setup *fs, lc_error *err);
/* Weighted average (Bavoil & Myers 2008) with the frame's opacities. */
int lc_render_weighted_average(lc_renderer *r, lc_frame_setup *fs, lc_error *err);

#endif
