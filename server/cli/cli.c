/* Helpers shared by the CLI subcommands: dataset specs, requests, flags, GL. */
#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "demo.h"
#include "loaders.h"
#include "memory.h"

#define MAX_REQUEST_BYTES (1 << 20)

static int parse_u64(const char *s, uint64_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno || end == s || (*end && *end != '&') || s[0] == '-')
        return -1;
    *out = v;
    return 0;
}

int lc_cli_open_dataset(const char *spec, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (strncmp(spec, "demo:", 5) != 0)
        return lc_scene_load_file(spec, out, err);
    char name[64];
    const char *q = strchr(spec + 5, '?');
    size_t n = q ? (size_t)(q - (spec + 5)) : strlen(spec + 5);
    if (n == 0 || n >= sizeof name)
        return lc_err(err, LC_ERR_INVALID, "%s: expected demo:NAME", spec);
    memcpy(name, spec + 5, n);
    name[n] = '\0';
    lc_demo_desc desc = {0};
    for (const char *p = q; p && *p; p = strchr(p + 1, '&')) {
        const char *kv = p + 1;
        uint64_t v;
        if (strncmp(kv, "count=", 6) == 0 && parse_u64(kv + 6, &v) == 0)
            desc.count = v;
        else if (strncmp(kv, "seed=", 5) == 0 && parse_u64(kv + 5, &v) == 0)
            desc.seed = v;
        else
            return lc_err(err, LC_ERR_INVALID, "%s: expected ?count=N&seed=S after the demo name", spec);
    }
    return lc_demo_create(name, &desc, out, err);
}

int lc_cli_read_request(const char *path, lc_request *req, lc_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return lc_err(err, LC_ERR_IO, "%s: %s", path, strerror(errno));
    char *buf = malloc(MAX_REQUEST_BYTES + 1);
    size_t n = buf ? fread(buf, 1, MAX_REQUEST_BYTES + 1, f) : 0;
    fclose(f);
    if (!buf)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    if (n > MAX_REQUEST_BYTES) {
        free(buf);
        return lc_err(err, LC_ERR_LIMIT, "%s: larger than %d bytes", path, MAX_REQUEST_BYTES);
    }
    lc_proto_limits lim;
    lc_proto_limits_default(&lim);
    lim.max_size = 16384;
    lim.max_pixels = 16384LL * 16384LL;
    lim.max_text = MAX_REQUEST_BYTES;
    lc_proto_error perr;
    memset(&perr, 0, sizeof perr);
    int rc = lc_proto_parse_request(buf, n, &lim, req, &perr);
    free(buf);
    if (rc)
        return lc_err(err, rc, "%s: %s", path, perr.message);
    return 0;
}

const char lc_cli_flags_help[] =
    "  --dataset SPEC        demo:NAME[?count=N&seed=S] or a file (" LC_DATASET_EXTENSIONS ")\n"
    "  --elements N          line elements or surface patches (default: derived from the data)\n"
    "  --width N, --height N, --size WxH\n"
    "  --method NAME         fourier | exact | opaque | direct | wboit\n"
    "  --bands M             Fourier bands 1..8\n"
    "  --q X, --r X, --lambda X, --smoothing S, --fade T, --estimator foo|midpoint\n"
    "  --depth-range auto|global|pixel|moments   depth normalization: the data bounds, each pixel's\n"
    "                        range, or the bounds warped around each pixel's importance (auto:\n"
    "                        moments, or global with --normalize off)\n"
    "  --normalize auto|off  density-aware opacity (auto) or the paper formula (off)\n"
    "  --importance ATTR     importance attribute;  --color ATTR|importance|rgb\n"
    "  --colormap NAME       viridis, coolwarm, grayscale, inferno, plasma, ...\n"
    "  --lod PX              lines: largest simplification error in pixels (default 0.2; 0 = every segment)\n"
    "  --line-width W        world units;  --point-size PX;  --unlit\n"
    "  --format png|jpeg, --quality Q\n"
    "  --exact-positions     float vertex buffers and session opacities (images bit for bit as before the\n"
    "                        compact 16-bit layout; about twice the bytes per vertex)\n"
    "  --max-memory BYTES    refuse a dataset whose estimated resident size exceeds BYTES (k, M, G suffixes)\n";

/* Applies one "key": value pair through the protocol's query aliases so the
 * flags get exactly the validation of the HTTP API. */
static int apply_query(lc_request *req, const char *key, const char *value)
{
    lc_proto_limits lim;
    lc_proto_limits_default(&lim);
    lim.max_size = 16384;
    lim.max_pixels = 16384LL * 16384LL;
    lc_proto_error perr;
    memset(&perr, 0, sizeof perr);
    if (lc_proto_apply_query(req, key, value, &lim, &perr) != 0 || lc_proto_validate_request(req, &lim, &perr) != 0) {
        fprintf(stderr, "lucent: --%s %s: %s\n", key, value, perr.message);
        return -1;
    }
    return 1;
}

int lc_cli_begin(const char *cmd, int argc, char **argv, lc_request *req, lc_cli_common *common)
{
    lc_request_default(req);
    common->input = NULL;
    common->device = -1;
    common->elements = 0;
    common->exact_positions = 0;
    common->max_memory = 0;
    lc_error err = {0};
    for (int i = 1; i + 1 < argc; i++)
        if (strcmp(argv[i], "--request") == 0 && lc_cli_read_request(argv[i + 1], req, &err) != 0) {
            fprintf(stderr, "lucent %s: %s\n", cmd, err.msg);
            return 1;
        }
    return 0;
}

int lc_cli_has_flag(int argc, char **argv, const char *flag)
{
    for (int i = 1; i < argc; i++)
        if (strcmp(argv[i], flag) == 0)
            return 1;
    return 0;
}

const char *lc_cli_dataset_spec(const lc_request *req, const lc_cli_common *common)
{
    return common->input ? common->input : req->dataset[0] ? req->dataset : "demo:tornado";
}

int lc_cli_open(const char *cmd, const lc_request *req, const lc_cli_common *common, lc_scene **scene, lc_cli_gl *g)
{
    lc_error err = {0};
    const char *spec = lc_cli_dataset_spec(req, common);
    *scene = NULL;
    if (lc_cli_open_dataset(spec, scene, &err) != 0 ||
        (common->elements && lc_scene_set_element_budget(*scene, (uint32_t)common->elements, &err) != 0)) {
        fprintf(stderr, "lucent %s: %s\n", cmd, err.msg);
        lc_scene_destroy(*scene);
        *scene = NULL;
        return 1;
    }
    if (lc_cli_gl_open(common->device, g, &err) != 0) {
        fprintf(stderr, "lucent %s: %s\n", cmd, err.msg);
        lc_scene_destroy(*scene);
        *scene = NULL;
        return 1;
    }
    return 0;
}

int lc_cli_apply_flag(lc_request *req, lc_cli_common *common, int argc, char **argv, int *i)
{
    static const struct {
        const char *flag, *key;
    } map[] = {{"--width", "width"},
               {"--height", "height"},
               {"--method", "method"},
               {"--bands", "bands"},
               {"--q", "q"},
               {"--r", "r"},
               {"--lambda", "lambda"},
               {"--smoothing", "smoothing"},
               {"--fade", "fadeHalfLife"},
               {"--estimator", "estimator"},
               {"--normalize", "normalize"},
               {"--importance", "importance"},
               {"--color", "color"},
               {"--colormap", "colormap"},
               {"--line-width", "lineWidth"},
               {"--point-size", "pointSize"},
               {"--format", "format"},
               {"--quality", "quality"},
               {"--resolution-scale", "resolutionScale"},
               {"--subset", "subset"},
               {"--lod", "lod"},
               {"--background", "background"},
               {"--depth-range", "depthRange"}};
    const char *flag = argv[*i];
    if (strcmp(flag, "--exact-positions") == 0) {
        common->exact_positions = 1;
        return 1;
    }
    int takes_value = strcmp(flag, "--request") == 0 || strcmp(flag, "--input") == 0 || strcmp(flag, "--device") == 0 ||
                      strcmp(flag, "--elements") == 0 || strcmp(flag, "--max-memory") == 0;
    if (takes_value) {
        if (*i + 1 >= argc) {
            fprintf(stderr, "lucent: %s needs a value\n", flag);
            return -1;
        }
        const char *value = argv[++*i];
        if (strcmp(flag, "--input") == 0) {
            common->input = value;
        } else if (strcmp(flag, "--device") == 0) {
            char *end;
            long d = strtol(value, &end, 10);
            if (*end || end == value || d < 0 || d > 255) {
                fprintf(stderr, "lucent: --device %s: expected an EGL device index 0..255\n", value);
                return -1;
            }
            common->device = (int)d;
        } else if (strcmp(flag, "--max-memory") == 0) {
            if (lc_memory_parse_bytes(value, &common->max_memory) != 0) {
                fprintf(stderr, "lucent: --max-memory %s: expected bytes, e.g. 20G, 512M or 1000000\n", value);
                return -1;
            }
            lc_scene_set_load_limit(common->max_memory); /* readers refuse before allocating beyond it */
        } else if (strcmp(flag, "--elements") == 0) {
            char *end;
            long n = strtol(value, &end, 10);
            if (*end || end == value || n < 1 || n > (1L << 24)) {
                fprintf(stderr, "lucent: --elements %s: expected a count 1..16777216\n", value);
                return -1;
            }
            common->elements = n;
        } /* --request was read by lc_cli_begin */
        return 1;
    }
    if (strcmp(flag, "--unlit") == 0) {
        req->render.style.shading = LC_SHADING_NONE;
        return 1;
    }
    int is_size = strcmp(flag, "--size") == 0, is_dataset = strcmp(flag, "--dataset") == 0;
    int known = is_size || is_dataset;
    for (size_t k = 0; !known && k < sizeof map / sizeof map[0]; k++)
        known = strcmp(flag, map[k].flag) == 0;
    if (!known)
        return 0;
    if (*i + 1 >= argc) {
        fprintf(stderr, "lucent: %s needs a value\n", flag);
        return -1;
    }
    const char *value = argv[++*i];
    if (is_dataset) {
        snprintf(req->dataset, sizeof req->dataset, "%s", value);
        return 1;
    }
    if (is_size) {
        int w, h;
        char extra;
        if (sscanf(value, "%dx%d%c", &w, &h, &extra) != 2) {
            fprintf(stderr, "lucent: --size %s: expected WxH, e.g. 1024x768\n", value);
            return -1;
        }
        char ws[16], hs[16];
        snprintf(ws, sizeof ws, "%d", w);
        snprintf(hs, sizeof hs, "%d", h);
        return apply_query(req, "width", ws) < 0 ? -1 : apply_query(req, "height", hs);
    }
    for (size_t k = 0; k < sizeof map / sizeof map[0]; k++)
        if (strcmp(flag, map[k].flag) == 0)
            return apply_query(req, map[k].key, value);
    return 0;
}

int lc_cli_gl_open(int device, lc_cli_gl *out, lc_error *err)
{
    memset(out, 0, sizeof *out);
    lc_gl_desc desc = {.device = device};
    int rc = lc_gl_create(&desc, &out->gl, err);
    if (rc)
        return rc;
    rc = lc_gl_make_current(out->gl, err);
    if (!rc)
        rc = lc_renderer_create(NULL, &out->renderer, err);
    if (rc) {
        lc_gl_destroy(out->gl);
        out->gl = NULL;
    }
    return rc;
}

void lc_cli_gl_close(lc_cli_gl *g)
{
    if (g->renderer)
        lc_renderer_destroy(g->renderer);
    if (g->gl) {
        lc_gl_release_current(g->gl);
        lc_gl_destroy(g->gl);
    }
    memset(g, 0, sizeof *g);
}

void lc_cli_print_timings(const lc_frame_info *info)
{
    /* In execution order: the optional depth-range pass runs first. */
    for (int k = 0; k < LC_PASS_COUNT; k++) {
        int i = k == 0 ? LC_PASS_DEPTH_RANGE : k - 1;
        if (info->pass_ms[i] >= 0)
            printf("  %-13s %8.2f ms\n", lc_pass_name(i), info->pass_ms[i]);
    }
    printf("  %-13s %8.2f ms (GPU), %.2f ms wall\n", "total", info->gpu_ms, info->wall_ms);
}

int lc_cli_upload(const char *cmd, const lc_cli_common *common, lc_scene *scene, lc_gpu_scene **gs)
{
    lc_error err = {0};
    lc_gpu_scene_desc desc = {.exact_positions = common->exact_positions};
    *gs = NULL;
    if (lc_memory_check(scene, &desc, 1, 1, common->max_memory, &err) != 0 ||
        lc_gpu_scene_create_ex(scene, &desc, gs, &err) != 0) {
        fprintf(stderr, "lucent %s: %s\n", cmd, err.msg);
        return 1;
    }
    lc_scene_release_vertex_arrays(scene);
    lc_memory_trim();
    return 0;
}

lc_frame_state *lc_cli_frame_state(const lc_cli_common *common, uint32_t element_count)
{
    return common->exact_positions ? lc_frame_state_create(element_count)
                                   : lc_frame_state_create_compact(element_count);
}

uint64_t lc_cli_resident_bytes(void) { return lc_memory_resident_bytes(); }

void lc_cli_print_memory(const lc_scene *scene, const lc_gpu_scene *gs, const lc_cli_common *common)
{
    lc_gpu_scene_desc desc = {.exact_positions = common->exact_positions};
    lc_memory_report m;
    lc_memory_report_of(scene, gs, &desc, 1, 1, &m);
    double n = scene->vertex_count ? (double)scene->vertex_count : 1.0;
    printf("memory per vertex (%s layout%s), bytes:\n", common->exact_positions ? "exact" : "compact",
           gs ? "" : ", GPU estimated");
    printf("  scene arrays (CPU)  %7.2f  (positions %.2f, colours %.2f, tangents/normals %.2f, topology %.2f, "
           "attributes %.2f, elements %.2f)\n",
           m.cpu.total / n, m.cpu.positions / n, m.cpu.colors / n, m.cpu.frames / n, m.cpu.topology / n,
           m.cpu.attributes / n, m.cpu.elements / n);
    printf("  GPU buffers         %7.2f  (positions %.2f, tangents/normals %.2f, attributes %.2f, colours %.2f, "
           "vertex->element %.2f, indices %.2f, adjacency %.2f)\n",
           m.gpu.total / n, m.gpu.positions / n, m.gpu.frames / n, m.gpu.attributes / n, m.gpu.colors / n,
           m.gpu.vertex_elements / n, m.gpu.indices / n, m.gpu.adjacency / n);
    printf("  per-element state   %7.2f  (one render worker)\n", m.per_element / n);
    printf("  per-session state   %7.2f  (one viewer)\n", m.per_session / n);
    printf("  total               %7.2f  (%.1f MB)\n", m.total / n, m.total / 1e6);
    if (!gs && m.cpu.total)
        printf("  once uploaded       %7.2f  (the scene arrays are freed after the upload)\n",
               (m.total - m.cpu.total) / n);
}
