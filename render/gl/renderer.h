/* The frame renderer: Fourier opacity optimization passes P1..P6 (docs/ALGORITHM.md)
 * and the reference/baseline methods, on one GL context, into RGBA8. */
#ifndef LC_RENDERER_H
#define LC_RENDERER_H

#include <stddef.h>
#include <stdint.h>

#include "camera.h"
#include "lc_base.h"
#include "lc_params.h"
#include "lc_work.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- GPU copy of a scene: vertex, attribute and element buffers.
 * Buffers are shared by every context created with lc_gl_desc.share, so one
 * lc_gpu_scene serves all render workers. Create and destroy with a context of
 * the share group current; the lc_scene must outlive it. After creation the
 * object is read-only and may be used from any worker thread. */
typedef struct lc_gpu_scene lc_gpu_scene;
/* Options of the GPU copy; zero = the compact layout (docs/MEMORY.md):
 * positions 16-bit unorm in chunks with their own bounds, directions in 32
 * bits, attributes 16-bit unorm over their range, colours RGBA8, element
 * blends without unused slots (none for points). */
typedef struct lc_gpu_scene_desc {
    int exact_positions; /* 1: float buffers as before the compact layout: images bit for bit */
} lc_gpu_scene_desc;
/* Bytes of a GPU copy by kind. */
typedef struct lc_gpu_memory {
    uint64_t positions;       /* positions (+ the chunk bounds of the compact layout) */
    uint64_t frames;          /* line tangents or surface normals */
    uint64_t attributes;      /* named attributes */
    uint64_t colors;          /* per-vertex RGB */
    uint64_t vertex_elements; /* vertex -> element blends */
    uint64_t indices;         /* index buffers */
    uint64_t adjacency;       /* element adjacency (smoothing) */
    uint64_t total;
} lc_gpu_memory;
/* lc_gpu_scene_create_ex with desc NULL (compact). */
int lc_gpu_scene_create(const lc_scene *scene, lc_gpu_scene **out, lc_error *err);
/* Uploads a finalized scene whose vertex arrays are still held (see
 * lc_scene_release_vertex_arrays); desc NULL = zero. */
int lc_gpu_scene_create_ex(const lc_scene *scene, const lc_gpu_scene_desc *desc, lc_gpu_scene **out, lc_error *err);
void lc_gpu_scene_destroy(lc_gpu_scene *gs);
uint64_t lc_gpu_scene_bytes(const lc_gpu_scene *gs);
void lc_gpu_scene_memory(const lc_gpu_scene *gs, lc_gpu_memory *out);
/* What lc_gpu_scene_create_ex(scene, desc) would allocate, without GL: for
 * `lucent info` and memory limits. Works on released scenes too. */
void lc_gpu_scene_estimate(const lc_scene *scene, const lc_gpu_scene_desc *desc, lc_gpu_memory *out);
/* Bytes per element that each renderer (render worker) holds for the largest
 * scene it has drawn: opacity buffers, smoothing ping-pong and the importance
 * cache and occluder weights of the visibility report. */
#define LC_RENDERER_BYTES_PER_ELEMENT 24u
/* Levels of detail (1 = full detail only) and the bytes of those beyond the
 * first (included in lc_gpu_scene_bytes). */
int lc_gpu_scene_levels(const lc_gpu_scene *gs);
/* Level i's simplification error (world units, 0 for level 0) and the
 * primitives it draws, i < lc_gpu_scene_levels(gs): what the cost model
 * needs to price the level a frame will pick. */
void lc_gpu_scene_level(const lc_gpu_scene *gs, int i, double *error, double *primitives);
uint64_t lc_gpu_scene_lod_bytes(const lc_gpu_scene *gs);

/* ---- One viewer's element opacities between frames (temporal fading).
 * Plain CPU memory, O(elements); not thread-safe: one frame at a time. */
typedef struct lc_frame_state lc_frame_state;
lc_frame_state *lc_frame_state_create(uint32_t element_count);
/* The same with 16-bit unorm opacities (2 bytes per element instead of 4; a
 * rounding of at most 1/131070 per frame, far below what 8-bit images show). */
lc_frame_state *lc_frame_state_create_compact(uint32_t element_count);
/* Bytes the state holds. */
uint64_t lc_frame_state_bytes(const lc_frame_state *st);
void lc_frame_state_destroy(lc_frame_state *st);
/* Forget the history: the next frame starts at its targets (no fade-in). */
void lc_frame_state_reset(lc_frame_state *st);
/* Current element opacities (count = element_count), for tests; NULL for a
 * compact state. */
const float *lc_frame_state_alphas(const lc_frame_state *st);
/* 1 until the state's first frame (or after a reset). */
int lc_frame_state_is_fresh(const lc_frame_state *st);
/* Takes element_count opacities as the history (a copy of another process's
 * state, docs/MPI.md); the state is no longer fresh. */
void lc_frame_state_load(lc_frame_state *st, const float *alpha);
/* Writes the element_count opacities as floats (either layout). */
void lc_frame_state_copy(const lc_frame_state *st, float *out);
/* color.equalize (docs/ALGORITHM.md §19): the session's transfer F, 257 knots
 * (render/image/equalize.h), moves toward target by DLS Eq. 10 (taken whole
 * when the state has none yet); _knots is NULL until the first equalized frame. */
void lc_frame_state_equalize(lc_frame_state *st, const float *target, double dt, double half_life);
const float *lc_frame_state_equalize_knots(const lc_frame_state *st);

/* ---- Per-frame report. */
typedef enum {
    LC_PASS_IMPORTANCE = 0, /* P1 (exact: fragment lists at optimization resolution) */
    LC_PASS_OPACITY,        /* P2 (exact: sort + exact sums + atomic-min) */
    LC_PASS_SMOOTH,         /* P3 smoothing and fading */
    LC_PASS_OPTICAL_DEPTH,  /* P4 (exact: fragment lists at full resolution) */
    LC_PASS_ACCUMULATE,     /* P5 (exact: sort + front-to-back blend) */
    LC_PASS_RESOLVE,        /* P6 */
    LC_PASS_READBACK,       /* RGBA readback */
    LC_PASS_DEPTH_RANGE, /* P0, depthRange "pixel" or "moments" only: per-pixel depth ranges or moments (runs first) */
    LC_PASS_COUNT
} lc_pass;
/* JSON-friendly pass names: "importance", "opacity", "smooth", "opticalDepth",
 * "accumulate", "resolve", "readback", "depthRange". */
const char *lc_pass_name(int pass);

/* ---- The pass plan: which passes a frame runs and at which resolution,
 * worked out once from the request. The frame's dispatch and its timer table
 * (frame.c) and the daemon's cost model (server/daemon/cost.c) all read it, so
 * that what runs, what is timed and what is charged cannot disagree. */
typedef enum {
    LC_RUN_NONE = 0, /* the pass does not run */
    LC_RUN_ONCE,     /* it runs once, at no image resolution (P3, on the elements) */
    LC_RUN_LOW,      /* at the optimization resolution (params.resolutionScale) */
    LC_RUN_FULL,     /* at the output resolution */
    LC_RUN_BOTH      /* at both (P0's per-pixel range) */
} lc_pass_run;
typedef struct lc_pass_plan {
    lc_method method;
    int reuse;        /* P1-P3 skipped: the frame state's opacities are reused */
    int pixel_range;  /* P0 as the per-pixel depth range (depthRange "pixel") */
    int moments;      /* P0 as the depth moments (depthRange "moments") */
    int kanzler_maps; /* P0 includes method kanzler's per-pixel maps (full resolution) */
    lc_pass_run run[LC_PASS_COUNT];
} lc_pass_plan;
/* The plan of a frame of p. reuse: the caller holds a frame state with
 * opacities to reuse (a frame without one, or the cost model's estimate of a
 * full frame, passes 0); it counts only where p asks for it and the method
 * has element opacities to reuse (fourier, wboit). */
void lc_pass_plan_make(const lc_render_params *p, int reuse, lc_pass_plan *out);
/* Tiled stills: the tiles (nx across, ny down) a frame of p composites in
 * with tile_size (0 = LC_TILE_SIZE, used only above LC_TILE_PIXELS pixels; a
 * renderer's forced lc_renderer_desc.tile_size tiles any larger frame);
 * returns nx * ny, or 0 when the frame is one tile. */
int lc_pass_plan_tiles(const lc_render_params *p, int tile_size, int *nx, int *ny);
/* Whether P1 and P2 may run over recorded fragments instead of drawing
 * (fragment_list.c: on software rasterizers, chosen process-wide when the
 * first renderer is created), for the cost model; configure sets it for the
 * driver named gl_renderer (LUCENT_FRAGMENT_LISTS=0/1 overrides). */
int lc_fragment_list_enabled(void);
void lc_fragment_list_configure(const char *gl_renderer);
/* Whether a Fourier frame of `fragments` full-resolution fragments (one
 * traversal's, no stride, layer or tile) sums P4 and P5 over the fragments
 * its P4 records instead of drawing P5, for the cost model. */
int lc_composite_list_expected(double fragments);
/* The nodes of the exact method's pool on this process's device (the
 * configured size clamped to the driver's largest storage block), for the
 * cost model: a list pass of more fragments runs in bands of rows (exact.c).
 * A renderer's creation configures it; 0 (none yet): no bands charged. */
uint64_t lc_exact_pool_nodes(void);
void lc_exact_pool_configure(uint64_t nodes);
/* The bands of rows a list pass of `fragments` takes with a pool of `nodes`
 * (1: the whole frame at once), as exact.c sizes them from the mean. */
int lc_exact_bands(double fragments, uint64_t nodes);
/* Whether the full-resolution list pass of a frame foretold to offer
 * `fragments` starts in bands without building the whole frame first. */
int lc_exact_foretold(double fragments, uint64_t nodes);

#define LC_CONVERGED_EPSILON 1e-3 /* max |delta alpha| under which fading counts as done */
/* importantOccluded (docs/ALGORITHM.md §8): a fragment is important above
 * this g, and hidden by importance when the mass of g^2 in front reaches
 * that of one fragment at the threshold; occluders.glsl uses the same. */
#define LC_IMPORTANT_G 0.8
#define LC_IMPORTANT_MASS 0.64

/* params.clarity (render/gl/clarity.c): a one-shot frame tries up to this
 * many strengths (P1-P3 each); the cost model charges LC_CLARITY_CHARGED_TRIES
 * (most data meet the goal at the first). */
#define LC_CLARITY_ITERATIONS 6
/* Tries that only halve params.smoothing (clarity.c), besides those: the
 * last of them takes it to none. */
#define LC_CLARITY_SMOOTHING_STEPS 4
#define LC_CLARITY_CHARGED_TRIES 2
/* Lines' element emphasis beyond the paper's strength (docs/ALGORITHM.md
 * §25, render/gl/visibility.c): each of the n element importances g (in
 * [0, 1]) as its rank above the median, max(0, 2 rank - 1), rank its mid-rank
 * in [0, 1]; malloc'ed, NULL when out of memory. */
float *lc_emphasis_ranks(const float *g, uint32_t n);
/* Whether the loop runs for p: clarity > 0, normalize auto, no explicit q/r/λ,
 * a method whose opacities are optimized (fourier, wboit; exact on its lists). */
int lc_clarity_active(const lc_render_params *p);
/* params.clarity's strength: factors on λ and on q and r, each >= 1. */
typedef struct lc_clarity_strength {
    double lambda, penalty;
    int stalled; /* a step did not bring the goal nearer: no more steps until the state resets */
    double miss; /* how far the last frame was from the goal (lc_clarity_miss; -1: none yet) */
    /* Factor on params.smoothing's iterations (1: as given; clarity.c halves
     * it while smoothing is what keeps the frame from the goal). */
    double smoothing;
} lc_clarity_strength;

typedef struct lc_frame_info {
    int width, height;
    double pass_ms[LC_PASS_COUNT]; /* GPU time per pass (timer queries); -1 = pass not run */
    /* Vertices of the data's geometry each pass's draws issued (a ribbon
     * segment pulled is 6, in a strip about 2; a sprite 1): what it set up,
     * counted at the draw calls; 0 for a pass that draws no geometry (computed
     * over lists or by the compute rasterizer, full-screen passes). */
    uint64_t pass_vertices[LC_PASS_COUNT];
    double gpu_ms;           /* sum of the passes */
    double wall_ms;          /* CPU wall time of lc_render_frame */
    uint64_t pipeline_bytes; /* GPU memory the method's targets/buffers hold */
    lc_camera camera;        /* the camera used (fitted when the request had none) */
    uint32_t element_count;
    /* Detail drawn (params.detail): the level of detail (0 = every segment)
     * and the primitives of a pass, the point stride, and whether P1-P3 were
     * skipped for the state's opacities. */
    int lod_level;
    uint64_t primitives_drawn;
    int point_stride;
    uint32_t kept_points;           /* with a stride: the important points drawn in full (point_subset.c) */
    int line_stride;                /* lines: one in n of the less important lines (line_subset.c); 1 = all */
    int point_sprites;              /* points drew as GL point sprites, not quads (lc_frame_point_sprites) */
    uint64_t kept_line_segments[2]; /* with a line stride: segments of the full and of the strided lines */
    int reused_opacities;
    double max_alpha_change; /* max |delta| of element opacities this frame */
    int converged;           /* max_alpha_change, or what is left to fade, < LC_CONVERGED_EPSILON */
    /* Density normalization (params.normalize; methods with element opacities): */
    double mass_median, mass_p95; /* per-pixel sum of g^2 over covered pixels (optimization resolution) */
    double covered_fraction;      /* covered pixels / pixels, at the optimization resolution */
    /* Visibility report over the elements that reach a pixel this frame (an
     * element's importance = mean of its vertices'); has_visibility = 0 for
     * methods without element opacities (opaque, direct). */
    int has_visibility;
    uint32_t visible_elements;
    double top_decile_alpha;  /* mean opacity of the 10% most important */
    double bottom_half_alpha; /* mean opacity of the least important half */
    /* Mean opacity of the least important half, each element weighted by the
     * importance mass behind its fragments (0 when they hide nothing). */
    double occluder_alpha;
    /* Share of the important fragments (g > LC_IMPORTANT_G) that have at
     * least LC_IMPORTANT_MASS of importance mass in front (docs/ALGORITHM.md
     * §8), at the optimization resolution; 0 when there are none. */
    double important_occluded;
    uint64_t important_fragments; /* the share's denominator */
    /* topDecileReach (docs/ALGORITHM.md §8): the top decile's share of the
     * importance the final composite shows (sum of g alpha T, T the
     * transmittance in front) over its share of the importance drawn (sum of
     * g alpha); below 1 hidden behind the rest, above 1 in front of it.
     * has_reach 0 where not measured (methods other than fourier).
     * top_decile_g: the lowest importance counted as the top decile's (its
     * lowest bin); reach_sums: all g w, all g alpha, top g w, top g alpha,
     * added over a frame's tiles. */
    int has_reach;
    double top_decile_reach, top_decile_g, reach_sums[4];
    /* The same three opacities over P2's targets before P3's smoothing (the
     * clarity loop weighs what smoothing cost the goal; clarity.c). */
    double raw_top_decile_alpha, raw_bottom_half_alpha, raw_occluder_alpha;
    /* Layered frames: the same report for each layer (the totals above are
     * over the transparent layers' elements together; a context layer, drawn
     * opaque, has visible_elements 0). */
    int layer_count;
    struct {
        uint32_t visible_elements;
        double top_decile_alpha, bottom_half_alpha, occluder_alpha;
    } layers[LC_MAX_LAYERS];
    /* Exact method only (0 otherwise): */
    uint64_t fragments;         /* fragments rasterized at full resolution (stored + dropped) */
    uint64_t dropped_fragments; /* fragments lost: the node pool was full, or a loop budget cut their list */
    uint64_t reduced_fragments; /* of fragments: left out below 1/255 opacity (M3D §2.4.1), not stored */
    uint64_t cut_lists;         /* lists a sort pass left unfinished: at its loop budget, or stopped by the
                                   driver's loop limit (exact.c) */
    double mean_layers;         /* mean fragments per covered pixel */
    uint32_t max_layers;
    int exact_bands; /* bands of rows the full-resolution list pass took (1: the whole frame at once) */
    /* With a reducer (lc_renderer_desc.reducer): time spent combining the
     * passes' targets across processes, and the bytes each process sent. */
    double reduce_ms;
    uint64_t reduce_bytes;
    int reductions;
    int tiles; /* tiles the frame was composited in (0: one frame; frame.c "Tiled stills") */
    /* params.clarity: the factors on λ and on q and r the frame's opacities
     * used (0: the loop was off; render/gl/clarity.c). */
    double clarity_lambda, clarity_penalty;
    int clarity_smoothing;     /* the smoothing iterations the frame's opacities used (params.smoothing, or fewer) */
    int clarity_smoothing_cut; /* the loop used fewer than params.smoothing (clarity.c) */
    int clarity_tries;         /* optimizations the loop ran this frame (1 for a session's frame; 0 when off) */
    int clarity_reached;       /* the frame met params.clarity's goal (lc_clarity_miss 0); else the factors are where it
                                  stopped */
    int importance_passes;     /* P1 draws this frame: 1 however many tries (their strength leaves P1's sums alone) */
    int opacity_from_list;     /* P2 ran over P1's fragment list (a compute pass), not as a draw (fragment_list.c) */
    int importance_from_list;  /* P1 ran over P0's fragments (a compute pass), not as a draw (fragment_list.c) */
    int composite_from_list;   /* P4's sums and P5 ran over P4's recorded fragments (compute passes; fragment_list.c) */
    int composite_walks;       /* the frame's walks over those fragments: 1 a compositing run where P5's walk
                                  makes P4's sums too, else 2 (style.antialias runs one per sample) */
    int computed_passes;       /* bit lc_raster_pass: P4 / P5 ran through the compute rasterizer (compute_raster.c) */
    int line_primitive;        /* the segments drew as wide line strips, not ribbons (line_primitive.c) */
    /* lines.clusters (line_clusters.c): whether this frame built the dendrogram
     * (else it reused the scene's), and the time spent building and cutting. */
    int clusters_built;
    double clusters_ms;
    /* color.equalize: the data values at 0, 1/4, 1/2, 3/4 and 1 of the
     * colormap's bar under the transfer this frame drew with (F^-1 through
     * color.range); has_color_ticks = 0 without equalization or with color.curve. */
    int has_color_ticks;
    double color_ticks[5];
    /* method surface-layers (server/daemon/pool/surface_job.c; 0 otherwise):
     * curves traced, the layers a pixel kept (K), layers per covered pixel,
     * the most in one pixel, fragments dropped beyond K, tracing time. */
    int has_surface;
    uint64_t surface_curves, surface_overflow;
    int surface_k;
    uint32_t surface_max_layers;
    double surface_mean_layers, surface_trace_ms;
    /* This frame's work on the layers: curves drawn and fragments rasterized
     * (only the new curves when surface_kept: the layers of the frame before
     * were kept), the measure of PRT's progressive insertion. */
    uint64_t surface_drawn_curves, surface_drawn_fragments;
    int surface_kept;
    /* params.autoSubset: the stride P1 drew with (1: every primitive) and the
     * median effective fragment count per covered pixel that P0 measured to
     * choose it ((sum g^2)^2 / sum g^4; 0 when the rule did not run). */
    int p1_subset;
    double p0_fragments_median;
    /* params.progressive: the batch this frame added (1 .. n) and n; 0 and 0
     * for a frame of every primitive. The last batch's image is the one-shot
     * frame's (render/gl/progressive.c). A call that ran every batch (batch
     * 0) reports the last and, in first_batch_ms, the wall time until the
     * first batch's picture was read back (wall_ms: until the last's). */
    int batch, batches;
    double first_batch_ms;
} lc_frame_info;

/* ---- Reduction hook: renders one image from a dataset split over several
 * processes (docs/MPI.md). Every Fourier sum is order-independent, so shards
 * rendered separately combine by adding their targets: after P0 the per-pixel
 * depth ranges (MIN), after P1 the importance coefficients (SUM into every
 * process), after P2 the element minima (MIN), after P4 the optical-depth
 * coefficients (SUM) and after P5 the colour/weight sums (SUM into rank 0,
 * whose image is the result). The renderer knows nothing of how the values
 * travel (MPI in server/mpi); every process must render the same frames with
 * the same parameters, so each call is collective.
 * Threading: called on the render thread during lc_render_frame. */
typedef enum { LC_REDUCE_SUM = 0, LC_REDUCE_MIN } lc_reduce_op;
typedef struct lc_reducer {
    void *ctx;
    int rank, size; /* this process and the process count; rank 0 gets the image */
    /* Combines the n floats of values element-wise over every process, in
     * place: into every process (root_only 0) or into rank 0 only (root_only
     * 1: the other processes' values are unspecified afterwards). Returns 0,
     * or a negative status with err filled. */
    int (*reduce)(void *ctx, float *values, size_t n, lc_reduce_op op, int root_only, lc_error *err);
} lc_reducer;

/* ---- Renderer: programs and render targets of one GL context. */
typedef struct lc_renderer lc_renderer;
typedef struct lc_renderer_desc {
    uint64_t exact_pool_bytes; /* node pool of the exact method; 0 = 256 MiB */
    int no_timer_queries;      /* 1 = skip GPU timer queries */
    /* NULL = one process. Otherwise the scene holds this process's shard
     * (lc_scene_shard) and only the fourier and direct methods are allowed.
     * Borrowed: must outlive the renderer. */
    const lc_reducer *reducer;
    /* Tiled stills (frame.c): frames of more than LC_TILE_PIXELS pixels
     * composite in tiles of at most tile_size^2 pixels; 0 = LC_TILE_SIZE.
     * A smaller value forces small frames into tiles (tests). */
    int tile_size;
    /* Pass progress (NULL = none), for a viewer waiting on a long frame: called
     * on the render thread when a frame's passes begin (done = 0) and after
     * each pass of its plan (lc_pass_plan order: P0, P1..P6, readback) with the
     * passes done, the passes planned and the pass that runs next (-1 once the
     * readback is done). Once a frame has run LC_PROGRESS_SYNC_MS, each report
     * waits for its pass to finish on the GPU (glFinish), so that a slow frame
     * reports what has run rather than what was queued; images do not change. */
    void (*progress)(void *ctx, int next_pass, int done, int planned);
    void *progress_ctx;
    /* Yield points (NULL = none; docs/ARCHITECTURE.md "Yielding"): called on
     * the render thread between passes (after P0, P1, P2, the optimization,
     * P4 and P5) and between the tiles of a tiled composite, each time after
     * the work so far has finished on the GPU once the frame has run
     * LC_PROGRESS_SYNC_MS. It may block, to leave the CPU/GPU to other work.
     * Nonzero ends the frame there: lc_render_frame returns LC_ERR_CANCELLED
     * and writes no image; the renderer and a frame state stay usable (the
     * state keeps the opacities of the last P3 that ran, as after a frame).
     * Not called with a reducer of more than one process (collective frames). */
    int (*yield)(void *ctx);
    void *yield_ctx;
    /* Pre-emption inside a pass (NULL = none): called with yield_ctx between
     * the batches of a draw of P0, P1, P2, P4 and P5 on a software rasterizer
     * (pipeline.c) and between the dispatches of a computed P4 or P5
     * (compute_raster.c), where a pass of a large still can take seconds. It must
     * not block. Nonzero ends the draw; the frame ends at its next yield
     * point as if desc.yield had said so there. */
    int (*preempted)(void *ctx);
} lc_renderer_desc;
#define LC_PROGRESS_SYNC_MS 100.0

/* Frames above LC_TILE_PIXELS pixels composite (P4-P6) tile by tile, each at
 * most LC_TILE_SIZE^2, after one optimization (P0-P3) of the whole view. */
#define LC_TILE_SIZE 2048
#define LC_TILE_PIXELS (4096LL * 4096LL)

/* Creates a renderer for the current context (compiles shaders). Errors carry
 * the shader info log. Thread: the thread that holds the context. */
int lc_renderer_create(const lc_renderer_desc *desc, lc_renderer **out, lc_error *err);
void lc_renderer_destroy(lc_renderer *r);

/* Renders one frame of gs with params into rgba (width*height*4 bytes, rows
 * top to bottom). state holds the viewer's opacities: NULL renders one-shot
 * (targets used directly); otherwise opacities fade toward this frame's
 * targets over dt seconds (the first frame of a state starts at its targets).
 * info may be NULL. Render targets grow to the largest size seen and stay
 * allocated. Errors: LC_ERR_INVALID (bad params, e.g. unknown attribute), LC_ERR_GL. */
int lc_render_frame(lc_renderer *r, const lc_gpu_scene *gs, const lc_render_params *params, lc_frame_state *state,
                    double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err);

/* A frame of n layers (1..LC_MAX_LAYERS; docs/ALGORITHM.md "Layers"):
 * layers[i] draws scenes[i] with its own mapping and style, params gives the
 * rest. The layers share the optimization (one G(d), one tau(d)); the
 * camera fits the union of their bounds; element ids of layer i follow those
 * of layers 0..i-1, so state holds the sum of their element counts. Methods
 * fourier, exact and direct; not with filters, line clusters, color.equalize
 * or a guard band (each refused naming its field). With a reducer the scenes
 * are this process's shards: transparent layers add into the combined targets
 * as one dataset's shards do, and the context layers' nearest depth and
 * colour are combined over the processes. Errors of a
 * layer's mapping name "layers[i].importance.attribute" and so on. */
int lc_render_layers(lc_renderer *r, const lc_gpu_scene *const *scenes, const lc_layer_params *layers, int n,
                     const lc_render_params *params, lc_frame_state *state, double dt, uint8_t *rgba,
                     lc_frame_info *info, lc_error *err);
/* The camera of a frame whose params have none (has_camera false), as
 * lc_render_frame (n = 1) and lc_render_layers (the n layers' scenes) choose
 * it: the first scene's suggested view, else -Z with +Y up, fitted to the
 * union of the scenes' bounds; cam's view angle, else 30 degrees. A movie's
 * path starts from it. */
void lc_render_fit_camera(const lc_gpu_scene *const *scenes, int n, lc_camera *cam);

/* The last frame's summed targets, for tests: which 0 = P1's importance
 * coefficients (optimization resolution), 1 = P0's depth moments. Copies
 * min(n, available) floats (RGBA texels, target by target, rows bottom-up)
 * into out; returns the floats available, 0 when the frame had none. */
size_t lc_renderer_read_targets(lc_renderer *r, int which, float *out, size_t n);

/* Sets the reduction hook after creation (same contract as the desc field). */
void lc_renderer_set_reducer(lc_renderer *r, const lc_reducer *reducer);
/* The work budget of the frames that follow (NULL = none; borrowed until
 * set again; lc_work.h): every yield point and every batch where a draw may
 * yield charges the time elapsed (lc_work_charge_elapsed); once exceeded the
 * frame ends at its next yield point with LC_ERR_BUDGET naming the budget's
 * field, as a pre-empted frame ends (no image; the renderer stays usable).
 * Checked with a reducer of one process only, as yield points are. */
void lc_renderer_set_work(lc_renderer *r, lc_work_budget *work);
/* Sets desc.tile_size for the frames that follow (0 = the default rule), e.g.
 * to give a large frame a yield point every tile. */
void lc_renderer_set_tile_size(lc_renderer *r, int tile_size);

/* What the geometry passes (P0, P1, P2, P4, P5 and the baselines' passes) run,
 * for `lucent bench --floor` (docs/EVALUATION.md, "The geometry path"):
 * everything (the default), the same vertex shader and coverage with a
 * fragment shader that returns right after its coverage test, its outputs
 * unwritten (the cost of vertex shading, set-up, binning, rasterization and
 * blending), or nothing
 * after the vertex shader (GL_RASTERIZER_DISCARD: vertex shading, primitive
 * assembly and clipping). Images are meaningless outside LC_FLOOR_FULL. */
/* LC_FLOOR_COMPUTE: P4 and P5 through the compute rasterizer wherever it
 * applies, whatever the device's rule (images as meaningful as FULL's). */
typedef enum {
    LC_FLOOR_FULL = 0,
    LC_FLOOR_EMPTY_SHADER,
    LC_FLOOR_NO_RASTER,
    LC_FLOOR_COMPUTE,
    LC_FLOOR_COUNT
} lc_floor_mode;
void lc_renderer_set_floor(lc_renderer *r, lc_floor_mode mode);
/* Whether geometry programs compile the frame's branch values in (1, the
 * default; LUCENT_SPECIALIZE=0 turns it off in every renderer): the images are
 * the same either way (docs/ALGORITHM.md "Specialized programs"). */
void lc_renderer_set_specialize(lc_renderer *r, int on);
const char *lc_floor_mode_name(lc_floor_mode mode);

/* The additive passes that may run as compute passes instead of drawn
 * (docs/ALGORITHM.md "Compute rasterization"). */
typedef enum { LC_RASTER_P4 = 0, LC_RASTER_P5, LC_RASTER_PASSES } lc_raster_pass;
/* The path pass takes for primitives of type prim on the device whose
 * GL_RENDERER string is gl_renderer, LUCENT_COMPUTE_RASTER (0 drawn, 1 compute)
 * included: "compute" or "drawn" (lucent bench, the health endpoint). A frame
 * where the compute rasterizer does not apply draws (compute_raster.c). No GL
 * calls; any thread. */
const char *lc_raster_path_name(const char *gl_renderer, lc_raster_pass pass, lc_prim_type prim);
/* Forces the path of P4 and P5 for the frames that follow: 0 drawn, 1 computed
 * where the compute rasterizer applies, -1 the device's rule (the default). */
void lc_renderer_set_raster_path(lc_renderer *r, int path);
/* The form line segments draw in, LUCENT_LINE_PRIMITIVE (0 ribbons, 1 lines)
 * included: "lines" (wide line strips, one primitive a segment, where a frame
 * draws every segment of one dataset and its ribbons are no wider than the
 * device's lines) or "ribbons" (triangle strips, two triangles a segment).
 * No GL calls; any thread. */
const char *lc_line_path_name(void);
/* Forces the form of the frames that follow: 0 ribbons, 1 lines where they
 * fit, -1 the device's rule (the default). */
void lc_renderer_set_line_path(lc_renderer *r, int path);
/* The widest line the device draws (GL_ALIASED_LINE_WIDTH_RANGE), pixels. */
float lc_renderer_line_width_max(const lc_renderer *r);
/* Whether the passes that record their fragments (P0, P4 on software
 * rasterizers) keep each pixel's chain head through framebuffer fetch
 * (GL_EXT_shader_framebuffer_fetch; LUCENT_HEADS_FETCH=0: no) rather than an
 * atomic exchange. */
bool lc_renderer_heads_fetch(const lc_renderer *r);

/* After a frame of params p above LC_LARGE_FRAME_PIXELS (a 4096^2 still; no
 * stream frame is that large): renders p once more at 8x8 (so that the
 * driver lets go of the large frame's state), frees every render target (the
 * next frame allocates its own size again) and trims the heap, so that one
 * large render does not pin its memory for the life of the process. Smaller
 * frames keep their targets. Not under MPI (the 8x8 frame is not collective).
 * Thread: the thread that holds the context. */
#define LC_LARGE_FRAME_PIXELS (2048LL * 2048LL)
void lc_renderer_release_after(lc_renderer *r, const lc_gpu_scene *gs, const lc_render_params *p);
/* The last color.equalize frame's visibility-weighted colour histogram H_b
 * (256 bins over the colormap coordinate, in pixels: sum = sum (1 - T)) and
 * the transfer it drew with (257 knots); either may be NULL. -1: none yet. */
int lc_renderer_color_histogram(const lc_renderer *r, double *hist, float *knots);
/* The exact method's last equalized frame: the sum over pixels of 1 - T
 * (each pixel's rounded once to 2^-20) and the part of it that halo fragments
 * cover (left out of the histogram, so sum H_b + halo = cover exactly).
 * -1: no such frame (other methods do not measure it). */
int lc_renderer_color_coverage(const lc_renderer *r, double *cover, double *halo);
/* The last method "kanzler" frame's per-pixel maps (docs/ALGORITHM.md §28),
 * for tests and debugging: width x height x 4 floats (C, M, D, V) in GL's
 * row order (bottom row first). -1: no such frame at that size. Renderer thread. */
int lc_kanzler_read_maps(lc_renderer *r, float *out, int width, int height);

/* GPU memory currently held by the renderer's targets and buffers. */
uint64_t lc_renderer_bytes(const lc_renderer *r);
/* Of that and its CPU caches: what grows with the element count. */
uint64_t lc_renderer_element_bytes(const lc_renderer *r);

#ifdef __cplusplus
}
#endif
#endif
