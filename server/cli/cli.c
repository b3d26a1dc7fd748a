/* Helpers shared by the CLI subcommands: dataset specs, requests, flags, GL. */
#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "demo.h"
#include "loaders.h"
#include "memory.h"
#include "streamlines.h"
#include "vtk_field.h"

#define MAX_REQUEST_BYTES (1 << 20)

int lc_cli_open_dataset(const char *spec, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (lc_streamlines_is_spec(spec)) {
        long cpus = sysconf(_SC_NPROCESSORS_ONLN);
        return lc_streamlines_load(spec, cpus > 0 ? (int)cpus : 1, out, err);
    }
    if (strncmp(spec, "demo:", 5) != 0)
        return lc_scene_load_file(spec, out, err);
    return lc_demo_create_spec(spec + 5, NULL, out, err);
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
    lc_request_release(req); /* a second --request replaces the first */
    int rc = lc_proto_parse_request(buf, n, &lim, req, &perr);
    free(buf);
    if (rc)
        return lc_err(err, rc, "%s: %s", path, perr.message);
    return 0;
}

/* A layered request maps each layer by its own layers[i].importance, .color
 * and .style (docs/ALGORITHM.md §24): the flags that set one dataset's
 * mapping and sizes would change nothing, so they are refused rather than
 * ignored. before: the request as the file left it. */
static int check_layer_flags(const char *cmd, const lc_request *req, const lc_render_params *before)
{
    const lc_render_params *p = &req->render;
    const lc_style *a = &before->style, *b = &p->style;
    if (lc_request_layer_count(req) == 0 ||
        (memcmp(&before->importance, &p->importance, sizeof p->importance) == 0 &&
         memcmp(&before->color, &p->color, sizeof p->color) == 0 && a->line_width == b->line_width &&
         a->min_line_pixels == b->min_line_pixels && a->point_size == b->point_size && a->shading == b->shading))
        return 0;
    fprintf(stderr,
            "lucent %s: layers: the request maps each layer by its layers[i].importance, .color and .style; "
            "--importance, --color, --colormap, --line-width, --point-size and --unlit apply to one dataset\n",
            cmd);
    return -1;
}

/* Applies one request field through the protocol's query aliases so the
 * flags get exactly the validation of the HTTP API. */
static int set_request_field(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    lc_cli_common *common = target;
    lc_request *req = common->req;
    common->width_set |= strcmp(o->key, "width") == 0;
    common->height_set |= strcmp(o->key, "height") == 0;
    lc_proto_limits lim;
    lc_proto_limits_default(&lim);
    lim.max_size = 16384;
    lim.max_pixels = 16384LL * 16384LL;
    lc_proto_error perr;
    memset(&perr, 0, sizeof perr);
    if (lc_proto_apply_query(req, o->key, arg, &lim, &perr) != 0 || lc_proto_validate_request(req, &lim, &perr) != 0) {
        snprintf(why, why_len, "\"%s\": %s", arg, perr.message);
        return -1;
    }
    return 0;
}

static int set_size(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    long long w, h;
    const char *x = strchr(arg, 'x');
    char ws[24], hs[24];
    if (!x || (size_t)(x - arg) >= sizeof ws) {
        snprintf(why, why_len, "\"%s\": expected WxH, e.g. 1024x768", arg);
        return -1;
    }
    snprintf(ws, sizeof ws, "%.*s", (int)(x - arg), arg);
    if (lc_opt_parse_int(ws, 1, 16384, &w) != 0 || lc_opt_parse_int(x + 1, 1, 16384, &h) != 0) {
        snprintf(why, why_len, "\"%s\": expected WxH, each side an integer in [1, 16384], e.g. 1024x768", arg);
        return -1;
    }
    lc_option width = *o, height = *o;
    width.key = "width";
    height.key = "height";
    snprintf(ws, sizeof ws, "%lld", w);
    snprintf(hs, sizeof hs, "%lld", h);
    return set_request_field(target, &width, ws, why, why_len) ? -1
                                                               : set_request_field(target, &height, hs, why, why_len);
}

static int set_dataset(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    (void)o;
    lc_request *req = ((lc_cli_common *)target)->req;
    if (!arg[0] || strlen(arg) >= sizeof req->dataset) {
        snprintf(why, why_len, "expected a dataset of 1 to %zu bytes", sizeof req->dataset - 1);
        return -1;
    }
    snprintf(req->dataset, sizeof req->dataset, "%s", arg);
    ((lc_cli_common *)target)->dataset_set = 1;
    return 0;
}

static int set_max_memory(void *target, const lc_option *o, const char *arg, char *why, size_t why_len)
{
    (void)o;
    if (lc_memory_parse_bytes(arg, &((lc_cli_common *)target)->max_memory) != 0) {
        snprintf(why, why_len, "\"%s\": expected bytes, e.g. 20G, 512M or 1000000", arg);
        return -1;
    }
    lc_scene_set_load_limit(((lc_cli_common *)target)->max_memory); /* readers refuse before allocating beyond it */
    return 0;
}

#define REQ(flag, meta, field, text)                                                                                   \
    {                                                                                                                  \
        flag, meta, LC_OPT_CALL, .call = set_request_field, .key = field, .help = text                                 \
    }
#define COMMON(member) LC_OPT_AT(lc_cli_common, member)
/* The flags every rendering subcommand takes: the request's fields (checked by
 * protocol/, as over HTTP) and how the dataset is opened. */
static const lc_option common_options[] = {
    {"--request", "REQ.json", LC_OPT_TEXT, COMMON(request),
     .help = "a render request (protocol/README.md); flags override its fields"},
    {"--dataset", "SPEC", LC_OPT_CALL, .call = set_dataset,
     .help = "demo:NAME[?count=N&seed=S], a file (" LC_DATASET_EXTENSIONS "),\n"
             "or streamlines:FIELD?seeding=...&seeds=...&count=N (a traced streamline set)"},
    {"--input", "SPEC", LC_OPT_TEXT, COMMON(input), .help = "the same, over the request's dataset"},
    {"--elements", "N", LC_OPT_INT, COMMON(elements), 1, 1 << 24,
     .help = "line elements or surface patches (default: derived from the data)"},
    {"--device", "N", LC_OPT_INT, COMMON(device), 0, 255,
     .help = "EGL device index (default: LUCENT_EGL_DEVICE or the first GPU)"},
    REQ("--width", "N", "width", ""),
    REQ("--height", "N", "height", ""),
    {"--size", "WxH", LC_OPT_CALL, .call = set_size, .numeric = 1, .help = "image size in pixels"},
    REQ("--method", "NAME", "method",
        "fourier | exact | opaque | direct | wboit | weighted-average | binning | kanzler"),
    REQ("--bands", "M", "bands", "Fourier bands 1..8"),
    REQ("--q", "X", "q", ""),
    REQ("--r", "X", "r", ""),
    REQ("--lambda", "X", "lambda", "opacity optimization: clutter, context and emphasis"),
    REQ("--smoothing", "S", "smoothing", "Laplacian smoothing iterations of the element opacities"),
    REQ("--fade", "T", "fadeHalfLife", "fading half-life of the opacities (s)"),
    REQ("--estimator", "NAME", "estimator", "foo | midpoint"),
    REQ("--alpha-source", "NAME", "alphaSource",
        "method direct's opacity: importance (g^k) | constant | angle | normalVariation"),
    REQ("--depth-range", "MODE", "depthRange",
        "auto|global|pixel|moments: depth normalization by the data bounds,\n"
        "each pixel's range, or the bounds warped around each pixel's\n"
        "importance (auto: moments, or global with --normalize off)"),
    REQ("--normalize", "auto|off", "normalize", "density-aware opacity (auto) or the paper formula (off)"),
    REQ("--clarity", "C", "clarity",
        "target opacity of the most important tenth, 0..1 (default 0.5;\n"
        "0 = off): a loop on the emphasis while q, r and lambda are not given"),
    REQ("--kanzler-m", "X", "kanzlerImportance", ""),
    REQ("--kanzler-c", "X", "kanzlerCoverage", ""),
    REQ("--kanzler-v", "X", "kanzlerVariance", ""),
    REQ("--kanzler-d", "X", "kanzlerDepth", ""),
    REQ("--kanzler-lambda", "X", "kanzlerLambda",
        "method kanzler: weights of the maximum importance, coverage,\n"
        "directional variance and in-front term, and the emphasis lambda"),
    REQ("--exclude-self", "true|false", "excludeSelf",
        "exact method: a fragment's sums leave out its own element's fragments (no self-occlusion)"),
    REQ("--importance", "ATTR", "importance", "importance attribute"),
    REQ("--color", "ATTR", "color", "colour by an attribute, importance or rgb"),
    REQ("--colormap", "NAME", "colormap", "viridis, coolwarm, grayscale, inferno, plasma, ..."),
    REQ("--lod", "PX", "lod",
        "lines: largest simplification error in pixels\n"
        "(default 0.2; 0 = every segment)"),
    REQ("--line-width", "W", "lineWidth", "line width in world units"),
    REQ("--point-size", "PX", "pointSize", "point size in pixels"),
    {"--unlit", NULL, LC_OPT_BOOL, COMMON(unlit), .help = "no shading"},
    REQ("--format", "png|jpeg", "format", ""),
    REQ("--quality", "Q", "quality", "image format and JPEG quality"),
    REQ("--resolution-scale", "S", "resolutionScale", "resolution of the opacity passes P1/P2"),
    REQ("--subset", "N", "subset", "P1/P4 use every N-th primitive, weights x N"),
    REQ("--auto-subset", "N", "autoSubset",
        "largest stride P1 draws with where P0 measured dense data\n"
        "(default 1 = off; e.g. 8)"),
    REQ("--progressive", "N", "progressive",
        "draw the still in N batches added to kept sums; the last\n"
        "batch's image is the one-shot image (default 1 = one frame)"),
    REQ("--background", "R,G,B", "background", "background colour, each in [0, 1]"),
    {"--exact-positions", NULL, LC_OPT_BOOL, COMMON(exact_positions),
     .help = "float vertex buffers and session opacities (images bit for bit\n"
             "as before the compact 16-bit layout; twice the bytes per vertex)"},
    {"--max-memory", "BYTES", LC_OPT_CALL, .call = set_max_memory, .numeric = 1,
     .help = "refuse a dataset whose estimated resident size exceeds BYTES\n"
             "(k, M, G suffixes)"},
    {NULL}};

int lc_cli_parse(const char *cmd, const lc_option *own, void *own_target, int argc, char **argv, lc_request *req,
                 lc_cli_common *common, void (*usage)(FILE *f, const lc_opt_set *sets, int nsets))
{
    lc_request_default(req);
    memset(common, 0, sizeof *common);
    common->req = req;
    common->device = -1;
    /* The request file first, so that flags override it wherever they stand. */
    lc_error err = {0};
    for (int i = 1; i < argc; i++) {
        const char *path = NULL;
        if (strncmp(argv[i], "--request=", 10) == 0)
            path = argv[i] + 10;
        else if (strcmp(argv[i], "--request") == 0 && i + 1 < argc)
            path = argv[i + 1];
        if (path && lc_cli_read_request(path, req, &err) != 0) {
            fprintf(stderr, "lucent %s: %s\n", cmd, err.msg);
            return 2;
        }
    }
    lc_render_params *before = malloc(sizeof *before); /* the request file's, for check_layer_flags */
    if (!before) {
        fprintf(stderr, "lucent %s: out of memory\n", cmd);
        return 2;
    }
    *before = req->render;
    lc_opt_set sets[2] = {{own, own_target}, {common_options, common}};
    int rc = lc_opt_parse(cmd, sets, 2, argc, argv, NULL, 0, NULL);
    if (rc > 0 && !lc_cli_has_flag(argc, argv, "--list-flags"))
        usage(stdout, sets, 2);
    if (rc == 0 && common->unlit)
        req->render.style.shading = LC_SHADING_NONE;
    if (rc == 0 && check_layer_flags(cmd, req, before) != 0)
        rc = -1;
    free(before);
    return rc < 0 ? 2 : rc > 0 ? 1 : 0;
}

int lc_cli_with_request(int argc, char **argv, int (*body)(int argc, char **argv, lc_request *req))
{
    lc_request req;
    lc_request_default(&req);
    int rc = body(argc, argv, &req);
    lc_request_release(&req);
    return rc;
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
    /* A vector field draws the streamline set of the request's streamlines
     * section, traced as a load-time set of the same spec (docs/ALGORITHM.md
     * §22); elsewhere the section is refused, naming its field. */
    char traced[8192];
    const char *given = NULL;
    if (!lc_streamlines_is_spec(spec) && lc_field_is_source(spec)) {
        if (lc_proto_streamlines_spec(req, spec, traced, sizeof traced) < 0) {
            fprintf(stderr, "lucent %s: streamlines.seeds: the set's settings are too long\n", cmd);
            return 1;
        }
        spec = traced;
    } else if (lc_proto_streamlines_given(req, &given)) {
        fprintf(stderr,
                "lucent %s: %s: applies when the dataset names a vector field (demo:abc-flow, a grid .vtk "
                "or .nc), not %s\n",
                cmd, given, spec);
        return 1;
    }
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
        if (info->pass_ms[i] >= 0 && info->pass_vertices[i])
            printf("  %-13s %8.2f ms, %llu geometry vertices\n", lc_pass_name(i), info->pass_ms[i],
                   (unsigned long long)info->pass_vertices[i]);
        else if (info->pass_ms[i] >= 0)
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
