/* The renderer's public entry: create/destroy, the frame's set-up (camera,
 * attribute mapping, sizes) and the dispatch to a method by the pass plan;
 * frame_compose.c composes an image of several composites (antialias
 * samples, tiles). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "colormap.h"
#include "exact.h"
#include "foo_math.h"
#include "frame_check.h"
#include "memory.h"
#include "renderer_internal.h"

const char *lc_pass_name(int pass)
{
    static const char *names[LC_PASS_COUNT] = {"importance", "opacity", "smooth",   "opticalDepth",
                                               "accumulate", "resolve", "readback", "depthRange"};
    return pass >= 0 && pass < LC_PASS_COUNT ? names[pass] : "unknown";
}

int lc_renderer_create(const lc_renderer_desc *desc, lc_renderer **out, lc_error *err)
{
    *out = NULL;
    lc_renderer *r = calloc(1, sizeof *r);
    if (!r)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    if (desc)
        r->desc = *desc;
    const char *gl_renderer = (const char *)glGetString(GL_RENDERER);
    lc_pipeline_configure(gl_renderer);
    lc_fragment_list_configure(gl_renderer);
    lc_scratch_configure(gl_renderer);
    lc_compute_raster_configure(gl_renderer);
    lc_line_primitive_configure(r);
    lc_fragment_heads_configure(r);
    lc_exact_configure(r);
    lc_programs_configure(gl_renderer);
    r->specialize = 1;
    r->raster_path = -1;
    glCreateVertexArrays(1, &r->vao);
    /* Line ribbons are strips separated by LC_STRIP_RESTART (gpu_scene.c);
     * triangle index buffers never hold that index. */
    glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
    glEnable(GL_PROGRAM_POINT_SIZE); /* point sprites size themselves (lc_frame_point_sprites) */
    GLfloat sizes[2] = {1, 1};
    glGetFloatv(GL_POINT_SIZE_RANGE, sizes);
    r->point_size_max = sizes[1];
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, r->max_viewport);
    glGenQueries(LC_PASS_COUNT + 1, r->timer_queries);
    r->dummy_buffer = lc_gl_buffer(NULL, 0, &(uint64_t){0});

    r->colormap_count = lc_colormap_count() < 16 ? lc_colormap_count() : 16;
    glCreateTextures(GL_TEXTURE_2D, r->colormap_count, r->colormap_tex);
    for (int i = 0; i < r->colormap_count; i++) {
        const float *table = lc_colormap_table(i);
        uint8_t rgba[256 * 4];
        for (int k = 0; k < 256; k++) {
            for (int c = 0; c < 3; c++) {
                float v = table[3 * k + c];
                rgba[4 * k + c] = (uint8_t)lrintf(255.0f * (v < 0 ? 0 : v > 1 ? 1 : v));
            }
            rgba[4 * k + 3] = 255;
        }
        glTextureStorage2D(r->colormap_tex[i], 1, GL_RGBA8, 256, 1);
        glTextureSubImage2D(r->colormap_tex[i], 0, 0, 0, 256, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
        glTextureParameteri(r->colormap_tex[i], GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(r->colormap_tex[i], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(r->colormap_tex[i], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(r->colormap_tex[i], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glCreateFramebuffers(1, &r->nofb);
    /* Compile the programs every frame needs now, so shader errors surface at start-up. */
    if (!lc_renderer_fixed_program(r, PROG_P3, err) || !lc_renderer_fixed_program(r, PROG_RESOLVE, err)) {
        lc_renderer_destroy(r);
        return err ? err->code : LC_ERR_GL;
    }
    *out = r;
    return 0;
}

void lc_renderer_destroy(lc_renderer *r)
{
    if (!r)
        return;
    lc_exact_destroy(r);
    lc_context_destroy(r);
    lc_kanzler_destroy(r);
    lc_shadow_destroy(r);
    lc_smart_destroy(r);
    lc_fragment_list_release(r);
    lc_compute_raster_release(r);
    if (r->marker_program)
        glDeleteProgram(r->marker_program);
    for (int k = 0; k < PROG_GEOMETRY_KINDS; k++)
        for (int p = 0; p < 3; p++)
            for (int b = 0; b <= LC_MAX_BANDS; b++)
                for (int v = 0; v < 3; v++)
                    for (int c = 0; c < 2; c++)
                        if (r->geometry_programs[k][p][b][v][c])
                            glDeleteProgram(r->geometry_programs[k][p][b][v][c]);
    for (int k = 0; k < PROG_GEOMETRY_KINDS; k++)
        for (int p = 0; p < 3; p++)
            for (int b = 0; b <= LC_MAX_BANDS; b++)
                for (int v = 0; v < 3; v++)
                    if (r->floor_programs[k][p][b][v])
                        glDeleteProgram(r->floor_programs[k][p][b][v]);
    for (int i = 0; i < LC_SPEC_PROGRAMS; i++)
        if (r->spec_programs[i].prog)
            glDeleteProgram(r->spec_programs[i].prog);
    for (int k = 0; k < PROG_FIXED_KINDS - PROG_GEOMETRY_KINDS; k++)
        if (r->fixed_programs[k])
            glDeleteProgram(r->fixed_programs[k]);
    uint64_t b = 0;
    lc_targets_free(&r->coef_low, &b);
    lc_targets_free(&r->coef_full, &b);
    lc_targets_free(&r->accum, &b);
    lc_targets_free(&r->output, &b);
    lc_targets_free(&r->range_full, &b);
    lc_targets_free(&r->range_low, &b);
    lc_targets_free(&r->moments, &b);
    lc_targets_free(&r->reach_sums, &b);
    if (r->reach_fbo)
        glDeleteFramebuffers(1, &r->reach_fbo);
    if (r->output_depth)
        glDeleteRenderbuffers(1, &r->output_depth);
    glDeleteFramebuffers(1, &r->nofb);
    GLuint bufs[] = {
        r->element_alpha_min, r->element_alpha,   r->smooth_a,           r->smooth_b,           r->stats,
        r->dummy_buffer,      r->mass_histogram,  r->element_importance, r->point_histogram,    r->point_list,
        r->element_behind,    r->color_histogram, r->element_g,          r->important_occluded, r->line_select,
        r->line_kept,         r->top_reach};
    for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++)
        if (bufs[i])
            glDeleteBuffers(1, &bufs[i]);
    glDeleteTextures(r->colormap_count, r->colormap_tex);
    for (int i = 0; i < LC_MAX_LAYERS; i++)
        if (r->equalized_tex[i])
            glDeleteTextures(1, &r->equalized_tex[i]);
    glDeleteQueries(LC_PASS_COUNT + 1, r->timer_queries);
    if (r->fragment_query)
        glDeleteQueries(1, &r->fragment_query);
    glDeleteVertexArrays(1, &r->vao);
    lc_filter_release(r);
    for (int i = 0; i < LC_MAX_LAYERS; i++)
        if (r->line_masks[i].buffer)
            glDeleteBuffers(1, &r->line_masks[i].buffer);
    free(r->importance_cache);
    free(r->reduce_buf);
    free(r->progressive_params);
    free(r);
}

uint64_t lc_renderer_bytes(const lc_renderer *r)
{
    uint64_t points = r->point_histogram ? POINT_BINS * 4 + ((uint64_t)r->point_list_capacity + 1) * 4 : 0;
    uint64_t filter = lc_filter_bytes(r);
    uint64_t fragments = lc_fragment_list_bytes(r); /* P0's and P1's lists (fragment_list.c) */
    return r->bytes_targets + r->bytes_elements + points + filter + r->line_select_bytes + r->line_kept_bytes +
           fragments;
}

uint64_t lc_renderer_element_bytes(const lc_renderer *r)
{
    return r->bytes_elements + (uint64_t)r->importance_cache_count * sizeof(float);
}

static void ensure_element_buffers(lc_renderer *r, uint32_t count)
{
    if (count <= r->element_capacity && r->element_alpha)
        return;
    GLuint *bufs[] = {&r->element_alpha_min, &r->element_alpha, &r->smooth_a, &r->smooth_b, &r->element_behind};
    for (int i = 0; i < 5; i++) {
        if (*bufs[i])
            glDeleteBuffers(1, bufs[i]);
        glCreateBuffers(1, bufs[i]);
        glNamedBufferStorage(*bufs[i], (GLsizeiptr)(count ? count : 1) * 4, NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    if (!r->stats) {
        glCreateBuffers(1, &r->stats);
        glNamedBufferStorage(r->stats, 16, NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    r->element_capacity = count;
    r->bytes_elements = (uint64_t)(count ? count : 1) * 20 + 16;
}

/* The request was validated where it was parsed (protocol/): this guard only
 * keeps a caller that skipped that from indexing outside the renderer's
 * arrays, and names no request field. */
static int check_trusted_params(const lc_render_params *p, lc_error *err)
{
    if (p->width < 1 || p->height < 1 || p->width > 16384 || p->height > 16384 || p->foo.bands < LC_MIN_BANDS ||
        p->foo.bands > LC_MAX_BANDS || !(p->foo.resolution_scale > 0 && p->foo.resolution_scale <= 1) ||
        (unsigned)p->method >= LC_METHOD_COUNT)
        return lc_err(err, LC_ERR_INTERNAL, "render parameters were not validated (size %dx%d, %d bands, method %d)",
                      p->width, p->height, p->foo.bands, (int)p->method);
    if (p->method == LC_METHOD_SURFACE_LAYERS) /* a field's surface: lc_surface_render */
        return lc_err_field(err, LC_ERR_INVALID, "method",
                            "surface-layers renders a vector field's surface "
                            "(surface.field), not a dataset");
    return 0;
}

/* Interactive frames may skip P1-P3 and draw with the opacities the state
 * holds from earlier frames: they change slowly under a moving camera and fade
 * anyway, and the still frame that follows optimizes them again. */
static int reuse_opacities(lc_renderer *r, const lc_frame_state *state, lc_frame_info *info)
{
    lc_frame_state_upload(state, r->element_alpha);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    info->reused_opacities = 1;
    info->max_alpha_change = 0;
    info->converged = 1;
    return 0;
}

/* ---- Guard band (params.guardBand, docs/ALGORITHM.md "Perception aids"):
 * P0 "moments" and P1-P3 see a frustum widened by g of the view on each side,
 * at the optimization resolution's pixel size, so that elements just outside
 * the view have optimized opacities before they enter it (FOO §5.7.3). */
static int optimize_frame(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                          int moments, lc_error *err)
{
    double g = fs->params->foo.guard_band;
    if (!(g > 0) || fs->pixel_depth_range)
        return lc_fourier_optimize(r, fs, state, dt, info, err);
    const lc_frame_setup saved = *fs;
    int lw = fs->low_width, lh = fs->low_height;
    int gx = (int)ceil(g * lw), gy = (int)ceil(g * lh);
    int w = lw + 2 * gx, h = lh + 2 * gy;
    for (int col = 0; col < 4; col++) {
        fs->view.view_proj[4 * col] *= (float)((double)lw / w);
        fs->view.view_proj[4 * col + 1] *= (float)((double)lh / h);
    }
    /* The same world size per pixel and point splats of the same pixel size. */
    lc_render_params wide = *fs->params;
    wide.style.point_size *= (double)lh / h;
    fs->view.pixel_world *= (double)h / lh;
    fs->params = &wide;
    fs->low_width = w, fs->low_height = h;
    int rc = moments && !fs->p1_done ? lc_fourier_depth_moments(r, fs, err) : 0; /* once a frame, as P1 */
    if (!rc)
        rc = lc_fourier_optimize(r, fs, state, dt, info, err);
    int depth_moments = fs->depth_moments, p1_done = fs->p1_done;
    uint64_t p0_fragments = fs->p0_fragments; /* over the guard band too: the list's guess errs large */
    *fs = saved;
    fs->depth_moments = depth_moments;
    fs->p1_done = p1_done;
    fs->p0_fragments = p0_fragments;
    if (depth_moments)
        fs->moments_guard[0] = gx, fs->moments_guard[1] = gy;
    return rc;
}

/* The order in which a frame's passes run (and are timed and reported). */
static const int pass_order[LC_PASS_COUNT] = {LC_PASS_DEPTH_RANGE, LC_PASS_IMPORTANCE,    LC_PASS_OPACITY,
                                              LC_PASS_SMOOTH,      LC_PASS_OPTICAL_DEPTH, LC_PASS_ACCUMULATE,
                                              LC_PASS_RESOLVE,     LC_PASS_READBACK};

static int render_passes(lc_renderer *r, lc_frame_setup *fs_in, lc_frame_state *state, double dt, uint8_t *rgba,
                         double t0, lc_error *err);

/* One frame of gs alone (layers NULL) or of the n layers over scenes. */
static int render(lc_renderer *r, const lc_gpu_scene *const *scenes, const lc_layer_params *layers, int n,
                  const lc_render_params *params, lc_frame_state *state, double dt, uint8_t *rgba, lc_frame_info *info,
                  lc_error *err)
{
    double t0 = lc_now();
    const lc_gpu_scene *gs = scenes[0];
    lc_frame_info local;
    if (!info)
        info = &local;
    memset(info, 0, sizeof *info);
    for (int i = 0; i < LC_PASS_COUNT; i++)
        info->pass_ms[i] = -1;
    int rc = check_trusted_params(params, err);
    /* What the server checked when the request arrived (frame_check.h), checked again for callers that did not. */
    const lc_scene *checked[LC_MAX_LAYERS];
    for (int i = 0; i < (layers ? n : 1); i++)
        checked[i] = scenes[i]->scene;
    if (rc || (rc = lc_render_check(checked, layers, layers ? n : 1, params, r->desc.tile_size, err)) != 0)
        return rc;
    const lc_scene *s = gs->scene;
    uint32_t elements = s->elements.count;
    for (int i = 1; layers && i < n; i++)
        elements += scenes[i]->scene->elements.count;
    if (state && state->count != elements)
        return lc_err(err, LC_ERR_INVALID, "frame state has %u elements, the %s has %u", state->count,
                      layers ? "layers" : s->name, elements);
    double bounds[6];
    if (layers)
        lc_layers_bounds(scenes, n, bounds);
    else
        memcpy(bounds, s->bounds, sizeof bounds);

    lc_render_params p = *params;
    lc_frame_setup fs = {
        .params = &p, .gs = gs, .width = p.width, .height = p.height, .info = info, .element_total = elements};
    if ((rc = lc_reduce_check_method(r, p.method, err)) != 0)
        return rc;
    fs.point_sprites = r->point_sprites = lc_frame_point_sprites(r, &p, p.width, p.height);
    fs.renderer = r;
    if ((rc = lc_progressive_begin(r, &fs, err)) != 0)
        return rc;
    r->draw_yields = r->yield_cut = 0;
    r->fragment_counting = false; /* lc_fragment_hint_begin */
    fs.state = state;
    r->pull_lines = 0;     /* lc_filter_prepare sets it for a time window */
    r->line_primitive = 0; /* set below for a frame of one line dataset */
    lc_filter_frame_begin(r);
    r->context_layers = 0; /* lc_context_draw sets it */
    if (!p.has_camera)     /* the dataset's suggested view, else ParaView's default (-Z, +Y up), fitted to the bounds */
        lc_render_fit_camera(scenes, layers ? n : 1, &p.camera);
    if (!layers) {
        rc = lc_frame_resolve_mapping(&fs, err);
        if (rc == 0)
            rc = lc_line_clusters_prepare(r, &fs, err);
        if (rc)
            return rc;
        if ((rc = lc_filter_prepare(r, &fs, err)) != 0)
            return rc;
    }
    lc_camera_view(&p.camera, bounds, (double)p.width / p.height, p.height, &fs.view);
    memcpy(fs.bounds, bounds, sizeof bounds);
    double diag = 0;
    for (int i = 0; i < 3; i++)
        diag += (s->bounds[i + 3] - s->bounds[i]) * (s->bounds[i + 3] - s->bounds[i]);
    diag = sqrt(diag);
    fs.line_half_width = 0.5 * (p.style.line_width > 0 ? p.style.line_width : 0.004 * diag);
    fs.low_width = (int)ceil(p.width * p.foo.resolution_scale);
    fs.low_height = (int)ceil(p.height * p.foo.resolution_scale);
    if (fs.low_width < 1)
        fs.low_width = 1;
    if (fs.low_height < 1)
        fs.low_height = 1;

    /* One level for every pass: the optimization passes would afford a
     * coarser one at their larger pixels, but the opacities (a minimum over
     * each element's fragments) follow coverage changes closely. */
    fs.level = lc_frame_pick_level(&fs);
    fs.point_stride = s->type == LC_PRIM_POINTS && p.method != LC_METHOD_EXACT && p.detail.point_stride > 1 && !layers
                          ? p.detail.point_stride
                          : 1;
    lc_layer_setup *setups = NULL;
    if (layers) {
        setups = malloc((size_t)n * sizeof *setups);
        if (!setups)
            return lc_err(err, LC_ERR_NOMEM, "out of memory (layers)");
        if ((rc = lc_frame_layers_prepare(&fs, scenes, layers, n, setups, err)) != 0) {
            free(setups);
            return rc;
        }
    }
    lc_shadow_clip_ground(&fs, &fs.view); /* the ground may lie beyond the data's clip planes */
    rc = render_passes(r, &fs, state, dt, rgba, t0, err);
    if (rc) /* a batch cut short (a yield, an error) leaves partial sums: the still starts again at batch 1 */
        r->progressive_next = 0;
    free(setups);
    return rc;
}

/* The passes of a set-up frame, its timings and its report. */
static int render_passes(lc_renderer *r, lc_frame_setup *fs_in, lc_frame_state *state, double dt, uint8_t *rgba,
                         double t0, lc_error *err)
{
    lc_frame_setup fs = *fs_in;
    lc_render_params p = *fs.params;
    fs.params = &p;
    lc_frame_info *info = fs.info;
    int rc = 0;
    lc_pass_plan plan;
    lc_pass_plan_make(&p, state && !state->fresh, &plan);

    ensure_element_buffers(r, fs.element_total);
    int nx, ny, tiles = lc_pass_plan_tiles(&p, r->desc.tile_size, &nx, &ny);
    if (!tiles)
        lc_frame_ensure_output(r, p.width, p.height, p.method == LC_METHOD_OPAQUE);
    if ((rc = lc_point_subset_prepare(r, &fs, err)) != 0)
        return rc;
    /* Lines thin only with a frame state that holds opacities (P3 keeps the
     * value of an element without fragments, so the dropped lines' elements
     * keep theirs while a moving frame re-optimizes), with the Fourier method
     * (its P1 and P4 weight a stride), and not under MPI (a rank's lines are
     * not the whole's). */
    fs.line_stride = state && !state->fresh && p.method == LC_METHOD_FOURIER && fs.gs->scene->type == LC_PRIM_LINES &&
                             !fs.layer_count && !r->desc.reducer && p.detail.line_stride > 1
                         ? p.detail.line_stride
                         : 1;
    if ((rc = lc_line_subset_prepare(r, &fs, err)) != 0)
        return rc;
    /* Wide line strips stand for the ribbons where they can (line_primitive.c):
     * on frames that draw every segment of one dataset's strips (no layers, no
     * time window's segment-by-segment draw, no moving frame's kept lines). */
    if (!fs.layer_count && !fs.pull_lines && !(fs.kept_line_indices[0] + fs.kept_line_indices[1]) &&
        lc_frame_line_primitive(r, &fs))
        fs.line_primitive = r->line_primitive = 1;
    if (info)
        info->line_primitive = fs.line_primitive;
    r->progress_planned = r->progress_done = 0;
    for (int i = 0; i < LC_PASS_COUNT; i++)
        if (plan.run[pass_order[i]] != LC_RUN_NONE)
            r->progress_order[r->progress_planned++] = pass_order[i];
    r->progress_t0 = t0;
    lc_renderer_timestamp(r, LC_PASS_COUNT);
    info->converged = 1;
    /* Opaque context layers first: every later pass tests against their depth. */
    if ((rc = lc_context_draw(r, &fs, tiles ? LC_CONTEXT_LOW : LC_CONTEXT_FULL | LC_CONTEXT_LOW, err)) != 0)
        return rc;
    /* P0 as the plan says (pass_plan.c says why the moments skip a reusing frame). */
    if (plan.pixel_range && (rc = lc_fourier_depth_range(r, &fs, !tiles, 1, err)) != 0)
        return rc;
    int guarded = p.foo.guard_band > 0 && !plan.pixel_range; /* optimize_frame runs the moments then */
    if (plan.moments && !guarded && (rc = lc_fourier_depth_moments(r, &fs, err)) != 0)
        return rc;
    if ((rc = lc_renderer_yield_point(r, err)) != 0)
        return rc;
    lc_color_equalize_begin(r, &fs, state);
    switch (p.method) {
    case LC_METHOD_FOURIER:
    case LC_METHOD_WBOIT:
    case LC_METHOD_WEIGHTED_AVERAGE:
    case LC_METHOD_BINNING:
        rc = plan.reuse ? reuse_opacities(r, state, info)
                        : lc_clarity_optimize(r, &fs, state, dt, info, plan.moments, optimize_frame, err);
        break;
    case LC_METHOD_DIRECT:
    case LC_METHOD_KANZLER:
    case LC_METHOD_OPAQUE: break;
    case LC_METHOD_EXACT: rc = lc_render_exact(r, &fs, state, dt, rgba, info, err); break;
    default: rc = lc_err(err, LC_ERR_INVALID, "unknown method");
    }
    int samples = lc_frame_antialias_samples(&p);
    if (!rc && p.method != LC_METHOD_EXACT)
        rc = lc_renderer_yield_point(r, err);
    if (!rc && p.method == LC_METHOD_KANZLER)
        lc_kanzler_report_begin(r);
    if (!rc) /* the light's map needs this frame's opacities; P6 composites over the shadowed context */
        rc = lc_shadow_apply(r, &fs, err);
    if (!rc && tiles)
        rc = lc_frame_render_tiles(r, &fs, state, dt, nx, ny, samples, plan.pixel_range, rgba, err);
    else if (!rc && p.method != LC_METHOD_EXACT)
        rc = lc_frame_composite(r, &fs, err);
    if (!rc && !tiles && (p.method == LC_METHOD_FOURIER || p.method == LC_METHOD_DIRECT))
        rc = lc_color_equalize_end(r, &fs, state, dt, p.method == LC_METHOD_DIRECT, err);
    if (!rc && !tiles && samples <= 1)
        rc = lc_markers_draw(r, &fs, err); /* over the finished image (a no-op without time.markers) */
    if (!rc && !tiles && samples > 1)
        rc = lc_frame_antialias(r, &fs, samples, rgba, err);
    else if (!rc && !tiles)
        lc_renderer_readback(r, &fs, rgba);
    if (!rc && p.method == LC_METHOD_KANZLER) /* after every sample's P4 (tiles are refused) */
        rc = lc_kanzler_report(r, &fs, info, err);
    if (rc)
        return rc;
    lc_renderer_timestamp(r, LC_PASS_READBACK);

    /* Timestamps of passes that ran are strictly after the previous slot. */
    if (!r->desc.no_timer_queries) {
        GLuint64 start = 0, prev;
        glGetQueryObjectui64v(r->timer_queries[LC_PASS_COUNT], GL_QUERY_RESULT, &start);
        prev = start;
        for (int i = 0; i < LC_PASS_COUNT; i++) {
            int pass = pass_order[i];
            if (plan.run[pass] == LC_RUN_NONE)
                continue;
            GLuint64 t = 0;
            glGetQueryObjectui64v(r->timer_queries[pass], GL_QUERY_RESULT, &t);
            info->pass_ms[pass] = t >= prev ? (double)(t - prev) * 1e-6 : 0.0;
            info->gpu_ms += info->pass_ms[pass];
            prev = t;
        }
    }
    memcpy(info->pass_vertices, r->pass_vertices, sizeof info->pass_vertices);
    info->width = p.width, info->height = p.height;
    info->camera = p.camera;
    info->element_count = fs.element_total;
    info->lod_level = fs.level;
    info->primitives_drawn = 0;
    for (int i = 0; i < lc_frame_layer_count(&fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(&fs, i, &tmp);
        if (lf)
            info->primitives_drawn +=
                (lf->gs->levels[lf->level].primitive_count + lf->point_stride - 1) / lf->point_stride;
    }
    /* The kept points replace the ones among them that the stride drew (about 1 in point_stride). */
    info->primitives_drawn += fs.kept_points - fs.kept_points / (uint64_t)fs.point_stride;
    info->kept_points = fs.kept_points;
    info->point_sprites = fs.point_sprites && fs.gs->scene->type == LC_PRIM_POINTS;
    info->point_stride = fs.point_stride;
    info->line_stride = 1;
    info->kept_line_segments[0] = info->kept_line_segments[1] = 0;
    if (fs.kept_line_indices[0] + fs.kept_line_indices[1]) {
        /* Two indices a segment plus four a run (its first vertex, two restarts): segments only approximately. */
        const lc_gpu_level *lv = &fs.gs->levels[fs.level];
        double per = lv->index_count ? (double)lv->primitive_count / (double)lv->index_count : 0;
        info->line_stride = fs.line_stride;
        info->kept_line_segments[0] = (uint64_t)(fs.kept_line_indices[0] * per + 0.5);
        info->kept_line_segments[1] = (uint64_t)(fs.kept_line_indices[1] * per + 0.5);
        info->primitives_drawn = info->kept_line_segments[0] + info->kept_line_segments[1];
    }
    lc_fragment_hint_store(r, &fs, info->primitives_drawn, fs.gs->levels[fs.level].primitive_count);
    if (p.foo.progressive > 1 && !p.foo.batch_prefix)
        info->batch = p.foo.batch, info->batches = p.foo.progressive;
    info->pipeline_bytes = lc_renderer_bytes(r);
    info->wall_ms = (lc_now() - t0) * 1e3;
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        return lc_err(err, LC_ERR_GL, "OpenGL error 0x%04x during the frame (out of GPU memory?)", e);
    return 0;
}

int lc_render_frame(lc_renderer *r, const lc_gpu_scene *gs, const lc_render_params *params, lc_frame_state *state,
                    double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    if (params->foo.progressive <= 1 || params->foo.batch != 0 || params->foo.batch_prefix)
        return render(r, &gs, NULL, 1, params, state, dt, rgba, info, err);
    /* params.progressive with batch 0: every batch in this call, the image
     * the last one's (progressive.c), and the time to the first picture. Each
     * batch is a frame dt after the one before; a fresh state takes every
     * batch's targets whole, as a one-shot frame takes its own. */
    double t0 = lc_now(), first = 0;
    lc_render_params p = *params;
    lc_frame_info local;
    if (!info)
        info = &local;
    int rc = 0, fresh = state && lc_frame_state_is_fresh(state);
    for (int k = 1; k <= params->foo.progressive && !rc; k++) {
        p.foo.batch = k;
        if (fresh && k > 1)
            lc_frame_state_reset(state);
        rc = render(r, &gs, NULL, 1, &p, state, dt, rgba, info, err);
        if (k == 1)
            first = (lc_now() - t0) * 1e3;
    }
    if (!rc)
        info->first_batch_ms = first, info->wall_ms = (lc_now() - t0) * 1e3;
    return rc;
}

int lc_render_layers(lc_renderer *r, const lc_gpu_scene *const *scenes, const lc_layer_params *layers, int n,
                     const lc_render_params *params, lc_frame_state *state, double dt, uint8_t *rgba,
                     lc_frame_info *info, lc_error *err)
{
    if (n < 1 || n > LC_MAX_LAYERS || !scenes || !layers)
        return lc_err_field(err, LC_ERR_INVALID, "layers", "%d layers; 1 to %d are allowed", n, LC_MAX_LAYERS);
    return render(r, scenes, layers, n, params, state, dt, rgba, info, err);
}

/* After a large frame (renderer.h): lives here, beside lc_render_frame, which
 * it calls for the 8x8 frames. */
void lc_renderer_release_after(lc_renderer *r, const lc_gpu_scene *gs, const lc_render_params *p)
{
    if ((long long)p->width * p->height <= LC_LARGE_FRAME_PIXELS)
        return;
    /* Deleting the targets is not enough for a software driver (llvmpipe):
     * its context keeps the last frame's textures bound, and its binning and
     * tile state sized for them, until a draw replaces them. An 8x8 one-shot
     * frame of the same request does that for the price of its geometry. */
    /* The exact method's heads grew to this frame and its pool holds the
     * pages its fragments touched: freed, and the small frames drawn by the
     * Fourier passes, so that the next exact frame allocates them anew. */
    lc_exact_release(r);
    lc_kanzler_release(r);
    lc_render_params tiny = *p;
    /* The fragment lists, sized by this frame: the 8x8 frames would not
     * shrink them (fragment_list.c keeps the largest counts seen). */
    lc_fragment_list_release(r);
    lc_compute_raster_release_sums(r); /* sized by this frame too */
    r->fragment_seen = r->composite_seen = 0;
    tiny.width = tiny.height = 8;
    if (tiny.method == LC_METHOD_EXACT)
        tiny.method = LC_METHOD_FOURIER;
    uint8_t rgba[8 * 8 * 4];
    lc_error ignored = {0};
    for (int k = 0; k < 2; k++) /* llvmpipe's scenes let go of their references only when reused (scratch.c) */
        lc_render_frame(r, gs, &tiny, NULL, 0.0, rgba, NULL, &ignored);
    lc_targets *sets[] = {&r->coef_low,   &r->coef_full, &r->accum,   &r->output,
                          &r->range_full, &r->range_low, &r->moments, &r->reach_sums};
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; k++)
        lc_targets_free(sets[k], &r->bytes_targets);
    if (r->reach_fbo) { /* its attachments would keep the freed targets (a frame that ended inside P5) */
        glDeleteFramebuffers(1, &r->reach_fbo);
        r->reach_fbo = 0;
    }
    if (r->output_depth) { /* attached to the output's framebuffer: goes with it */
        glDeleteRenderbuffers(1, &r->output_depth);
        r->bytes_targets -= (uint64_t)r->depth_width * (uint64_t)r->depth_height * 4;
        r->output_depth = 0;
        r->depth_width = r->depth_height = 0;
    }
    glFinish();
    lc_memory_trim();
}
