/* Command-line subcommands of `lucent` (render, info, gen, bench, compare) and
 * the helpers they share: dataset specs, request files, a GL renderer. */
#ifndef LC_CLI_H
#define LC_CLI_H

#include "gl_context.h"
#include "lc_options.h"
#include "renderer.h"
#include "request.h"
#include "scene.h"

/* Opens a dataset spec: "demo:NAME" with optional "?count=N&seed=S" (e.g.
 * "demo:points?count=2000000"), or a file path (LC_DATASET_EXTENSIONS). The scene is finalized;
 * the caller destroys it. */
int lc_cli_open_dataset(const char *spec, lc_scene **out, lc_error *err);

/* Reads and parses a render request file (CLI limits: up to 16384 px a side) into
 * req, a request whose layers it releases first. */
int lc_cli_read_request(const char *path, lc_request *req, lc_error *err);

/* A headless context with a renderer, current on the calling thread. */
typedef struct lc_cli_gl {
    lc_gl *gl;
    lc_renderer *renderer;
} lc_cli_gl;

int lc_cli_gl_open(int device, lc_cli_gl *out, lc_error *err);
void lc_cli_gl_close(lc_cli_gl *g);

/* Options every rendering subcommand takes besides the request's own fields. */
typedef struct lc_cli_common {
    lc_request *req;               /* the request the field flags (--q, --width, ...) set */
    const char *request;           /* --request FILE (read before the other flags) */
    const char *input;             /* --input FILE|demo:NAME (overrides the request's dataset) */
    int device;                    /* --device N, -1 = LUCENT_EGL_DEVICE or the first GPU */
    long long elements;            /* --elements N: line elements or surface patches, 0 = derived from the data */
    int exact_positions;           /* --exact-positions: float GPU buffers and session opacities */
    int unlit;                     /* --unlit: no shading */
    int width_set, height_set;     /* a flag gave the width, the height (--width, --height, --size) */
    int dataset_set;               /* --dataset was given */
    unsigned long long max_memory; /* --max-memory BYTES: refuse larger datasets; 0 = no limit */
} lc_cli_common;

/* A rendering subcommand's arguments: defaults, the --request file (if any),
 * then its own table (own, into own_target) and the shared flags (the
 * request's fields, dataset, device, memory) in order, strictly. Returns 0 to
 * go on, 1 when --help printed usage() (exit 0), 2 on a bad flag (message
 * printed: exit 2). */
int lc_cli_parse(const char *cmd, const lc_option *own, void *own_target, int argc, char **argv, lc_request *req,
                 lc_cli_common *common, void (*usage)(FILE *f, const lc_opt_set *sets, int nsets));

/* True if argv holds flag (e.g. "--request"). */
int lc_cli_has_flag(int argc, char **argv, const char *flag);

/* Runs a subcommand's body on a default request it owns, releasing the
 * request (its layers' reference) whatever the body returns. */
int lc_cli_with_request(int argc, char **argv, int (*body)(int argc, char **argv, lc_request *req));

/* Opens the dataset (common->input, else the request's, else demo:tornado) and
 * a GL renderer. Prints "lucent CMD: reason" and returns non-zero on error;
 * on success the caller destroys *scene and closes g. */
/* The dataset a command works on: --dataset/--input, the request's, or demo:tornado. */
const char *lc_cli_dataset_spec(const lc_request *req, const lc_cli_common *common);
int lc_cli_open(const char *cmd, const lc_request *req, const lc_cli_common *common, lc_scene **scene, lc_cli_gl *g);

/* Uploads scene in the layout common asks for (compact, or exact with
 * --exact-positions) after checking --max-memory, then releases the scene's
 * CPU vertex arrays the GPU copy now holds. Prints "lucent CMD: reason" and
 * returns non-zero on error. */
int lc_cli_upload(const char *cmd, const lc_cli_common *common, lc_scene *scene, lc_gpu_scene **gs);
/* A viewer's frame state: 16-bit opacities, or floats with --exact-positions. */
lc_frame_state *lc_cli_frame_state(const lc_cli_common *common, uint32_t element_count);
/* Current resident memory of the process in bytes (/proc/self/statm), 0 if unknown. */
uint64_t lc_cli_resident_bytes(void);
/* Prints the bytes per vertex of scene by kind: CPU arrays, GPU buffers (gs,
 * or the estimate of the layout common asks for when gs is NULL), per-element
 * state of one renderer and one session. */
void lc_cli_print_memory(const lc_scene *scene, const lc_gpu_scene *gs, const lc_cli_common *common);

/* The scene a command renders (cli_scene.c): one dataset, or the datasets of
 * the request's layers[] (docs/ALGORITHM.md §24), each a spec as --input
 * takes (demo:NAME[?count=N&seed=S] or a file), drawn in one frame as POST
 * /api/v1/render draws them. */
typedef struct lc_cli_scene {
    int layer_count;                  /* lc_request_layer_count(req); 0: one dataset, scenes[0] */
    int count;                        /* scenes held: 1, or layer_count once open */
    lc_scene *scenes[LC_MAX_LAYERS];  /* finalized; their vertex arrays released after the upload */
    lc_gpu_scene *gpu[LC_MAX_LAYERS]; /* their GPU copies */
    const lc_layer_params *layers;    /* req->layers->p: the request's snapshot, which outlives the scene */
} lc_cli_scene;

/* Opens req's scene and a GL renderer, and uploads the scene in the layout
 * common asks for. Without layers: lc_cli_open and lc_cli_upload. With
 * layers: every layer's dataset (--elements applied to each, --max-memory to
 * their sum); an unknown one names layers[i].dataset; --input and --dataset
 * are refused (the layers name their datasets). Prints "lucent CMD: reason"
 * and returns non-zero on error; on success the caller closes both. */
int lc_cli_scene_open(const char *cmd, const lc_request *req, const lc_cli_common *common, lc_cli_scene *out,
                      lc_cli_gl *g);
/* One frame of the scene: lc_render_frame of the dataset, or lc_render_layers
 * of the layers (state then spans the sum of their element counts). */
int lc_cli_scene_render(lc_renderer *r, const lc_cli_scene *s, const lc_render_params *p, lc_frame_state *state,
                        double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err);
/* The elements (a frame state's size) and primitives of every scene together. */
uint64_t lc_cli_scene_elements(const lc_cli_scene *s);
uint64_t lc_cli_scene_primitives(const lc_cli_scene *s);
/* "demo:points + demo:tornado": the scenes' names, in buf. */
const char *lc_cli_scene_name(const lc_cli_scene *s, char *buf, size_t cap);
/* The camera a frame of the scene without a camera gets (lc_render_fit_camera):
 * where a movie's path starts. */
void lc_cli_scene_camera(const lc_cli_scene *s, lc_camera *cam);
/* Destroys the GPU copies (g current), closes g, destroys the scenes. */
void lc_cli_scene_close(lc_cli_scene *s, lc_cli_gl *g);

/* Prints the per-pass timings of a frame as "  importance   1.23 ms" lines. */
void lc_cli_print_timings(const lc_frame_info *info);

int lc_cli_render(int argc, char **argv);
int lc_cli_info(int argc, char **argv);
int lc_cli_gen(int argc, char **argv);
/* `lucent gen FIELD`'s tracing flags: step and length 0 = the tracer's
 * defaults; seeding NULL = the curves of --seed-line. */
typedef struct lc_cli_streamlines {
    uint32_t curves;       /* --count */
    double step, length;   /* --step (negative: backward), --length */
    const char *seeding;   /* --seeding points|rake|box|density */
    const char *seeds;     /* --seeds: the points, or a rake's ends / a box's corners */
    const char *direction; /* --direction forward|backward|both; NULL = forward */
    double separation;     /* --separation: density seeding's d_sep; 0 = default */
} lc_cli_streamlines;
/* The curves particles seeded along seed_text ("x,y,z;x,y,z...") or, with
 * sl->seeding, a streamline set (render/field/seeding.h), trace through the
 * field spec (lc_field_open), as a finalized line scene with attributes
 * time, speed, seed_u and normal_x/y/z (cli_trace.c). */
int lc_cli_trace_scene(const char *spec, const char *seed_text, const lc_cli_streamlines *sl, lc_scene **out,
                       lc_error *err);
/* `lucent gen FIELD --seed-line ... --mesh`: the meshed reference of the
 * surface (render/field/stream_mesh.h) as a triangle scene; split 0 = the
 * default insertion distance. */
int lc_cli_mesh_scene(const char *spec, const char *seed_text, double split, double step, double length, lc_scene **out,
                      lc_error *err);
int lc_cli_bench(int argc, char **argv);
int lc_cli_compare(int argc, char **argv);
int lc_cli_schema(int argc, char **argv);
/* `lucent movie MOVIE.json -o OUT`: a movie request rendered and encoded offline. */
int lc_cli_movie(int argc, char **argv);
/* `lucent ssim A B`: SSIM and RMSE of two image files. */
int lc_cli_ssim(int argc, char **argv);

#endif
