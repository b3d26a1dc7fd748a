/* `lucent render`, `lucent info` and `lucent gen`: one frame to a file, a
 * dataset summary, and demo data written as PLY/OBJ. */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "cli.h"
#include "demo.h"
#include "image.h"
#include "lc_mpi.h"
#include "loaders.h"
#include "lod.h"
#include "memory.h"
#include "vtk_field.h"

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

/* The flags of `lucent render` besides the shared ones (cli.c). */
typedef struct render_args {
    const char *out, *stats;
    int frames, mpi, point_stride, uniform_points, line_stride;
    double dt, pixel_scale;
} render_args;

#define RENDER(member) LC_OPT_AT(render_args, member)
static const lc_option render_options[] = {
    {"--out", "IMG", LC_OPT_TEXT, RENDER(out), .help = "the image: .png, .jpg or .jpeg (required)"},
    {"-o", "IMG", LC_OPT_TEXT, RENDER(out), .help = NULL},
    {"--frames", "N", LC_OPT_INT, RENDER(frames), 1, 100000,
     .help = "render N frames with fading, dt = --dt, keep the last"},
    {"--dt", "S", LC_OPT_REAL, RENDER(dt), 0, 86400, .help = "time step between those frames (default 1/30 s)"},
    {"--stats", "FILE.json", LC_OPT_TEXT, RENDER(stats),
     .help = "write the (last) frame's statistics: pass times, the vertices each\n"
             "pass drew, normalization, visibility"},
    {"--mpi", NULL, LC_OPT_BOOL, RENDER(mpi),
     .help = "under mpirun/srun: each rank renders its shard, rank 0 writes the\n"
             "image (docs/MPI.md; methods fourier and direct); of line files,\n"
             "point clouds and point tables each rank reads only its share\n"
             "(LUCENT_MPI_READ=whole: every rank reads all, keeps its shard)"},
    {"--point-stride", "N", LC_OPT_INT, RENDER(point_stride), 1, 1024,
     .help = "points: draw as a session does while the camera moves: the most\n"
             "important 1/(4N) of the points in full, one in N of the rest"},
    {"--uniform-points", NULL, LC_OPT_BOOL, RENDER(uniform_points),
     .help = "with --point-stride: one in N of all points instead"},
    {"--pixel-scale", "S", LC_OPT_REAL, RENDER(pixel_scale), 0.01, 1,
     .help = "draw as a session's moving frame drawn at the fraction S of its\n"
             "view's size: point splats and time markers keep their size in the\n"
             "view's pixels (default 1, a still)"},
    {"--line-stride", "N", LC_OPT_INT, RENDER(line_stride), 1, 1024,
     .help = "lines, with --frames 2 or more: the last frame reuses the opacities\n"
             "and draws as a session does while the camera moves: the most\n"
             "important 1/(4N) of the lines in full, one in N of the rest\n"
             "(1: every line)"},
    {NULL}};

static void render_usage(FILE *f, const lc_opt_set *sets, int nsets)
{
    fprintf(f, "usage: lucent render [--request REQ.json] [--input FILE|demo:NAME] --out IMG.png|.jpg [flags]\n"
               "Renders one frame of a render request (protocol/README.md); flags override its fields.\n"
               "A request's layers[] (several datasets in one view) name each dataset as --input does.\n");
    lc_opt_usage(f, sets, nsets);
}

/* The frame's statistics as JSON (what --stats writes). */
static json_t *frame_stats_json(const lc_frame_info *info, const char *dataset, const lc_render_params *p)
{
    json_t *passes = json_object(), *vertices = json_object();
    for (int i = 0; i < LC_PASS_COUNT; i++)
        if (info->pass_ms[i] >= 0) {
            json_object_set_new(passes, lc_pass_name(i), json_real(info->pass_ms[i]));
            json_object_set_new(vertices, lc_pass_name(i), json_integer((json_int_t)info->pass_vertices[i]));
        }
    json_t *o = json_pack("{s:s, s:s, s:i, s:i, s:I, s:o, s:f, s:f, s:b, s:f}", "dataset", dataset, "method",
                          lc_method_name(p->method), "width", info->width, "height", info->height, "elements",
                          (json_int_t)info->element_count, "passMs", passes, "gpuMs", info->gpu_ms, "wallMs",
                          info->wall_ms, "converged", info->converged, "maxAlphaChange", info->max_alpha_change);
    json_object_set_new(o, "passVertices", vertices); /* what each pass's draws issued (lc_frame_info) */
    if (info->has_visibility) {
        json_object_set_new(o, "normalize",
                            json_pack("{s:s, s:f, s:f}", "mode", p->foo.normalize == LC_NORMALIZE_OFF ? "off" : "auto",
                                      "massMedian", info->mass_median, "massP95", info->mass_p95));
        json_object_set_new(o, "visibility",
                            json_pack("{s:f, s:f, s:f, s:I, s:f, s:f, s:I}", "topDecileAlpha", info->top_decile_alpha,
                                      "bottomHalfAlpha", info->bottom_half_alpha, "coveredFraction",
                                      info->covered_fraction, "visibleElements", (json_int_t)info->visible_elements,
                                      "occluderAlpha", info->occluder_alpha, "importantOccluded",
                                      info->important_occluded, "importantFragments",
                                      (json_int_t)info->important_fragments));
        if (info->has_reach) /* the fourier method's P5 measured it */
            json_object_set_new(json_object_get(o, "visibility"), "topDecileReach", json_real(info->top_decile_reach));
        json_t *layers = info->layer_count > 0 ? json_array() : NULL;
        for (int i = 0; layers && i < info->layer_count; i++)
            json_array_append_new(layers, json_pack("{s:I, s:f, s:f, s:f}", "visibleElements",
                                                    (json_int_t)info->layers[i].visible_elements, "topDecileAlpha",
                                                    info->layers[i].top_decile_alpha, "bottomHalfAlpha",
                                                    info->layers[i].bottom_half_alpha, "occluderAlpha",
                                                    info->layers[i].occluder_alpha));
        if (layers)
            json_object_set_new(json_object_get(o, "visibility"), "layers", layers);
        if (info->clarity_lambda > 0) /* params.clarity: the factors the loop settled on */
            json_object_set_new(o, "clarity",
                                json_pack("{s:f, s:f, s:i, s:i, s:b}", "lambdaFactor", info->clarity_lambda,
                                          "penaltyFactor", info->clarity_penalty, "smoothing", info->clarity_smoothing,
                                          "tries", info->clarity_tries, "reached", info->clarity_reached));
    }
    if (info->has_color_ticks) /* color.equalize: the legend's data values at 0, 1/4, ..., 1 of the bar */
        json_object_set_new(o, "colorTicks",
                            json_pack("[f, f, f, f, f]", info->color_ticks[0], info->color_ticks[1],
                                      info->color_ticks[2], info->color_ticks[3], info->color_ticks[4]));
    if (info->reductions)
        json_object_set_new(o, "mpi",
                            json_pack("{s:i, s:f, s:I}", "reductions", info->reductions, "reduceMs", info->reduce_ms,
                                      "reduceBytes", (json_int_t)info->reduce_bytes));
    if (p->method == LC_METHOD_EXACT)
        json_object_set_new(o, "exact",
                            json_pack("{s:I, s:I, s:f, s:I, s:I, s:i}", "fragments", (json_int_t)info->fragments,
                                      "dropped", (json_int_t)info->dropped_fragments, "meanLayers", info->mean_layers,
                                      "maxLayers", (json_int_t)info->max_layers, "cutLists",
                                      (json_int_t)info->cut_lists, "bands", info->exact_bands));
    return o;
}

/* `render --mpi` of a request's layers[] (docs/MPI.md "Layers"): the GL
 * context, then each layer's dataset read as --input would be under --mpi (line
 * files and point clouds in parts, anything else whole and then sharded),
 * context layers too (the ranks combine the context's nearest depth in the
 * frame), and uploaded. Collective: a failure on any rank fails every rank,
 * with err naming layers[i].dataset. */
static int open_mpi_layers(lc_mpi *mpi, const lc_request *req, const lc_cli_common *common, lc_cli_scene *cs,
                           lc_cli_gl *g, lc_error *err)
{
    memset(cs, 0, sizeof *cs);
    if (common->input || common->dataset_set) /* every rank parses the same flags: no agreement needed */
        return lc_err_field(err, LC_ERR_INVALID, "layers", "%s names one dataset; the request's layers name theirs",
                            common->input ? "--input" : "--dataset");
    int rank = lc_mpi_rank(mpi), size = lc_mpi_size(mpi);
    const char *how = getenv("LUCENT_MPI_READ");
    int rc = lc_mpi_agree(mpi, lc_cli_gl_open(common->device, g, err), err);
    cs->layer_count = lc_request_layer_count(req);
    cs->layers = req->layers ? req->layers->p : NULL;
    for (int i = 0; rc == 0 && i < lc_request_layer_count(req); i++) {
        const char *spec = req->layers->dataset[i];
        int parts = lc_scene_can_read_part(spec) && !(how && strcmp(how, "whole") == 0);
        char way[1100];
        snprintf(way, sizeof way, "layers[%d]: %s%s", i, parts ? "in parts: " : "whole", parts ? spec : "");
        if ((rc = lc_mpi_check_same(mpi, "datasets or ways of reading them", way, err)) != 0)
            break;
        lc_scene *s = NULL;
        int read_rc = parts ? lc_scene_read_file_part(spec, rank, size, &s, err) : lc_cli_open_dataset(spec, &s, err);
        if (read_rc == 0 && !parts && common->elements)
            read_rc = lc_scene_set_element_budget(s, (uint32_t)common->elements, err);
        if (read_rc) { /* named as in one process (cli_scene.c) */
            char reason[LC_ERROR_MSG_LEN];
            snprintf(reason, sizeof reason, "%s", err->msg);
            char field[32];
            snprintf(field, sizeof field, "layers[%d].dataset", i);
            lc_err_field(err, read_rc, field, "cannot open \"%.300s\": %.400s", spec, reason);
        }
        if (parts) {
            rc = lc_mpi_finalize_part(mpi, read_rc, &s, (uint32_t)common->elements, stdout, err);
        } else if ((rc = lc_mpi_agree(mpi, read_rc, err)) == 0) {
            rc = lc_mpi_shard(mpi, &s, stdout, err); /* on failure s is still the whole */
        }
        if (rc && !parts) {
            lc_scene_destroy(s);
            s = NULL;
        }
        if (rc == 0)
            cs->scenes[cs->count++] = s;
    }
    for (int i = 0; rc == 0 && i < cs->count; i++) {
        if ((rc = lc_cli_upload("render", common, cs->scenes[i], &cs->gpu[i])) != 0) /* prints its reason */
            lc_err(err, rc, "cannot upload (the reason is above)");
        if ((rc = lc_mpi_agree(mpi, rc, err)) != 0)
            lc_err_prefix(err, "layers[%d].dataset", i);
    }
    return rc;
}

/* lc_cli_render with its request, which the caller releases (layers are a shared snapshot). */
static int render_main(int argc, char **argv, lc_request *req)
{
    lc_cli_common common;
    render_args args = {.frames = 1, .point_stride = 1, .line_stride = 0, .dt = 1.0 / 30.0};
    lc_error err = {0};
    int pr = lc_cli_parse("render", render_options, &args, argc, argv, req, &common, render_usage);
    if (pr != 0)
        return pr == 1 ? 0 : 2;
    if (!args.out) {
        fprintf(stderr, "lucent render: --out IMG.png|.jpg is required (lucent render --help lists the options)\n");
        return 2;
    }
    if (args.line_stride > 0 && args.frames < 2) {
        fprintf(stderr, "lucent render: --line-stride needs --frames 2 or more (its frame reuses opacities)\n");
        return 2;
    }
    if (args.uniform_points && args.point_stride == 1) {
        fprintf(stderr, "lucent render: --uniform-points needs --point-stride > 1\n");
        return 2;
    }
    const char *out = args.out, *stats_path = args.stats;
    int frames = args.frames, use_mpi = args.mpi, point_stride = args.point_stride,
        uniform_points = args.uniform_points;
    double dt = args.dt;
    req->render.detail.point_stride = point_stride;
    req->render.detail.uniform_points = uniform_points;
    if (args.pixel_scale > 0)
        req->render.detail.pixel_scale = args.pixel_scale;
    if (lc_request_layer_count(req) > 0 &&
        (point_stride > 1 || args.line_stride > 1)) { /* every flag used or refused */
        fprintf(stderr, "lucent render: layers: %s\n",
                point_stride > 1 ? "not with --point-stride (a layered frame draws every point of its layers)"
                                 : "not with --line-stride (a layered frame draws every line of its layers)");
        return 2;
    }
    lc_scene *scene = NULL;
    lc_cli_gl g = {0};
    lc_cli_scene cs = {0}; /* the scene (or layers) rendered */
    lc_mpi *mpi = NULL;
    if (use_mpi && lc_mpi_init(&mpi, &err) != 0) {
        fprintf(stderr, "lucent render: --mpi: %s\n", err.msg);
        return 1;
    }
    int rank = mpi ? lc_mpi_rank(mpi) : 0;
    int open_rc;
    if (mpi && lc_request_layer_count(req) > 0) { /* layers: each rank keeps its shard of every layer */
        if ((open_rc = open_mpi_layers(mpi, req, &common, &cs, &g, &err)) != 0) {
            if (rank == 0)
                fprintf(stderr, "lucent render: --mpi: %s; every rank exits\n", err.msg);
            lc_cli_scene_close(&cs, &g);
            lc_mpi_finalize(mpi);
            return 1;
        }
        lc_renderer_set_reducer(g.renderer, lc_mpi_reducer(mpi));
    } else if (mpi) {
        /* Line files, point clouds and point tables (a format that can be
         * skipped through): each rank reads only its share and the ranks finalize the
         * parts together (docs/MPI.md "Loading"). Other
         * datasets: every rank loads the whole (global bounds, ranges,
         * percentiles and elements come out the same), then keeps its shard.
         * LUCENT_MPI_READ=whole forces the second way (for comparisons). */
        const char *spec = lc_cli_dataset_spec(req, &common), *how = getenv("LUCENT_MPI_READ");
        int parts = lc_scene_can_read_part(spec) && !(how && strcmp(how, "whole") == 0);
        /* Parts of different files would combine into nonsense: the same file on every rank. */
        char way[1100];
        snprintf(way, sizeof way, "%s%s", parts ? "in parts: " : "whole", parts ? spec : "");
        open_rc = lc_mpi_check_same(mpi, "datasets or ways of reading them", way, &err);
        if (open_rc == 0 && parts) { /* the GL context first, as lc_cli_open: the memory reports compare */
            open_rc = lc_mpi_agree(mpi, lc_cli_gl_open(common.device, &g, &err), &err);
            if (open_rc == 0)
                open_rc = lc_mpi_finalize_part(mpi, lc_scene_read_file_part(spec, rank, lc_mpi_size(mpi), &scene, &err),
                                               &scene, (uint32_t)common.elements, stdout, &err);
        } else if (open_rc == 0) {
            open_rc = lc_cli_open("render", req, &common, &scene, &g);
            lc_err(&err, open_rc, "cannot open the dataset or a GL context (its message is above)");
            if (lc_mpi_agree(mpi, open_rc, &err) == 0)
                open_rc = lc_mpi_shard(mpi, &scene, stdout, &err);
            else
                open_rc = 1;
        }
        if (open_rc) {
            if (rank == 0)
                fprintf(stderr, "lucent render: --mpi: %s; every rank exits\n", err.msg);
            lc_cli_gl_close(&g);
            lc_scene_destroy(scene);
            lc_mpi_finalize(mpi);
            return 1;
        }
        lc_renderer_set_reducer(g.renderer, lc_mpi_reducer(mpi));
    } else if (lc_cli_scene_open("render", req, &common, &cs, &g) != 0) {
        return 1;
    }
    int status = 1;
    lc_gpu_scene *gs = NULL;
    lc_frame_state *state = NULL;
    size_t bytes = (size_t)req->render.width * req->render.height * 4;
    uint8_t *rgba = malloc(bytes);
    lc_frame_info info;
    if (!rgba) {
        fprintf(stderr, "lucent render: out of memory\n");
        goto done;
    }
    if (mpi && !cs.count) { /* the shard (or part) this rank holds is the scene */
        if (lc_cli_upload("render", &common, scene, &gs) != 0)
            goto done;
        cs.scenes[0] = scene, cs.gpu[0] = gs, cs.count = 1;
        scene = NULL, gs = NULL;
    }
    scene = cs.scenes[0], gs = cs.gpu[0]; /* one dataset's, or the first layer's */
    if (frames > 1 && !(state = lc_cli_frame_state(&common, (uint32_t)lc_cli_scene_elements(&cs)))) {
        fprintf(stderr, "lucent render: out of memory\n");
        goto done;
    }
    double wait_ms = 0, transfer_ms = 0;
    for (int f = 0; f < frames; f++) {
        if (mpi) /* the figures of the last frame */
            lc_mpi_profile(mpi, &wait_ms, &transfer_ms);
        lc_render_params p = req->render;
        if (args.line_stride > 0 && f == frames - 1) /* a moving frame after the stills */
            p.detail.reuse_opacities = true, p.detail.line_stride = args.line_stride;
        if (lc_cli_scene_render(g.renderer, &cs, &p, state, dt, rgba, &info, &err) != 0) {
            fprintf(stderr, "lucent render: %s\n", err.msg);
            goto done;
        }
    }
    if (rank != 0) { /* the image is on rank 0 */
        status = 0;
        goto done;
    }
    int quality = req->quality;
    if (!has_suffix(out, ".png") && !has_suffix(out, ".jpg") && !has_suffix(out, ".jpeg")) {
        fprintf(stderr, "lucent render: %s: the output must end in .png, .jpg or .jpeg\n", out);
        goto done;
    }
    if (lc_image_write_file(out, rgba, req->render.width, req->render.height, quality, &err) != 0) {
        fprintf(stderr, "lucent render: %s\n", err.msg);
        goto done;
    }
    char names[1200];
    lc_cli_scene_name(&cs, names, sizeof names);
    printf("%s: %dx%d, %s, method %s, m=%d, %s estimator, %u elements\n", out, info.width, info.height, names,
           lc_method_name(req->render.method), req->render.foo.bands, lc_estimator_name(req->render.foo.estimator),
           info.element_count);
    lc_cli_print_timings(&info);
    for (int i = 0; i < cs.layer_count; i++) /* a layered frame: what each layer is */
        printf("  layer %d: %s, %llu %s, %u elements, %s%s\n", i, cs.scenes[i]->name,
               (unsigned long long)lc_scene_primitive_count(cs.scenes[i]),
               cs.scenes[i]->type == LC_PRIM_POINTS  ? "points"
               : cs.scenes[i]->type == LC_PRIM_LINES ? "segments"
                                                     : "triangles",
               cs.scenes[i]->elements.count, cs.layers[i].role == LC_LAYER_CONTEXT ? "context" : "transparent",
               cs.layers[i].visible ? "" : ", hidden");
    if (cs.layer_count == 0 && scene->type != LC_PRIM_POINTS) /* (a layer's level of detail is its own) */
        printf("  detail: level %d of %d (lod %.3g px), %llu of %llu %s\n", info.lod_level, lc_gpu_scene_levels(gs),
               req->render.detail.lod_pixels, (unsigned long long)info.primitives_drawn,
               (unsigned long long)lc_scene_primitive_count(scene),
               scene->type == LC_PRIM_LINES ? "segments" : "triangles");
    if (info.line_stride > 1)
        printf("  lines: about %llu segments of the most important lines in full, %llu of one line in %d of the "
               "others\n",
               (unsigned long long)info.kept_line_segments[0], (unsigned long long)info.kept_line_segments[1],
               info.line_stride);
    else if (cs.layer_count == 0 && info.point_stride > 1)
        printf("  detail: %llu of %llu points (stride %d, %u important ones in full)\n",
               (unsigned long long)info.primitives_drawn, (unsigned long long)lc_scene_primitive_count(scene),
               info.point_stride, info.kept_points);
    if (mpi)
        printf("  mpi: %d ranks, %d reductions, %.1f MB per rank, %.2f ms in reductions (wall)\n", lc_mpi_size(mpi),
               info.reductions, info.reduce_bytes / 1e6, info.reduce_ms);
    if (mpi) {
        lc_mpi_profile(mpi, &wait_ms, &transfer_ms);
        printf("  mpi: rank 0 waited %.2f ms for the other ranks, %.2f ms transferring (LUCENT_MPI_PROFILE=1 "
               "separates them)\n",
               wait_ms, transfer_ms);
    }
    if (info.has_visibility)
        printf("  visibility: top decile alpha %.3f, bottom half alpha %.3f, %.1f%% of pixels covered; "
               "importance mass per pixel: median %.3g, p95 %.3g; occluder alpha %.3f; important fragments hidden "
               "by importance %.1f%% (of %llu)\n",
               info.top_decile_alpha, info.bottom_half_alpha, 100.0 * info.covered_fraction, info.mass_median,
               info.mass_p95, info.occluder_alpha, 100.0 * info.important_occluded,
               (unsigned long long)info.important_fragments);
    if (info.has_visibility && info.has_reach)
        printf("  top decile reach: %.3f (its share of the importance shown over its share of the importance drawn)\n",
               info.top_decile_reach);
    if (info.batches > 0) /* params.progressive: the timings above are the last batch's */
        printf("  progressive: %d batches, first picture after %.1f ms, complete after %.1f ms (wall)\n", info.batches,
               info.first_batch_ms, info.wall_ms);
    if (info.p0_fragments_median > 0 || info.p1_subset > 1)
        printf("  importance pass (P1): every %d-th primitive, weighted %d (P0's median effective fragments per "
               "pixel %.3g; params.autoSubset)\n",
               info.p1_subset, info.p1_subset, info.p0_fragments_median);
    if (stats_path) {
        json_t *o = frame_stats_json(&info, names, &req->render);
        if (!o || json_dump_file(o, stats_path, JSON_INDENT(2) | JSON_REAL_PRECISION(6)) != 0) {
            fprintf(stderr, "lucent render: %s: cannot write the statistics\n", stats_path);
            json_decref(o);
            goto done;
        }
        json_decref(o);
    }
    if (info.exact_bands > 1)
        printf("  exact: %llu fragments at full resolution, listed in %d bands of rows (the node pool holds %llu)\n",
               (unsigned long long)info.fragments, info.exact_bands, (unsigned long long)lc_exact_pool_nodes());
    if (info.dropped_fragments)
        printf("  WARNING: %llu fragments did not fit the exact method's node pool\n",
               (unsigned long long)info.dropped_fragments);
    if (info.cut_lists)
        printf("  WARNING: the driver's loop limit stopped %llu of the exact method's list invocations part way\n",
               (unsigned long long)info.cut_lists);
    status = 0;
done:
    /* The report reaches a pipe even when the process ends in _exit (a
     * sanitizer's leak report at exit flushes no stdio buffer). */
    fflush(stdout);
    free(rgba);
    lc_frame_state_destroy(state);
    if (mpi && !cs.count) { /* the upload failed: the shard is not in cs */
        lc_gpu_scene_destroy(gs);
        lc_scene_destroy(scene);
    }
    lc_cli_scene_close(&cs, &g);
    lc_mpi_finalize(mpi);
    return status;
}

int lc_cli_render(int argc, char **argv) { return lc_cli_with_request(argc, argv, render_main); }

/* The level-of-detail ladder of a line or surface scene and what its GPU
 * buffers cost next to the scene's own arrays. */
static void print_detail_levels(const lc_scene *s)
{
    lc_lod lod;
    lc_error err = {0};
    if (s->type == LC_PRIM_POINTS || lc_lod_plan(s, &lod, &err) != 0)
        return;
    const char *what = s->type == LC_PRIM_LINES ? "segments" : "triangles";
    printf("detail      %d levels:", lod.count);
    printf(" %llu %s (full)", (unsigned long long)lod.levels[0].primitives, what);
    for (int i = 1; i < lod.count; i++)
        printf(", %llu within %.3g", (unsigned long long)lod.levels[i].primitives, lod.levels[i].error);
    printf("\n            %.3f MB of level buffers (the scene's arrays: %.3f MB)\n", lc_lod_extra_bytes(s, &lod) / 1e6,
           lc_scene_bytes(s) / 1e6);
}

/* `lucent info` of a vector field (lc_field_is_source): grid, bounds, time span, magnitude range. */
static int print_field_info(const char *spec)
{
    lc_error err = {0};
    lc_field *f = NULL;
    double t0 = lc_now();
    if (lc_field_open(spec, &f, &err) != 0) {
        fprintf(stderr, "lucent info: %s\n", err.msg);
        return 1;
    }
    double ms = (lc_now() - t0) * 1e3;
    printf("dataset     %s\n", f->name);
    printf("type        vector field (%s)\n",
           f->time_dependent ? "time-dependent: path surfaces" : "steady: stream surfaces");
    if (f->kind == LC_FIELD_ANALYTIC)
        printf("grid        analytic\n");
    else
        printf("grid        %s, %u x %u x %u nodes\n", lc_field_kind_name(f->kind), f->dims[0], f->dims[1], f->dims[2]);
    printf("bounds      [%g, %g] x [%g, %g] x [%g, %g]\n", f->bounds[0], f->bounds[3], f->bounds[1], f->bounds[4],
           f->bounds[2], f->bounds[5]);
    if (f->time_dependent)
        printf("time        [%g, %g]\n", f->t0, f->t1);
    printf("magnitude   [%g, %g]%s\n", f->mag_min, f->mag_max,
           f->kind == LC_FIELD_ANALYTIC ? " (on a 33^3 lattice at the start time)" : " (at the grid nodes)");
    if (f->vectors_name[0])
        printf("vectors     %s\n", f->vectors_name);
    printf("loaded in   %.1f ms\n", ms);
    printf("memory      %.3f MB\n", lc_field_bytes(f) / 1e6);
    lc_field_destroy(f);
    return 0;
}

int lc_cli_info(int argc, char **argv)
{
    static const lc_option none[] = {{NULL}};
    lc_opt_set set = {none, NULL};
    const char *spec = NULL;
    int npos = 0;
    int pr = lc_opt_parse("info", &set, 1, argc, argv, &spec, 1, &npos);
    if (pr != 0 || !spec) {
        if (pr <= 0 || !lc_cli_has_flag(argc, argv, "--list-flags"))
            fprintf(pr > 0 ? stdout : stderr,
                    "usage: lucent info FILE|demo:NAME[?count=N&seed=S]\n"
                    "  (vector fields: demo:tornado-flow, demo:abc-flow, demo:shear-flow, demo:double-gyre-flow or\n"
                    "  a STRUCTURED_POINTS/RECTILINEAR_GRID .vtk or a gridded u/v/w .nc)\n");
        return pr > 0 ? 0 : 2;
    }
    if (lc_field_is_source(spec))
        return print_field_info(spec);
    lc_error err = {0};
    lc_scene *s = NULL;
    double t0 = lc_now();
    if (lc_cli_open_dataset(spec, &s, &err) != 0) {
        fprintf(stderr, "lucent info: %s\n", err.msg);
        return 1;
    }
    double ms = (lc_now() - t0) * 1e3;
    printf("dataset     %s\n", s->name);
    printf("type        %s\n", lc_prim_type_name(s->type));
    printf("vertices    %u\n", s->vertex_count);
    if (s->type == LC_PRIM_LINES)
        printf("lines       %u (%llu segments)\n", s->line_count, (unsigned long long)lc_scene_primitive_count(s));
    if (s->type == LC_PRIM_TRIANGLES)
        printf("triangles   %u\n", s->triangle_count);
    printf("bounds      [%g, %g] x [%g, %g] x [%g, %g]\n", s->bounds[0], s->bounds[3], s->bounds[1], s->bounds[4],
           s->bounds[2], s->bounds[5]);
    printf("elements    %u (adjacency %u)\n", s->elements.count, s->elements.adjacency_count);
    print_detail_levels(s);
    /* Which path the additive passes take (compute_raster.c's rule; the
     * device is known only once a context exists, so both kinds are named). */
    printf("P4, P5      %s / %s on a software rasterizer (llvmpipe), %s / %s on a GPU%s\n",
           lc_raster_path_name("llvmpipe", LC_RASTER_P4, s->type),
           lc_raster_path_name("llvmpipe", LC_RASTER_P5, s->type), lc_raster_path_name("GPU", LC_RASTER_P4, s->type),
           lc_raster_path_name("GPU", LC_RASTER_P5, s->type),
           getenv("LUCENT_COMPUTE_RASTER") ? " (LUCENT_COMPUTE_RASTER)" : "");
    if (s->type == LC_PRIM_LINES)
        printf("segments    %s%s\n", lc_line_path_name(),
               getenv("LUCENT_LINE_PRIMITIVE") ? " (LUCENT_LINE_PRIMITIVE)" : "");
    printf("rgb         %s\n", lc_scene_has_rgb(s) ? "yes" : "no");
    printf("importance  %s (default)\n", s->default_importance[0] ? s->default_importance : "(none: g = 1)");
    printf("color       %s (default)\n", s->default_color);
    printf("attributes  %d\n", s->attribute_count);
    for (int i = 0; i < s->attribute_count; i++)
        printf("  %-20s [%g, %g]  2nd-98th percentiles [%g, %g]  auto range [%g, %g]%s%s\n", s->attributes[i].name,
               s->attributes[i].min, s->attributes[i].max, s->attributes[i].p02, s->attributes[i].p98,
               s->attributes[i].auto_lo, s->attributes[i].auto_hi,
               s->attributes[i].smaller_matters ? "  (smaller matters: importance inverted)" : "",
               s->attributes[i].categorical ? "  (class labels: not a default importance)" : "");
    printf("loaded in   %.1f ms\n", ms);
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("memory      %.3f MB in the scene's arrays, peak RSS %.1f MB\n", lc_scene_bytes(s) / 1e6,
           ru.ru_maxrss / 1e3);
    /* Once served: the GPU buffers (estimated, no GL needed) and the state. */
    lc_cli_common compact = {0};
    lc_cli_print_memory(s, NULL, &compact);
    lc_memory_report ex;
    lc_memory_report_of(s, NULL, &(lc_gpu_scene_desc){.exact_positions = 1}, 1, 1, &ex);
    printf("  with --exact-positions: GPU buffers %.2f bytes per vertex\n",
           s->vertex_count ? (double)ex.gpu.total / s->vertex_count : 0.0);
    lc_scene_destroy(s);
    return 0;
}

/* The flags of `lucent gen`. */
typedef struct gen_args {
    const char *out;
    long long count, seed;
    const char *seed_line;                   /* vector fields: the seed polyline */
    const char *seeding, *seeds, *direction; /* ... or a streamline set, and the way curves run */
    double separation;
    double step, length;
    int mesh;     /* vector fields: the meshed reference instead of curves */
    double split; /* ... its insertion distance */
} gen_args;

#define GEN(member) LC_OPT_AT(gen_args, member)
static const lc_option gen_options[] = {
    {"--out", "FILE", LC_OPT_TEXT, GEN(out), .help = "the file: .ply, .obj or .vtk (required)"},
    {"-o", "FILE", LC_OPT_TEXT, GEN(out), .help = NULL},
    {"--count", "N", LC_OPT_INT, GEN(count), 1, 1e10,
     .help = "lines, points or grid size of a demo (default: the demo's)"},
    {"--seed", "S", LC_OPT_INT, GEN(seed), 0, 9007199254740992.0,
     .help = "random seed of a demo (default: the demo's)"},
    {"--seed-line", "X,Y,Z;X,Y,Z", LC_OPT_TEXT, GEN(seed_line),
     .help = "vector fields: the seed polyline the curves start from (--count curves, default 64)"},
    {"--seeding", "KIND", LC_OPT_TEXT, GEN(seeding),
     .help = "vector fields: a streamline set seeded at points, a rake, a box or density (evenly spaced)"},
    {"--seeds", "X,Y,Z;...", LC_OPT_TEXT, GEN(seeds),
     .help = "with --seeding: the points, a rake's two ends, or a box's two corners (default: the field's box)"},
    {"--separation", "D", LC_OPT_REAL, GEN(separation), 1e-12, 1e12,
     .help = "with --seeding density: the least distance of a new seed to the lines so far (default: automatic)"},
    {"--direction", "DIR", LC_OPT_TEXT, GEN(direction),
     .help = "vector fields: forward (default), backward or both (two-way curves through the seeds)"},
    {"--step", "H", LC_OPT_REAL, GEN(step), -1e9, 1e9,
     .help = "vector fields: RK4 time step, negative = backward (default: automatic)"},
    {"--length", "L", LC_OPT_REAL, GEN(length), 1e-9, 1e12,
     .help = "vector fields: arc length of a curve (default: 2 domain diagonals)"},
    {"--mesh", NULL, LC_OPT_BOOL, GEN(mesh),
     .help = "vector fields: the surface as a triangle mesh with front refinement (the meshed reference)"},
    {"--split", "D", LC_OPT_REAL, GEN(split), 1e-12, 1e12,
     .help = "with --mesh: insert a particle where neighbours drift farther apart (default: diagonal / 200)"},
    {NULL}};

int lc_cli_gen(int argc, char **argv)
{
    gen_args args = {0};
    const char *name = NULL;
    int npos = 0;
    lc_opt_set set = {gen_options, &args};
    int pr = lc_opt_parse("gen", &set, 1, argc, argv, &name, 1, &npos);
    if (pr < 0)
        return 2;
    if (pr > 0 || !name || !args.out) {
        FILE *f = pr > 0 ? stdout : stderr;
        if (pr > 0 && lc_cli_has_flag(argc, argv, "--list-flags"))
            return 0;
        fprintf(
            f,
            "usage: lucent gen NAME -o FILE.ply|FILE.obj|FILE.vtk [--count N] [--seed S]\n"
            "       lucent gen DATASET -o FILE.ply|FILE.obj|FILE.vtk   (a file or demo:NAME?count=N: converts)\n"
            "       lucent gen FIELD --seed-line X,Y,Z;X,Y,Z -o FILE.vtk [--count CURVES] [--step H] [--length L]\n"
            "         (the curves of an integral surface: FIELD is demo:abc-flow, ... or a grid .vtk)\n"
            "       lucent gen FIELD --seeding points|rake|box|density [--seeds X,Y,Z;...] -o FILE.vtk [--count N]\n"
            "         [--direction forward|backward|both] [--separation D]   (a streamline set)\n"
            "       lucent gen FIELD --seed-line X,Y,Z;X,Y,Z --mesh -o FILE.obj [--split D] [--step H] [--length L]\n"
            "         (the surface as a triangle mesh, front refinement: the meshed reference)\n");
        lc_opt_usage(f, &set, 1);
        fprintf(f, "demos:");
        for (const char *const *d = lc_demo_names(); *d; d++)
            fprintf(f, "\n  %-8s %s", *d, lc_demo_description(*d));
        fprintf(f, "\n");
        return pr > 0 ? 0 : 2;
    }
    const char *out = args.out;
    lc_demo_desc desc = {.count = (uint64_t)args.count, .seed = (uint64_t)args.seed};
    const char *bare = strncmp(name, "demo:", 5) == 0 ? name + 5 : name;
    lc_error err = {0};
    lc_scene *s = NULL;
    /* A demo name takes --count/--seed; any other dataset (a file in a format
     * Lucent reads, demo:NAME?count=N) is loaded and written: a converter. */
    int rc =
        lc_field_is_source(name)
            ? (args.mesh && (args.seeding || args.seeds || args.direction || args.separation || args.step < 0)
                   ? lc_err(&err, LC_ERR_INVALID,
                            "--mesh meshes the forward surface of --seed-line: --seeding, --seeds, --direction, "
                            "--separation and a negative --step do not apply")
               : args.mesh ? lc_cli_mesh_scene(name, args.seed_line, args.split, args.step, args.length, &s, &err)
               : args.count > 100000 ? lc_err(&err, LC_ERR_LIMIT, "--count: at most 100000 curves")
               : (args.seeds || args.separation) && !args.seeding
                   ? lc_err(&err, LC_ERR_INVALID, "--seeds and --separation need --seeding")
                   : lc_cli_trace_scene(name, args.seed_line,
                                        &(lc_cli_streamlines){.curves = args.count ? (uint32_t)args.count : 64,
                                                              .step = args.step,
                                                              .length = args.length,
                                                              .seeding = args.seeding,
                                                              .seeds = args.seeds,
                                                              .direction = args.direction,
                                                              .separation = args.separation},
                                        &s, &err))
        : args.seed_line || args.step || args.length || args.mesh || args.split || args.seeding || args.seeds ||
                args.direction || args.separation
            ? lc_err(&err, LC_ERR_INVALID,
                     "%s: --seed-line, --seeding, --seeds, --direction, --separation, --step, --length, --mesh and "
                     "--split apply to vector fields only",
                     name)
        : lc_demo_description(bare) ? lc_demo_create(bare, &desc, &s, &err)
        : desc.count || desc.seed
            ? lc_err(&err, LC_ERR_INVALID, "%s: --count and --seed apply to demo names only", name)
            : lc_cli_open_dataset(name, &s, &err);
    if (rc != 0) {
        fprintf(stderr, "lucent gen: %s\n", err.msg);
        return 1;
    }
    if (has_suffix(out, ".ply"))
        rc = lc_save_ply(s, out, &err);
    else if (has_suffix(out, ".obj"))
        rc = lc_save_obj(s, out, &err);
    else if (has_suffix(out, ".vtk"))
        rc = lc_save_vtk(s, out, &err);
    else
        rc = lc_err(&err, LC_ERR_INVALID, "%s: the output must end in .ply, .obj or .vtk", out);
    if (rc)
        fprintf(stderr, "lucent gen: %s\n", err.msg);
    else
        printf("%s: %s, %u vertices, %llu primitives\n", out, s->name, s->vertex_count,
               (unsigned long long)lc_scene_primitive_count(s));
    lc_scene_destroy(s);
    return rc ? 1 : 0;
}
