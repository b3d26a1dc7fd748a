/* Dataset registry: loads files and demos at start-up, uploads them once to the
 * shared GPU context and describes them as JSON for the API. */
#include "datasets.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "data_paths.h"
#include "dataset_cache.h"
#include "demo.h"
#include "fields.h"
#include "loaders.h"
#include "request.h"
#include "streamlines.h"
#include "vtk_field.h"

#define MOD "datasets"
#define MAX_DATASETS 256

struct lc_datasets {
    int count;
    lc_dataset items[MAX_DATASETS];
    lc_datasets_options opts;
    uint64_t estimated; /* lc_memory_estimate of every dataset so far */
    lc_fields fields;   /* vector fields, listed beside the scenes */
};

static void file_stem(const char *path, char *out, size_t cap)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    snprintf(out, cap, "%s", base);
    char *dot = strrchr(out, '.');
    if (dot && dot != out)
        *dot = '\0';
}

static int name_taken(const lc_datasets *d, const char *name)
{
    for (int i = 0; i < d->count; i++)
        if (strcmp(d->items[i].name, name) == 0)
            return 1;
    return 0;
}

/* The demos' suggested parameters: the paper's settings where it shows the
 * same kind of data (its tornado figure: q = 60, r = 500, lambda = 1). */
static json_t *demo_preset(const char *demo)
{
    if (strcmp(demo, "tornado") == 0)
        return json_pack("{s:{s:f, s:f, s:f}}", "params", "q", 60.0, "r", 500.0, "lambda", 1.0);
    return NULL;
}

#define SIDECAR_MAX_BYTES (64 * 1024)
#define LC_MAX_ELEMENT_BUDGET (1u << 24) /* as lc_scene_set_element_budget */

int lc_dataset_read_sidecar(const char *path, bool follow_symlinks, lc_scene *scene, json_t **preset, lc_error *err)
{
    *preset = NULL;
    char side[600];
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - path) : strlen(path);
    if (stem + sizeof ".lucent.json" > sizeof side)
        return 0;
    snprintf(side, sizeof side, "%.*s.lucent.json", (int)stem, path);
    struct stat st;
    if (stat(side, &st) != 0)
        return 0; /* no sidecar */
    int confined = lc_data_sidecar_check(path, side, follow_symlinks, err);
    if (confined)
        return confined;
    if (!S_ISREG(st.st_mode) || st.st_size > SIDECAR_MAX_BYTES)
        return lc_err(err, LC_ERR_INVALID, "%s: not a regular file of at most %d bytes", side, SIDECAR_MAX_BYTES);
    json_error_t je;
    json_t *root = json_load_file(side, JSON_REJECT_DUPLICATES, &je);
    if (!root)
        return lc_err(err, LC_ERR_INVALID, "%s: not JSON (line %d: %s)", side, je.line, je.text);
    int rc = 0;
    if (!json_is_object(root)) {
        rc = lc_err(err, LC_ERR_INVALID, "%s: expected a JSON object", side);
        goto done;
    }
    const char *key;
    json_t *v;
    json_object_foreach(root, key, v)
    {
        static const char *const allowed[] = {"params", "importance", "color", "style",
                                              "camera", "elements",   "lines", NULL};
        int ok = 0;
        for (int i = 0; allowed[i]; i++)
            ok |= strcmp(key, allowed[i]) == 0;
        if (!ok) {
            rc = lc_err_field(err, LC_ERR_INVALID, key,
                              "%s: unknown field \"%s\" (expected params, importance, "
                              "color, style, camera, elements or lines)",
                              side, key);
            goto done;
        }
    }
    json_t *elements = json_object_get(root, "elements");
    if (elements) {
        /* Range before the cast: 4294967297 must not become 1. */
        if (!json_is_integer(elements) || json_integer_value(elements) < 1 ||
            json_integer_value(elements) > LC_MAX_ELEMENT_BUDGET) {
            rc = lc_err_field(err, LC_ERR_INVALID, "elements", "%s: elements: expected an integer in 1..%u, got %s",
                              side, LC_MAX_ELEMENT_BUDGET,
                              json_is_integer(elements) ? "a number outside it" : "another type");
            goto done;
        }
        if ((rc = lc_scene_set_element_budget(scene, (uint32_t)json_integer_value(elements), err)) != 0) {
            lc_err_prefix(err, "%s", side);
            goto done;
        }
        json_object_del(root, "elements");
    }
    /* The rest must be a valid partial render request: the protocol's parser
     * checks every field and range, exactly as for a client's request. */
    char *text = json_dumps(root, JSON_COMPACT);
    lc_proto_limits lim;
    lc_proto_limits_default(&lim);
    lc_request req;
    lc_proto_error pe;
    memset(&pe, 0, sizeof pe);
    int bad = !text || lc_proto_parse_request(text, strlen(text), &lim, &req, &pe) != 0;
    free(text);
    lc_request_release(&req); /* what follows reads its mapping and style */
    if (bad) {
        rc = lc_err_field(err, LC_ERR_INVALID, pe.field, "%s: %s", side, pe.message[0] ? pe.message : "invalid");
        goto done;
    }
    /* Attributes the sidecar names become the dataset's defaults, so that a
     * request naming none gets them; explicit request fields still win. */
    if (json_object_get(json_object_get(root, "importance"), "attribute")) {
        if (lc_scene_find_attribute(scene, req.render.importance.attribute) < 0) {
            rc = lc_err_field(err, LC_ERR_INVALID, "importance.attribute", "%s: %s has no attribute \"%s\"", side,
                              scene->name, req.render.importance.attribute);
            goto done;
        }
        snprintf(scene->default_importance, sizeof scene->default_importance, "%s", req.render.importance.attribute);
    }
    if (json_object_get(json_object_get(root, "color"), "attribute")) {
        const char *c = req.render.color.attribute;
        if (strcmp(c, "importance") != 0 &&
            (strcmp(c, "rgb") == 0 ? !scene->rgb : lc_scene_find_attribute(scene, c) < 0)) {
            rc = lc_err_field(err, LC_ERR_INVALID, "color.attribute", "%s: %s has no %s \"%s\"", side, scene->name,
                              strcmp(c, "rgb") == 0 ? "per-vertex colour" : "attribute", c);
            goto done;
        }
        snprintf(scene->default_color, sizeof scene->default_color, "%s", c);
    }
    LC_INFO(MOD, "%s: preset from %s", scene->name, side);
    *preset = root;
    root = NULL;
done:
    json_decref(root);
    return rc;
}

int lc_datasets_set_element_budget(lc_datasets *d, uint32_t budget, lc_error *err)
{
    for (int i = 0; i < d->count; i++) {
        lc_dataset *ds = &d->items[i];
        int rc = lc_scene_set_element_budget(ds->scene, budget, err);
        if (rc)
            return rc;
        LC_INFO(MOD, "%s: %u elements (--elements)", ds->name, ds->scene->elements.count);
    }
    return 0;
}
static int add_directory(lc_datasets *d, const char *dir, lc_error *err);

static lc_gpu_scene_desc layout_of(const lc_datasets *d)
{
    return (lc_gpu_scene_desc){.exact_positions = d->opts.exact_positions};
}

/* --max-memory: refuses ds (loaded, not yet counted) when the estimate of
 * every dataset so far and this one exceeds the limit. */
static int check_budget(lc_datasets *d, const lc_dataset *ds, lc_error *err)
{
    lc_gpu_scene_desc desc = layout_of(d);
    int workers = d->opts.workers > 0 ? d->opts.workers : 1;
    uint64_t need = lc_memory_estimate(ds->scene, &desc, workers, 1);
    uint64_t limit = d->opts.max_memory;
    if (limit && d->estimated + need > limit)
        return lc_err(err, LC_ERR_LIMIT,
                      "%s: refused: needs an estimated %.1f MB resident (%u vertices at %.1f bytes, %u elements, "
                      "%d worker%s), %.1f MB with the datasets before it, over --max-memory %.1f MB",
                      ds->source, need / 1e6, ds->scene->vertex_count,
                      ds->scene->vertex_count ? (double)need / ds->scene->vertex_count : 0.0, ds->scene->elements.count,
                      workers, workers == 1 ? "" : "s", (d->estimated + need) / 1e6, limit / 1e6);
    d->estimated += need;
    return 0;
}

static int add_source(lc_datasets *d, const char *source, lc_error *err)
{
    unsigned long long demo_size = d->opts.demo_size;
    if (lc_cancelled()) /* a signal during start-up: no further dataset */
        return lc_err_cancelled(err, source);
    if (!lc_streamlines_is_spec(source) && lc_field_is_source(source)) { /* a vector field: fields.h */
        /* Its grid counts against --max-memory as a dataset does: the reader
         * refuses before allocating beyond what is left. */
        uint64_t left = d->opts.max_memory > d->estimated ? d->opts.max_memory - d->estimated : 1;
        lc_scene_set_load_limit(d->opts.max_memory ? left : 0);
        int rc = lc_fields_add(&d->fields, source, err);
        lc_scene_set_load_limit(0);
        if (rc == 0)
            d->estimated += lc_field_bytes(d->fields.items[d->fields.count - 1].field);
        return rc;
    }
    if (d->count >= MAX_DATASETS)
        return lc_err(err, LC_ERR_LIMIT, "%s: more than %d datasets", source, MAX_DATASETS);
    lc_dataset *ds = &d->items[d->count];
    memset(ds, 0, sizeof *ds);
    snprintf(ds->source, sizeof ds->source, "%s", source);
    double t0 = lc_now();
    /* The per-dataset time budget: loading stops at its next check (after
     * reading, in the scene's derivation, elements and level of detail). Not
     * under --mpi: the ranks read a file's shares together and must all stop
     * or none. */
    lc_load_budget(d->opts.read_part ? 0 : d->opts.load_timeout);
    int rc;
    char base[128];
    if (lc_streamlines_is_spec(source)) { /* a streamline set traced from a field */
        LC_INFO(MOD, "tracing %s ...", source);
        long cpus = sysconf(_SC_NPROCESSORS_ONLN);
        rc = lc_streamlines_load(source, cpus > 0 ? (int)cpus : 1, &ds->scene, err);
        snprintf(base, sizeof base, "%s", rc ? source : ds->scene->name);
    } else if (strncmp(source, "demo:", 5) == 0) {
        lc_demo_desc desc = {.seed = 0, .count = demo_size}; /* "?count=N&seed=S" overrides */
        LC_INFO(MOD, "generating %s ...", source);
        rc = lc_demo_create_spec(source + 5, &desc, &ds->scene, err);
        snprintf(base, sizeof base, "%s", source);
        char demo[64];
        snprintf(demo, sizeof demo, "%.*s", (int)strcspn(source + 5, "?"), source + 5);
        ds->preset = rc ? NULL : demo_preset(demo);
    } else {
        struct stat st;
        if (stat(source, &st) != 0)
            return lc_err(err, LC_ERR_IO, "%s: cannot open (no such file)", source);
        if (S_ISDIR(st.st_mode) && !lc_scene_is_dataset_file(source)) /* a TRX directory is one dataset */
            return add_directory(d, source, err);
        LC_INFO(MOD, "loading %s (%.1f MB) ...", source, st.st_size / 1e6);
        uint64_t left = d->opts.max_memory > d->estimated ? d->opts.max_memory - d->estimated : 1;
        lc_scene_set_load_limit(d->opts.max_memory ? left : 0);  /* readers refuse before allocating beyond it */
        if (d->opts.read_part && lc_scene_can_read_part(source)) /* serve --mpi: this rank's share */
            rc = d->opts.read_part(d->opts.read_part_ctx, source, &ds->scene, err);
        else
            rc = lc_dataset_cache_load(d->opts.cache_dir, source, &ds->scene, &ds->from_cache, err);
        file_stem(source, base, sizeof base);
        if (strncmp(base, "demo:", 5) == 0) { /* the demos' names are theirs: "demo:x.csv" is "demo_x" */
            base[4] = '_';
            LC_WARN(MOD, "%s: served as \"%s\" (names starting with demo: are the demos')", source, base);
        }
        if (rc == 0 &&
            (rc = lc_dataset_read_sidecar(source, d->opts.follow_symlinks, ds->scene, &ds->preset, err)) != 0) {
            lc_scene_destroy(ds->scene);
            ds->scene = NULL;
        }
    }
    lc_load_budget(0);
    if (rc == LC_ERR_LIMIT && err && strstr(err->msg, "over the load budget")) {
        char msg[sizeof err->msg];
        snprintf(msg, sizeof msg, "%s", err->msg);
        lc_err(err, rc, "%.*s (--load-timeout)", (int)sizeof msg - 20, msg);
    }
    if (rc != 0)
        return rc;
    snprintf(ds->name, sizeof ds->name, "%s", base);
    for (int k = 2; name_taken(d, ds->name); k++)
        snprintf(ds->name, sizeof ds->name, "%.100s-%d", base, k);
    ds->load_seconds = lc_now() - t0;
    ds->exact_positions = d->opts.exact_positions;
    if ((rc = check_budget(d, ds, err)) != 0) {
        lc_scene_destroy(ds->scene);
        ds->scene = NULL;
        json_decref(ds->preset);
        ds->preset = NULL;
        return rc;
    }
    const lc_scene *s = ds->scene;
    lc_scene_measure(s, &ds->cost);
    LC_INFO(MOD, "loaded %s: %s, %u vertices, %llu primitives, %u elements in %.2f s%s", ds->name,
            lc_prim_type_name(s->type), s->vertex_count, (unsigned long long)lc_scene_primitive_count(s),
            s->elements.count, ds->load_seconds, ds->from_cache ? " (scene cache)" : "");
    d->count++;
    return 0;
}

static int not_hidden(const struct dirent *e) { return e->d_name[0] != '.'; }

/* Every file of dir (not recursive, by name) that a reader recognizes by its
 * extension. A file that fails to load is logged and skipped, so that one bad
 * file does not keep a folder from being served; a folder without any dataset
 * that loads is an error. */
static int add_directory(lc_datasets *d, const char *dir, lc_error *err)
{
    struct dirent **entries = NULL;
    int n = scandir(dir, &entries, not_hidden, alphasort);
    if (n < 0)
        return lc_err(err, LC_ERR_IO, "%s: cannot list the folder: %s", dir, strerror(errno));
    int loaded = 0, failed = 0, rc = 0;
    lc_error last = {0};
    char root[PATH_MAX];
    if (!realpath(dir, root)) {
        for (int i = 0; i < n; i++)
            free(entries[i]);
        free(entries);
        return lc_err(err, LC_ERR_IO, "%s: cannot resolve the folder: %s", dir, strerror(errno));
    }
    for (int i = 0; i < n; i++) {
        char path[1024];
        struct stat st;
        int len = snprintf(path, sizeof path, "%s/%s", dir, entries[i]->d_name);
        lc_error e = {0};
        if (rc == 0 && len > 0 && (size_t)len < sizeof path && stat(path, &st) == 0 &&
            (S_ISREG(st.st_mode) || S_ISDIR(st.st_mode)) && lc_scene_is_dataset_file(path)) {
            int r = lc_data_path_check(root, path, d->opts.follow_symlinks, &e);
            if (r == 0)
                r = add_source(d, path, &e);
            if (r == 0) {
                loaded++;
            } else if (r == LC_ERR_CANCELLED || (r == LC_ERR_LIMIT && d->count >= MAX_DATASETS)) {
                rc = lc_err(err, r, "%s", e.msg);
            } else {
                LC_ERROR(MOD, "skipping %s", e.msg);
                last = e;
                failed++;
            }
        }
        free(entries[i]);
    }
    free(entries);
    if (rc)
        return rc;
    if (loaded == 0 && failed > 0)
        return lc_err(err, last.code ? last.code : LC_ERR_INVALID, "%s: no dataset loaded (%d failed; last: %s)", dir,
                      failed, last.msg);
    if (loaded == 0)
        return lc_err(err, LC_ERR_NOT_FOUND, "%s: no dataset files (%s) in the folder", dir, LC_DATASET_EXTENSIONS);
    LC_INFO(MOD, "%s: %d dataset(s) loaded, %d skipped", dir, loaded, failed);
    return 0;
}

int lc_datasets_add_demos(lc_datasets *d, lc_error *err)
{
    for (const char *const *n = lc_demo_names(); *n; n++) {
        char src[128];
        snprintf(src, sizeof src, "demo:%s", *n);
        if (lc_datasets_find(d, src))
            continue;
        int rc = add_source(d, src, err);
        if (rc != 0)
            return rc;
    }
    return lc_fields_add_demos(&d->fields, err);
}

int lc_datasets_load(const char *const *sources, int count, const lc_datasets_options *opts, lc_datasets **out,
                     lc_error *err)
{
    *out = NULL;
    lc_datasets *d = calloc(1, sizeof *d);
    if (!d)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    if (opts)
        d->opts = *opts;
    int rc = 0;
    if (count == 0)
        rc = lc_datasets_add_demos(d, err);
    for (int i = 0; rc == 0 && i < count; i++)
        rc = add_source(d, sources[i], err);
    if (rc != 0) {
        lc_datasets_destroy(d);
        return rc;
    }
    *out = d;
    return 0;
}

void lc_datasets_set_workers(lc_datasets *d, int workers)
{
    if (!d || workers < 1 || workers == d->opts.workers)
        return;
    d->opts.workers = workers;
    lc_gpu_scene_desc desc = layout_of(d);
    d->estimated = 0;
    for (int i = 0; i < d->count; i++)
        if (d->items[i].scene)
            d->estimated += lc_memory_estimate(d->items[i].scene, &desc, workers, 1);
}

/* The uploaded levels of detail, for the cost model: a frame is priced at
 * the level it will draw (cost.c), not at full detail. */
static void measure_levels(lc_dataset *ds)
{
    lc_scene_measures *m = &ds->cost;
    int n = lc_gpu_scene_levels(ds->gpu);
    double e0 = 0, p0 = 0;
    m->levels = 0;
    if (n <= 1 || n > LC_MEASURE_LEVELS)
        return;
    lc_gpu_scene_level(ds->gpu, 0, &e0, &p0);
    if (!(p0 > 0))
        return;
    for (int i = 0; i < n; i++) {
        double e, prims;
        lc_gpu_scene_level(ds->gpu, i, &e, &prims);
        m->level_error[i] = e, m->level_share[i] = prims / p0;
    }
    m->levels = n;
}

int lc_datasets_upload(lc_datasets *d, lc_error *err)
{
    for (int i = 0; i < d->count; i++) {
        lc_dataset *ds = &d->items[i];
        if (ds->gpu)
            continue;
        lc_gpu_scene_desc desc = layout_of(d);
        int rc = lc_gpu_scene_create_ex(ds->scene, &desc, &ds->gpu, err);
        if (rc != 0) {
            lc_err_prefix(err, "%s", ds->name);
            return rc;
        }
        measure_levels(ds);
        /* Nothing reads the per-vertex arrays after the upload (cost stats
         * and descriptions were taken at load). */
        lc_scene_release_vertex_arrays(ds->scene);
        lc_memory_trim();
        lc_memory_report_of(ds->scene, ds->gpu, &desc, d->opts.workers > 0 ? d->opts.workers : 1, 1, &ds->memory);
        LC_INFO(MOD, "uploaded %s: %.1f MB of GPU buffers (%s layout, %.1f bytes per vertex with its state)", ds->name,
                lc_gpu_scene_bytes(ds->gpu) / 1e6, desc.exact_positions ? "exact" : "compact",
                ds->scene->vertex_count ? (double)ds->memory.total / ds->scene->vertex_count : 0.0);
    }
    return 0;
}

void lc_datasets_release_gpu(lc_datasets *d)
{
    if (!d)
        return;
    for (int i = 0; i < d->count; i++) {
        if (d->items[i].gpu)
            lc_gpu_scene_destroy(d->items[i].gpu);
        d->items[i].gpu = NULL;
    }
}

void lc_datasets_destroy(lc_datasets *d)
{
    if (!d)
        return;
    for (int i = 0; i < d->count; i++) {
        if (d->items[i].scene)
            lc_scene_destroy(d->items[i].scene);
        json_decref(d->items[i].preset);
        json_decref(d->items[i].whole_info);
    }
    lc_fields_clear(&d->fields);
    /* A leftover GPU copy here means the caller had no context to destroy it
     * with; the process is exiting, so the driver reclaims it. */
    free(d);
}

int lc_datasets_count(const lc_datasets *d) { return d ? d->count : 0; }

const lc_fields *lc_datasets_fields(const lc_datasets *d) { return d ? &d->fields : NULL; }

const lc_dataset *lc_datasets_at(const lc_datasets *d, int i)
{
    return (d && i >= 0 && i < d->count) ? &d->items[i] : NULL;
}

const lc_dataset *lc_datasets_find(const lc_datasets *d, const char *name)
{
    if (!d || d->count == 0)
        return NULL;
    if (!name || !name[0])
        return &d->items[0];
    for (int i = 0; i < d->count; i++)
        if (strcmp(d->items[i].name, name) == 0)
            return &d->items[i];
    /* "tornado" finds "demo:tornado" when no file claims that stem. */
    for (int i = 0; i < d->count; i++)
        if (strncmp(d->items[i].name, "demo:", 5) == 0 && strcmp(d->items[i].name + 5, name) == 0)
            return &d->items[i];
    return NULL;
}

int lc_datasets_shard(lc_datasets *d, int (*shard)(void *ctx, lc_scene **scene, lc_error *err), void *ctx,
                      lc_error *err)
{
    for (int i = 0; i < d->count; i++) {
        lc_dataset *ds = &d->items[i];
        json_t *whole = lc_dataset_info(ds);
        int rc = ds->scene->part_of ? 0 : shard(ctx, &ds->scene, err); /* a part is a share already */
        if (rc) {
            json_decref(whole);
            return rc;
        }
        ds->whole_info = whole;
    }
    return 0;
}

#define J(v) json_integer((json_int_t)(v))

/* Bytes by kind of one uploaded dataset, and per vertex. */
static json_t *memory_json(const lc_dataset *ds)
{
    const lc_memory_report *m = &ds->memory;
    double n = ds->scene->vertex_count ? (double)ds->scene->vertex_count : 1.0;
    json_t *cpu = json_pack("{s:o, s:o, s:o, s:o, s:o, s:o, s:o}", "positions", J(m->cpu.positions), "colors",
                            J(m->cpu.colors), "frames", J(m->cpu.frames), "topology", J(m->cpu.topology), "attributes",
                            J(m->cpu.attributes), "elements", J(m->cpu.elements), "total", J(m->cpu.total));
    json_t *gpu = json_pack("{s:o, s:o, s:o, s:o, s:o, s:o, s:o, s:o}", "positions", J(m->gpu.positions), "frames",
                            J(m->gpu.frames), "attributes", J(m->gpu.attributes), "colors", J(m->gpu.colors),
                            "vertexElements", J(m->gpu.vertex_elements), "indices", J(m->gpu.indices), "adjacency",
                            J(m->gpu.adjacency), "total", J(m->gpu.total));
    return json_pack("{s:s, s:o, s:o, s:o, s:o, s:o, s:f}", "layout", ds->exact_positions ? "exact" : "compact",
                     "sceneArrays", cpu, "gpuBuffers", gpu, "perElementState", J(m->per_element), "perSessionState",
                     J(m->per_session), "total", J(m->total), "bytesPerVertex", m->total / n);
}

void lc_datasets_budget(const lc_datasets *d, uint64_t *estimated, uint64_t *limit)
{
    *estimated = d->estimated;
    *limit = d->opts.max_memory;
}

json_t *lc_datasets_memory_json(const lc_datasets *d)
{
    return json_pack("{s:o, s:o, s:o, s:s}", "budget", d->opts.max_memory ? J(d->opts.max_memory) : json_null(),
                     "estimated", J(d->estimated), "resident", J(lc_memory_resident_bytes()), "layout",
                     d->opts.exact_positions ? "exact" : "compact");
}

json_t *lc_dataset_info(const lc_dataset *ds)
{
    if (ds->whole_info) { /* serve --mpi: this rank holds a shard; describe the whole */
        json_t *o = json_deep_copy(ds->whole_info);
        if (o && ds->gpu)
            json_object_set_new(o, "gpuBytes", json_integer((json_int_t)lc_gpu_scene_bytes(ds->gpu)));
        return o;
    }
    const lc_scene *s = ds->scene;
    json_t *o = json_object();
    json_object_set_new(o, "name", json_string(ds->name));
    if (strncmp(ds->source, "demo:", 5) == 0) {
        const char *desc = lc_demo_description(ds->source + 5);
        if (desc)
            json_object_set_new(o, "description", json_string(desc));
    }
    json_object_set_new(o, "type", json_string(lc_prim_type_name(s->type)));
    /* A part read by this rank (serve --mpi) describes the whole it belongs to. */
    json_int_t vertices = s->part_of ? (json_int_t)s->whole_vertices : s->vertex_count;
    json_object_set_new(o, "vertices", json_integer(vertices));
    json_object_set_new(o, "primitives",
                        json_integer((json_int_t)(s->part_of ? s->whole_primitives : lc_scene_primitive_count(s))));
    json_object_set_new(o, "lines", json_integer(s->part_of ? (json_int_t)s->whole_lines : s->line_count));
    json_object_set_new(o, "triangles", json_integer(s->triangle_count));
    json_object_set_new(o, "elements", json_integer(s->elements.count));
    json_object_set_new(o, "points", json_integer(s->type == LC_PRIM_POINTS ? vertices : 0));
    json_t *b = json_array(); /* [[xmin, ymin, zmin], [xmax, ymax, zmax]] as in openapi.yaml */
    for (int k = 0; k < 2; k++) {
        json_t *corner = json_array();
        for (int i = 0; i < 3; i++)
            json_array_append_new(corner, json_real(isfinite(s->bounds[3 * k + i]) ? s->bounds[3 * k + i] : 0.0));
        json_array_append_new(b, corner);
    }
    json_object_set_new(o, "bounds", b);
    if (s->has_view) {
        /* The suggested initial view the renderer fits to when a request has no
         * camera; clients fit their own camera to it the same way. */
        json_t *view = json_object(), *dir = json_array(), *up = json_array();
        for (int i = 0; i < 3; i++) {
            json_array_append_new(dir, json_real(isfinite(s->view_direction[i]) ? s->view_direction[i] : 0.0));
            json_array_append_new(up, json_real(isfinite(s->view_up[i]) ? s->view_up[i] : 0.0));
        }
        json_object_set_new(view, "direction", dir);
        json_object_set_new(view, "up", up);
        json_object_set_new(o, "view", view);
    }
    json_object_set_new(o, "hasRgb", json_boolean(lc_scene_has_rgb(s)));
    json_t *attrs = json_array();
    for (int i = 0; i < s->attribute_count; i++) {
        const lc_attribute *a = &s->attributes[i];
        json_t *ja = json_object();
        json_object_set_new(ja, "name", json_string(a->name));
        json_t *r = json_array();
        json_array_append_new(r, json_real(isfinite(a->min) ? a->min : 0.0));
        json_array_append_new(r, json_real(isfinite(a->max) ? a->max : 0.0));
        json_object_set_new(ja, "range", r);
        json_t *pct = json_array();
        json_array_append_new(pct, json_real(isfinite(a->p02) ? a->p02 : 0.0));
        json_array_append_new(pct, json_real(isfinite(a->p98) ? a->p98 : 0.0));
        json_object_set_new(ja, "percentiles", pct);
        json_t *ar = json_array();
        json_array_append_new(ar, json_real(isfinite(a->auto_lo) ? a->auto_lo : 0.0));
        json_array_append_new(ar, json_real(isfinite(a->auto_hi) ? a->auto_hi : 0.0));
        json_object_set_new(ja, "autoRange", ar);
        if (a->smaller_matters) /* the importance maps it inverted by default (docs/GUIDE.md "Default attributes") */
            json_object_set_new(ja, "smallerMatters", json_true());
        if (a->categorical) /* class labels: never the default importance (docs/GUIDE.md "Default attributes") */
            json_object_set_new(ja, "categorical", json_true());
        json_array_append_new(attrs, ja);
    }
    json_object_set_new(o, "attributes", attrs);
    json_object_set_new(o, "defaultImportance", json_string(s->default_importance));
    json_object_set_new(o, "defaultColor", json_string(s->default_color));
    if (ds->gpu)
        json_object_set_new(o, "gpuBytes", json_integer((json_int_t)lc_gpu_scene_bytes(ds->gpu)));
    if (ds->gpu)
        json_object_set_new(o, "memory", memory_json(ds));
    if (ds->preset)
        json_object_set_new(o, "preset", json_deep_copy(ds->preset));
    return o;
}
