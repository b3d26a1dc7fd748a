/* Dataset registry of the daemon: scenes loaded before the port opens, their
 * GPU copies (shared by every render context) and their JSON descriptions. */
#ifndef LC_SERVER_DATASETS_H
#define LC_SERVER_DATASETS_H

#include <jansson.h>
#include <stdint.h>

#include "fields.h"
#include "lc_base.h"
#include "memory.h"
#include "renderer.h"
#include "scene.h"
#include "scene_measure.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One loaded dataset. Immutable after lc_datasets_upload(); pointers stay valid
 * until lc_datasets_destroy(), which runs after every thread has stopped. */
typedef struct lc_dataset {
    char name[128];    /* file stem or "demo:NAME" (unique) */
    char source[512];  /* path or demo:NAME it came from */
    lc_scene *scene;   /* owned */
    lc_gpu_scene *gpu; /* owned; NULL until uploaded */
    double load_seconds;
    /* Suggested parameters, a partial render request ({params, importance,
     * color, style, camera}): the paper's settings for demos, the sidecar
     * NAME.lucent.json beside a file. Shown by /datasets, applied by clients
     * on dataset switch; NULL = none. Owned. */
    json_t *preset;
    lc_scene_measures cost; /* what render cost estimates need (cost.h) */
    /* serve --mpi: the description of the whole dataset, taken before the
     * scene became this rank's shard (lc_datasets_shard); NULL otherwise. */
    json_t *whole_info;
    int exact_positions;      /* float GPU buffers and session opacities (--exact-positions) */
    lc_memory_report memory;  /* bytes by kind once uploaded (one worker's and one session's state) */
    int from_cache;           /* the scene came from the scene cache (dataset_cache.h) */
    struct lc_traced *traced; /* a streamline set a request traced (traced.h); NULL for loaded datasets */
} lc_dataset;

/* How datasets are loaded and held (lucent serve flags); zero = defaults. */
typedef struct lc_datasets_options {
    unsigned long long demo_size; /* lc_demo_desc.count for demos; 0 = the generator's */
    int exact_positions;          /* --exact-positions */
    uint64_t max_memory;          /* --max-memory: estimated resident bytes of all datasets; 0 = no limit */
    bool follow_symlinks;         /* --follow-symlinks: a folder's links may leave it */
    int workers;                  /* render workers, each holding per-element state; 0 = 1 */
    double load_timeout;          /* --load-timeout: seconds one dataset may take to load; 0 = none */
    /* serve --mpi: reads this rank's share of a file whose format allows it
     * (lc_scene_can_read_part), collectively with the other ranks, which load
     * the same sources in the same order; NULL: every file is read whole. */
    int (*read_part)(void *ctx, const char *path, lc_scene **out, lc_error *err);
    void *read_part_ctx;
    /* --cache: the scene cache folder (dataset_cache.h); NULL or "" = none. */
    const char *cache_dir;
} lc_datasets_options;

typedef struct lc_datasets lc_datasets;

/* Loads every source (file path or demo:NAME) in order, logging a line before
 * and after each so that large files show progress. With count == 0 loads
 * all demos. Names clash -> a numeric suffix. With opts->max_memory, a
 * dataset whose estimated resident size (lc_memory_estimate: GPU buffers,
 * per-element state of every worker, one session, plus the datasets before
 * it) exceeds the limit is refused as soon as it is loaded, before the next
 * one loads and before any upload: LC_ERR_LIMIT naming the estimate and the
 * limit. Thread: main, before the server starts. */
int lc_datasets_load(const char *const *sources, int count, const lc_datasets_options *opts, lc_datasets **out,
                     lc_error *err);
/* The estimated resident bytes of every dataset and the limit (0 = none). */
void lc_datasets_budget(const lc_datasets *d, uint64_t *estimated, uint64_t *limit);
/* {"budget": bytes|null, "estimated": bytes, "resident": bytes, "layout": "compact"|"exact"}. */
json_t *lc_datasets_memory_json(const lc_datasets *d);
/* Appends all demos (for --demo together with --data). */
int lc_datasets_add_demos(lc_datasets *d, lc_error *err);
/* Rebuilds the elements of every line or surface dataset with `budget` line
 * elements or patches (lucent serve --elements; wins over a sidecar's). */
int lc_datasets_set_element_budget(lc_datasets *d, uint32_t budget, lc_error *err);
/* Reads the sidecar of a data file (PATH minus its extension + ".lucent.json")
 * if there is one: validates it (unknown or bad fields name the file and the
 * field), applies its "elements" and its importance/colour attributes as the
 * scene's defaults, and returns the rest as the preset in *preset (NULL when
 * there is no sidecar). A sidecar that links outside the data file's folder
 * is refused unless follow_symlinks. */
int lc_dataset_read_sidecar(const char *path, bool follow_symlinks, lc_scene *scene, json_t **preset, lc_error *err);
/* Replaces every scene with shard(ctx, &scene, err), keeping the whole
 * dataset's description for lc_dataset_info (serve --mpi; before upload).
 * A part read by this rank (read_part) is kept as it is. */
int lc_datasets_shard(lc_datasets *d, int (*shard)(void *ctx, lc_scene **scene, lc_error *err), void *ctx,
                      lc_error *err);
/* The render workers the daemon runs, once the GL context tells (the default
 * is 1 on llvmpipe with little memory): the estimate of every dataset is
 * taken again with them. Loading counted opts->workers, which serve sets to
 * the default's upper bound, so this never raises the estimate of a dataset
 * already accepted. Before lc_datasets_upload. */
void lc_datasets_set_workers(lc_datasets *d, int workers);
/* Creates the GPU copies (the layout of the options), then releases the
 * scenes' CPU vertex arrays that the GPU now holds; a context of the share
 * group must be current. */
int lc_datasets_upload(lc_datasets *d, lc_error *err);
/* Destroys the GPU copies (context current), then everything else. */
void lc_datasets_release_gpu(lc_datasets *d);
void lc_datasets_destroy(lc_datasets *d);

int lc_datasets_count(const lc_datasets *d);
/* The vector fields loaded beside the scenes (demo fields, grid .vtk files:
 * lc_field_is_source); not counted by lc_datasets_count. Any thread. */
const lc_fields *lc_datasets_fields(const lc_datasets *d);
const lc_dataset *lc_datasets_at(const lc_datasets *d, int i);
/* By exact name, by "demo:NAME" / "NAME" for demos, "" = the first one.
 * NULL when unknown. Any thread. */
const lc_dataset *lc_datasets_find(const lc_datasets *d, const char *name);

/* New JSON object describing ds: name, source, type, vertices, primitives,
 * lines, triangles, elements, points, bounds, view {direction, up} (when the
 * scene suggests one), hasRgb, attributes [{name, range}], defaultImportance,
 * defaultColor, gpuBytes and memory (bytes by kind, once uploaded), preset (when there is one) and a
 * description for demos. Attributes also carry "percentiles" (the 2nd and
 * 98th) and "autoRange", the importance range of normalize "auto" when a
 * request gives none (lc_attribute_update_range).
 * Caller json_decref()s. Any thread (builds fresh objects every call). */
json_t *lc_dataset_info(const lc_dataset *ds);

#ifdef __cplusplus
}
#endif
#endif
