/* Pipeline plumbing shared by every method: render targets, the geometry
 * binding and draw of a pass, blending set-ups, resolve and readback. */
#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "gl_context.h"
#include "renderer_internal.h"

static uint64_t texel_bytes(GLenum format)
{
    return format == GL_RGBA32F ? 16u : format == GL_RGBA16F || format == GL_RG32F ? 8u : 4u;
}

void lc_targets_free(lc_targets *t, uint64_t *bytes)
{
    if (t->fbo)
        glDeleteFramebuffers(1, &t->fbo);
    if (t->count)
        glDeleteTextures(t->count, t->tex);
    uint64_t px = (uint64_t)t->width * (uint64_t)t->height;
    *bytes -= px * (uint64_t)t->count * texel_bytes(t->format);
    memset(t, 0, sizeof *t);
}

void lc_targets_ensure(lc_targets *t, int w, int h, int count, GLenum format, uint64_t *bytes)
{
    if (t->fbo && t->width == w && t->height == h && t->count == count && t->format == format)
        return;
    lc_targets_free(t, bytes);
    t->width = w, t->height = h, t->count = count, t->format = format;
    glCreateFramebuffers(1, &t->fbo);
    glCreateTextures(GL_TEXTURE_2D, count, t->tex);
    GLenum draw[LC_MAX_COEF_TARGETS];
    for (int i = 0; i < count; i++) {
        glTextureStorage2D(t->tex[i], 1, format, w, h);
        glTextureParameteri(t->tex[i], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t->tex[i], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glNamedFramebufferTexture(t->fbo, GL_COLOR_ATTACHMENT0 + i, t->tex[i], 0);
        draw[i] = GL_COLOR_ATTACHMENT0 + i;
    }
    glNamedFramebufferDrawBuffers(t->fbo, count, draw);
    *bytes += (uint64_t)w * (uint64_t)h * (uint64_t)count * texel_bytes(format);
}

void lc_targets_clear(const lc_targets *t, const float *value)
{
    static const float zero[4] = {0, 0, 0, 0};
    for (int i = 0; i < t->count; i++)
        glClearNamedFramebufferfv(t->fbo, GL_COLOR, i, value ? value : zero);
}

/* Reports the pass that ended at timestamp slot (LC_PASS_COUNT: the frame's
 * start) to desc.progress. A pass that is not in the plan, or that runs again
 * (antialias samples), reports nothing, so done only grows. */
static void report_progress(lc_renderer *r, int slot)
{
    if (!r->desc.progress || r->progress_planned == 0)
        return;
    int done = 0;
    if (slot < LC_PASS_COUNT) {
        for (int i = 0; i < r->progress_planned; i++)
            if (r->progress_order[i] == slot)
                done = i + 1;
        if (done <= r->progress_done)
            return;
        /* GL queues the passes: a slow frame waits for this one, so that what
         * it reports has run; a fast frame never waits. */
        if ((lc_now() - r->progress_t0) * 1e3 > LC_PROGRESS_SYNC_MS)
            glFinish();
    }
    r->progress_done = done;
    int next = done < r->progress_planned ? r->progress_order[done] : -1;
    r->desc.progress(r->desc.progress_ctx, next, done, r->progress_planned);
}

void lc_renderer_timestamp(lc_renderer *r, int slot)
{
    if (!r->desc.no_timer_queries)
        glQueryCounter(r->timer_queries[slot], GL_TIMESTAMP);
    /* The draws since the last timestamp were this pass's (a pass that runs
     * again, per tile or sample, adds); the frame's start begins the count. */
    if (slot < LC_PASS_COUNT)
        r->pass_vertices[slot] += r->vertices_issued - r->vertices_mark;
    else
        memset(r->pass_vertices, 0, sizeof r->pass_vertices);
    r->vertices_mark = r->vertices_issued;
    report_progress(r, slot);
}

void lc_renderer_set_tile_size(lc_renderer *r, int tile_size) { r->desc.tile_size = tile_size > 0 ? tile_size : 0; }

void lc_renderer_set_work(lc_renderer *r, lc_work_budget *work) { r->work = work; }

int lc_renderer_yield_point(lc_renderer *r, lc_error *err)
{
    bool collective = r->desc.reducer && r->desc.reducer->size > 1;
    if (r->work && !collective && lc_work_charge_elapsed(r->work)) { /* the work ran past its budget */
        r->yield_cut = 0;
        return lc_work_err(r->work, err, "the frame");
    }
    if (r->yield_cut) { /* a draw of this pass ended at a batch (batch_yield) */
        r->yield_cut = 0;
        return lc_err(err, LC_ERR_CANCELLED, "the frame yielded (pre-empted during a pass)");
    }
    if (!r->desc.yield || (r->desc.reducer && r->desc.reducer->size > 1))
        return 0;
    /* What is queued runs now, not while the caller waits (or after it gave up). */
    if ((lc_now() - r->progress_t0) * 1e3 > LC_PROGRESS_SYNC_MS)
        glFinish();
    if (!r->desc.yield(r->desc.yield_ctx))
        return 0;
    return lc_err(err, LC_ERR_CANCELLED, "the frame yielded (pre-empted between passes)");
}

double lc_frame_focal_distance(const lc_frame_setup *fs)
{
    double focal = 0;
    for (int i = 0; i < 3; i++)
        focal += (fs->params->camera.focal_point[i] - fs->view.eye[i]) * fs->view.dir[i];
    return focal;
}

/* A splat's radius and weight (lc_point_splat) from the radius the still
 * draws in this pass, the frame's fraction s of its view and its stride n. */
static void splat_size(double still, double s, double n, double *radius, double *weight)
{
    double a = still * s, want = a * sqrt(n);
    double base = a > POINT_RADIUS_FLOOR ? a : POINT_RADIUS_FLOOR;
    double most = s < 1 ? SPLAT_SPREAD * base : base;
    double r = want > POINT_RADIUS_FLOOR ? want : POINT_RADIUS_FLOOR;
    *radius = r < most ? r : most;
    *weight = n * (a / *radius) * (a / *radius);
}

/* The radius a still draws a splat with in a pass of pass_h of out_h rows. */
static double still_radius(const lc_render_params *p, int pass_h, int out_h)
{
    double r = 0.5 * p->style.point_size * (double)pass_h / out_h;
    return r > POINT_RADIUS_FLOOR ? r : POINT_RADIUS_FLOOR;
}

int lc_frame_point_sprites(const lc_renderer *r, const lc_render_params *p, int frame_width, int frame_height)
{
    const char *e = getenv("LUCENT_POINT_SPRITES"); /* 0: quads always */
    int allowed = !(e && e[0] == '0');
    /* The widest splat of the frame: at full resolution, with the request's
     * stride (the frame's is at most that; a splat widens with its stride). */
    double radius, weight;
    splat_size(still_radius(p, 1, 1), lc_point_scale(p), p->detail.point_stride > 1 ? p->detail.point_stride : 1,
               &radius, &weight);
    int guard = (int)ceil(radius) + 1;
    return allowed && 2 * radius <= r->point_size_max && frame_width + 2 * guard <= r->max_viewport[0] &&
           frame_height + 2 * guard <= r->max_viewport[1];
}

unsigned lc_renderer_weight(int subset) { return subset > 0 ? (unsigned)subset : 1u; }

unsigned lc_renderer_subset(const lc_frame_setup *fs, int subset)
{
    unsigned n = lc_renderer_weight(subset);
    return fs->gs->scene->type == LC_PRIM_POINTS && fs->point_stride > 1 ? n * (unsigned)fs->point_stride : n;
}

double lc_point_scale(const lc_render_params *p)
{
    double s = p->detail.pixel_scale;
    return s > 0 && s < 1 ? s : 1.0;
}

void lc_point_splat(const lc_frame_setup *fs, int pass_h, int out_h, int listed, double *radius, double *weight)
{
    double n = !listed && fs->point_stride > 1 ? fs->point_stride : 1;
    splat_size(still_radius(fs->params, pass_h, out_h), lc_point_scale(fs->params), n, radius, weight);
}

void lc_renderer_bind_terms(GLuint prog, const lc_importance_terms *t)
{
    lc_uniform_i(prog, "u_importance_terms", t->count);
    if (t->count <= 0)
        return;
    float range[LC_MAX_IMPORTANCE_TERMS][2], weight[LC_MAX_IMPORTANCE_TERMS];
    for (int i = 0; i < t->count; i++) {
        range[i][0] = (float)t->range[i][0], range[i][1] = (float)t->range[i][1];
        weight[i] = (float)t->weight[i];
    }
    glProgramUniform1iv(prog, glGetUniformLocation(prog, "u_term_attr"), t->count, t->attr);
    glProgramUniform2fv(prog, glGetUniformLocation(prog, "u_term_range"), t->count, &range[0][0]);
    glProgramUniform1fv(prog, glGetUniformLocation(prog, "u_term_weight"), t->count, weight);
    glProgramUniform1iv(prog, glGetUniformLocation(prog, "u_term_invert"), t->count, t->invert);
    lc_uniform_f(prog, "u_term_norm", t->norm);
    lc_uniform_i(prog, "u_term_penalty", t->penalty);
}

/* Transfer functions: point i of the importance curve in u_curve[i].xy, of
 * the colour curve in .zw (one vec4 per point keeps the uniform count low). */
void lc_renderer_bind_curves(GLuint prog, const lc_importance_terms *t, const lc_curve *color)
{
    int n = t->curve_count > color->count ? t->curve_count : color->count;
    glProgramUniform2i(prog, glGetUniformLocation(prog, "u_curve_n"), t->curve_count, color->count);
    if (n <= 0)
        return;
    float points[LC_MAX_CURVE_POINTS][4] = {{0}};
    for (int i = 0; i < n; i++) {
        if (i < t->curve_count)
            points[i][0] = t->curve[i][0], points[i][1] = t->curve[i][1];
        if (i < color->count)
            points[i][2] = (float)color->points[i][0], points[i][3] = (float)color->points[i][1];
    }
    glProgramUniform4fv(prog, glGetUniformLocation(prog, "u_curve"), n, &points[0][0]);
}

void lc_renderer_bind_geometry(lc_renderer *r, GLuint prog, const lc_frame_setup *fs, int w, int h, int subset)
{
    const lc_gpu_scene *gs = fs->gs;
    const lc_view *v = &fs->view;
    const lc_render_params *p = fs->params;
    const lc_gpu_level *level = &gs->levels[fs->level];
    /* A full-resolution pass of a tile projects the whole frame, shifted so
     * that the tile's pixels land on the tile-sized target. */
    int tile = fs->tiled && w == fs->width && h == fs->height;
    int vx = tile ? -fs->tile_origin[0] : 0, vy = tile ? -fs->tile_origin[1] : 0;
    if (tile)
        w = fs->frame_width, h = fs->frame_height;
    int out_h = fs->tiled ? fs->frame_height : fs->height;
    lc_renderer_check_spec(r, prog, fs);
    glUseProgram(prog);
    glBindVertexArray(r->vao);
    int line_strips = fs->line_primitive && gs->scene->type == LC_PRIM_LINES; /* line_primitive.c */
    glVertexArrayElementBuffer(r->vao, line_strips ? level->line_indices : level->indices);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_POSITIONS, gs->positions);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAMES, gs->frames);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ATTRIBUTES, gs->attributes);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_COLORS, gs->colors);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_VERTEX_ELEMENTS, gs->vertex_elements);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_VERTEX_WEIGHTS, gs->vertex_weights);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_INDICES, level->indices);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA_MIN, r->element_alpha_min);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA, r->element_alpha);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_POSITION_CHUNKS, gs->position_chunks);
    lc_uniform_i(prog, "u_compact", gs->exact ? 0 : 1);
    lc_uniform_i(prog, "u_blend", (int)gs->blend);
    lc_uniform_u(prog, "u_element_offset", fs->element_offset);
    int na = gs->scene->attribute_count;
    if (na > 0) {
        glProgramUniform1uiv(prog, glGetUniformLocation(prog, "u_attr_offset"), na, gs->attr_offset);
        glProgramUniform1iv(prog, glGetUniformLocation(prog, "u_attr_format"), na, gs->attr_format);
        glProgramUniform2fv(prog, glGetUniformLocation(prog, "u_attr_decode"), na, &gs->attr_decode[0][0]);
    }
    glBindTextureUnit(TEX_COLORMAP, lc_renderer_colormap_texture(r, fs));

    glProgramUniformMatrix4fv(prog, glGetUniformLocation(prog, "u_view"), 1, GL_FALSE, v->view);
    glProgramUniformMatrix4fv(prog, glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, v->view_proj);
    lc_uniform_v3(prog, "u_eye", v->eye);
    lc_uniform_v3(prog, "u_view_dir", v->dir);
    lc_uniform_i(prog, "u_ortho", p->camera.parallel_projection ? 1 : 0);
    lc_uniform_v2(prog, "u_viewport", w, h);
    /* Pixel size scales with this pass's resolution relative to the output. */
    lc_uniform_f(prog, "u_pixel_world", v->pixel_world * (double)out_h / h);
    double focal = lc_frame_focal_distance(fs);
    lc_uniform_f(prog, "u_focal_dist", focal > 0 ? focal : 1);
    lc_uniform_f(prog, "u_line_half_width", fs->line_half_width);
    lc_uniform_f(prog, "u_min_half_pixels", 0.5 * (p->style.min_line_pixels > 0 ? p->style.min_line_pixels : 1.0));
    double radius = 1, weight = 1, listed_radius = 1, listed_weight = 1;
    if (gs->scene->type == LC_PRIM_POINTS) {
        lc_point_splat(fs, h, out_h, 0, &radius, &weight);
        lc_point_splat(fs, h, out_h, 1, &listed_radius, &listed_weight);
    }
    lc_uniform_f(prog, "u_point_radius_px", radius);
    lc_uniform_f(prog, "u_point_list_radius_px", listed_radius);
    lc_uniform_v2(prog, "u_point_weight", weight, listed_weight);
    /* Point sprites (lc_frame_point_sprites): GL drops a point whose centre
     * lies outside the viewport, so the viewport reaches a splat's radius and
     * a pixel beyond the target on each side and the projection shrinks to
     * match (u_clip_scale): every pixel stays where it was, and a splat
     * centred just outside still draws the part that reaches in. */
    int guard = 0;
    if (fs->point_sprites && gs->scene->type == LC_PRIM_POINTS) {
        guard = (int)ceil(radius) + 1;
        int room =
            (r->max_viewport[0] - w < r->max_viewport[1] - h ? r->max_viewport[0] - w : r->max_viewport[1] - h) / 2;
        guard = guard < room ? guard : room > 0 ? room : 0;
    }
    lc_uniform_v2(prog, "u_clip_scale", (double)w / (w + 2 * guard), (double)h / (h + 2 * guard));
    lc_uniform_u(prog, "u_vertex_count", gs->scene->vertex_count);
    lc_uniform_u(prog, "u_subset", lc_renderer_subset(fs, subset));
    lc_uniform_u(prog, "u_point_jitter",
                 gs->scene->type == LC_PRIM_POINTS && fs->point_stride > 1 ? lc_renderer_subset(fs, subset) : 1);
    lc_uniform_i(prog, "u_keep_bin", fs->kept_points ? fs->keep_bin : POINT_BINS + 1);
    lc_uniform_i(prog, "u_point_list", 0);
    lc_uniform_i(prog, "u_line_mask", fs->line_mask);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_LINE_MASK, fs->line_mask ? fs->line_mask_buffer : r->dummy_buffer);
    if (fs->kept_points)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_POINT_LIST, r->point_list);
    lc_uniform_i(prog, "u_importance_attr", fs->importance_attr);
    lc_uniform_v2(prog, "u_importance_range", fs->importance_range[0], fs->importance_range[1]);
    lc_uniform_f(prog, "u_importance_exp", fs->importance_exponent);
    lc_renderer_bind_terms(prog, &fs->terms);
    lc_renderer_bind_curves(prog, &fs->terms, &p->color.curve);
    lc_uniform_i(prog, "u_filtered", fs->filtered);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_VISIBLE, fs->filtered ? fs->filter_mask : r->dummy_buffer);
    lc_uniform_i(prog, "u_color_mode", fs->color_mode);
    lc_uniform_i(prog, "u_color_attr", fs->color_attr);
    lc_uniform_v2(prog, "u_color_range", fs->color_range[0], fs->color_range[1]);
    lc_uniform_i(prog, "u_shading", p->style.shading == LC_SHADING_NONE ? 1 : 0);
    lc_uniform_f(prog, "u_silhouette_exponent", p->style.silhouette_exponent); /* read by compositing passes */
    lc_uniform_v2(prog, "u_depth_range", v->depth_min, v->depth_max);
    /* Per pixel, the nearest and farthest fragment sit at d = 1/4 and 3/4: half a
     * period apart both ways, where the truncated series of one step is exact at
     * the other for every m (its error sum_{k>m} sin(2 pi k x)/(pi k) vanishes at
     * x = 1/2), so the ends of a pixel's stack cannot disturb each other. */
    lc_uniform_f(prog, "u_depth_margin", fs->pixel_depth_range ? LC_PIXEL_DEPTH_MARGIN : p->foo.depth_margin);
    lc_uniform_i(prog, "u_pixel_depth_range", fs->pixel_depth_range);
    /* The moments live at the optimization resolution; a full-resolution pass
     * reads the texel its pixel falls in, as its projection and evaluation both do. */
    lc_uniform_i(prog, "u_depth_moments", fs->depth_moments);
    /* Opaque context (context.c): the depth of this pass's resolution; the
     * context pass itself runs before the textures are set. */
    GLuint context_depth = tile || (w == fs->width && h == fs->height) ? fs->context_depth[0] : fs->context_depth[1];
    lc_uniform_i(prog, "u_context_depth", context_depth ? 1 : 0);
    if (context_depth)
        glBindTextureUnit(TEX_CONTEXT_DEPTH, context_depth);
    if (fs->depth_moments) {
        glBindTextureUnit(TEX_DEPTH_MOMENTS, r->moments.tex[0]);
        lc_uniform_v2(prog, "u_moments_scale", (double)fs->low_width / w, (double)fs->low_height / h);
        lc_uniform_v2(prog, "u_moments_offset", fs->moments_guard[0], fs->moments_guard[1]);
        lc_uniform_v2(prog, "u_pixel_origin", -vx, -vy); /* the frame's pixel of the target's (0, 0) */
    }
    if (fs->pixel_depth_range)
        glBindTextureUnit(TEX_PIXEL_RANGE,
                          tile || (w == fs->width && h == fs->height) ? r->range_full.tex[0] : r->range_low.tex[0]);
    /* Wide lines (line_primitive.c) as wide as this pass's widest ribbon;
     * the fragments find their distance from the segment in window pixels. */
    if (line_strips) {
        glLineWidth((GLfloat)lc_line_primitive_width(fs, h, out_h));
        lc_uniform_v2(prog, "u_window_origin", vx, vy);
    }
    glViewport(vx - guard, vy - guard, w + 2 * guard, h + 2 * guard);
}

/* Triangles per draw call of a large draw on a software rasterizer: llvmpipe
 * bins a draw far ahead of its rasterizer threads, and the bins held about
 * 160 bytes per triangle (650 MB for two million points, 1.5 GB for four
 * million) for the rest of the process. Batches with at most two in flight
 * bound that whatever the dataset's size; primitives keep their order, so
 * images do not change. Each batch is a scene that llvmpipe's rasterizer
 * threads finish together, so small batches idle them: on the 896k-segment
 * tornado at 1024x1024 a frame took 1010 ms with 8k triangles, 830 ms with
 * 32k, 800 ms with 64k and about 700 ms unbatched, and the 5,000-line tornado's
 * resident bytes per vertex were 46, 57 and 72 for the first three
 * (unbatched was measured only before line strips: 100, against 75 with 8k
 * then; docs/MEMORY.md). 32k keeps that under 64. A draw of few batches pipelines poorly (binning of
 * the first and rasterizing of the last overlap nothing), so a draw is split
 * into at least 8 batches down to 8k triangles: tornado interactive frames at
 * 486x381 (100k triangles) took 44-46 ms split so, 44-90 ms in 32k batches.
 * GPUs draw in one call (0 = no batches). */
#define SOFTWARE_BATCH_TRIANGLES (1u << 15)
#define SOFTWARE_BATCH_MIN (1u << 13)
#define SOFTWARE_BATCH_SPLIT 8
static _Atomic uint64_t draw_batch_triangles; /* every worker's renderer sets the same value */

void lc_pipeline_configure(const char *gl_renderer)
{
    int software = lc_gl_renderer_is_software(gl_renderer);
    atomic_store(&draw_batch_triangles, software ? SOFTWARE_BATCH_TRIANGLES : 0);
}

/* Counts what a draw issues for the frame's report (lc_frame_info.pass_vertices). */
static void issued(const lc_frame_setup *fs, uint64_t vertices)
{
    if (fs->renderer)
        fs->renderer->vertices_issued += vertices;
}

/* Issues primitives [first, first + count) of the current program: points
 * (GL points when sprites, else instances), pulled primitives (six or three
 * corners each) or triangles of the index buffer. */
static void draw_range(const lc_frame_setup *fs, lc_prim_type prim, int pulled, int sprites, uint64_t first,
                       uint64_t count)
{
    if (prim == LC_PRIM_POINTS) {
        GLint prog = 0;
        glGetIntegerv(GL_CURRENT_PROGRAM, &prog);
        lc_uniform_u((GLuint)prog, "u_first_primitive", (unsigned)first);
        if (sprites)
            glDrawArrays(GL_POINTS, 0, (GLsizei)count);
        else
            glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)count);
        issued(fs, sprites ? count : 4 * count);
        return;
    }
    uint64_t corners = prim == LC_PRIM_TRIANGLES ? 3u : 6u;
    issued(fs, count * corners);
    if (pulled)
        glDrawArrays(GL_TRIANGLES, (GLint)(first * corners), (GLsizei)(count * corners));
    else
        glDrawElements(GL_TRIANGLES, (GLsizei)(count * corners), GL_UNSIGNED_INT,
                       (const void *)(uintptr_t)(first * corners * sizeof(uint32_t)));
}

/* Ends batch k of a split draw: waits for the batch before the previous one
 * and fences this one, so at most two are in flight (SOFTWARE_BATCH_TRIANGLES). */
static void end_batch(GLsync in_flight[2], uint64_t k)
{
    GLsync *slot = &in_flight[k & 1];
    if (*slot) {
        glClientWaitSync(*slot, GL_SYNC_FLUSH_COMMANDS_BIT, GL_TIMEOUT_IGNORED);
        glDeleteSync(*slot);
    }
    *slot = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
}

/* Pre-emption between two batches of a draw (desc.preempted;
 * docs/ARCHITECTURE.md "Yielding"): one pass of a large still on llvmpipe
 * takes up to a couple of seconds, which new input would otherwise wait out.
 * Only where fourier.c allows it (r->draw_yields); nonzero ends the draw, and
 * the frame's next yield point ends the frame. Large renders wait for other
 * sessions only at the passes' yield points: waiting between batches as well
 * starved them behind a steady orbit. */
int lc_renderer_batch_yield(const lc_frame_setup *fs)
{
    lc_renderer *r = fs->renderer;
    if (!r || !r->draw_yields || (!r->desc.preempted && !r->work) || (r->desc.reducer && r->desc.reducer->size > 1))
        return r && r->yield_cut;
    if (!r->yield_cut &&
        ((r->desc.preempted && r->desc.preempted(r->desc.yield_ctx)) || (r->work && lc_work_charge_elapsed(r->work))))
        r->yield_cut = 1; /* past the budget: the yield point that follows says so */
    return r->yield_cut;
}

/* Line strips split only where a run starts (the level's breaks): a batch
 * takes whole runs until it holds about `batch` triangles. */
static void draw_strips(const lc_frame_setup *fs, const lc_gpu_level *lv, uint64_t batch, GLsync in_flight[2])
{
    /* params.progressive: the runs that start in the batches' share of the
     * strip (whole runs from break to break, so lines stay whole). */
    uint64_t lo, hi;
    lc_progressive_range(fs, lv->index_count, &lo, &hi);
    uint32_t b0 = 0, b1 = lv->break_count;
    while (b0 < lv->break_count && lv->breaks[b0] < lo)
        b0++;
    while (b1 > b0 && lv->breaks[b1 - 1] >= hi)
        b1--;
    if (fs->batch_count > 0 && b1 <= b0)
        return;
    uint64_t stop = b1 < lv->break_count ? lv->breaks[b1] : lv->index_count;
    uint64_t start = fs->batch_count > 0 ? lv->breaks[b0] : 0, k = 0;
    for (uint32_t i = fs->batch_count > 0 ? b0 + 1 : 1; i <= b1; i++) {
        uint64_t end = i < b1 ? lv->breaks[i] : stop;
        if (end - start < batch && i < b1)
            continue;
        if (fs->line_primitive) /* the line strip holds every other index of the ribbon strip */
            glDrawElements(GL_LINE_STRIP, (GLsizei)((end - start) / 2), GL_UNSIGNED_INT,
                           (const void *)(uintptr_t)(start / 2 * sizeof(uint32_t)));
        else
            glDrawElements(GL_TRIANGLE_STRIP, (GLsizei)(end - start), GL_UNSIGNED_INT,
                           (const void *)(uintptr_t)(start * sizeof(uint32_t)));
        issued(fs, fs->line_primitive ? (end - start) / 2 : end - start);
        start = end;
        if (batch < stop - (fs->batch_count > 0 ? lv->breaks[b0] : 0)) {
            end_batch(in_flight, k++);
            if (lc_renderer_batch_yield(fs))
                return;
        }
    }
}

/* The important points that a strided point draw leaves out
 * (point_subset.c): every one, counted once in P1/P4 (draw_weight in
 * fragment_common.glsl). */
static void draw_point_list(const lc_frame_setup *fs, uint64_t batch, GLsync in_flight[2])
{
    GLint prog = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &prog);
    lc_uniform_i((GLuint)prog, "u_point_list", 1);
    uint64_t n = fs->kept_points;
    for (uint64_t first = 0, k = 0; first < n; first += batch, k++) {
        draw_range(fs, LC_PRIM_POINTS, 0, fs->point_sprites, first, n - first < batch ? n - first : batch);
        if (n > batch) {
            end_batch(in_flight, k);
            if (lc_renderer_batch_yield(fs))
                break;
        }
    }
    lc_uniform_i((GLuint)prog, "u_point_list", 0);
}

/* The kept strip of an importance-aware line subset (line_subset.c): the
 * full runs with the pass's weight, the strided ones with line_stride times
 * it (P4's u_weight; other passes have none). Batches split at even offsets
 * and overlap by one vertex pair: a strip resumes at any pair without losing
 * or repeating a segment. A subset stride (params.subset in P0, P1 and P4,
 * which weight it in u_weight) pulls every step-th ribbon slot of the kept
 * strip: the shader reads slot (first + i) * u_subset, so a batch's first is
 * its first slot's multiple of step. */
static void draw_kept_lines(const lc_frame_setup *fs, int pulled, uint64_t step, uint64_t batch, GLsync in_flight[2])
{
    GLint prog = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &prog);
    GLint loc = glGetUniformLocation((GLuint)prog, "u_weight");
    GLfloat weight = 1;
    if (loc >= 0)
        glGetUniformfv((GLuint)prog, loc, &weight);
    /* Indexed strips read the kept strip as their element buffer; pulled
     * segments (a time window) read its ribbon slots as the indices SSBO. */
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, fs->kept_line_buffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_INDICES, fs->kept_line_buffer);
    batch &= ~(uint64_t)1;
    uint64_t k = 0;
    int cut = 0; /* batch_yield ended the draw */
    for (int part = 0; part < 2 && !cut; part++) {
        uint64_t start = part ? fs->kept_line_total - fs->kept_line_indices[1] : 0;
        uint64_t end = start + fs->kept_line_indices[part];
        if (loc >= 0)
            glProgramUniform1f((GLuint)prog, loc, part ? weight * (float)fs->line_stride : weight);
        for (uint64_t s = start; s + 2 < end && !cut; s += batch ? batch : end) {
            uint64_t e = batch && s + batch + 2 < end ? s + batch + 2 : end;
            if (pulled) { /* slot q spans indices 2q .. 2q + 3: (e - s) / 2 - 1 slots from s / 2 */
                uint64_t first = (s / 2 + step - 1) / step, last = (s / 2 + (e - s) / 2 - 1 + step - 1) / step;
                if (last > first)
                    glDrawArrays(GL_TRIANGLES, (GLint)(first * 6), (GLsizei)((last - first) * 6));
                issued(fs, last > first ? (last - first) * 6 : 0);
            } else {
                glDrawElements(GL_TRIANGLE_STRIP, (GLsizei)(e - s), GL_UNSIGNED_INT,
                               (const void *)(uintptr_t)(s * sizeof(uint32_t)));
                issued(fs, e - s);
            }
            if (batch && fs->kept_line_indices[0] + fs->kept_line_indices[1] > batch) {
                end_batch(in_flight, k++);
                cut = lc_renderer_batch_yield(fs);
            }
        }
    }
    if (loc >= 0)
        glProgramUniform1f((GLuint)prog, loc, weight);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, fs->gs->levels[fs->level].indices);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_INDICES, fs->gs->levels[fs->level].indices);
}

void lc_renderer_draw_geometry(const lc_frame_setup *fs, int subset)
{
    lc_prim_type prim = fs->gs->scene->type;
    const lc_gpu_level *lv = &fs->gs->levels[fs->level];
    uint64_t n = lv->primitive_count;
    int pulled = lc_pulls_primitives(prim, subset, fs->pull_lines);
    if (prim == LC_PRIM_LINES && pulled)
        n = lv->index_count >= 4 ? lv->index_count / 2 - 1 : 0; /* ribbon slots of the strip */
    uint64_t step = lc_renderer_subset(fs, subset);
    uint64_t drawn = (n + step - 1) / step;
    if (!drawn || (fs->renderer && fs->renderer->yield_cut))
        return;
    if (!pulled && prim != LC_PRIM_POINTS)
        drawn = n; /* indexed draws cover every primitive */
    uint64_t per_batch = atomic_load(&draw_batch_triangles);
    if (per_batch) {
        uint64_t kept = fs->kept_line_indices[0] + fs->kept_line_indices[1];
        uint64_t triangles = prim == LC_PRIM_LINES && !pulled ? (kept ? kept : lv->index_count)
                                                              : drawn * (prim == LC_PRIM_TRIANGLES ? 1 : 2);
        uint64_t share = triangles / SOFTWARE_BATCH_SPLIT;
        per_batch = share < SOFTWARE_BATCH_MIN ? SOFTWARE_BATCH_MIN : share < per_batch ? share : per_batch;
    }
    GLsync in_flight[2] = {0, 0};
    int no_raster = fs->renderer && fs->renderer->floor == LC_FLOOR_NO_RASTER; /* lc_renderer_set_floor */
    if (no_raster)
        glEnable(GL_RASTERIZER_DISCARD);
    if (prim == LC_PRIM_LINES && fs->kept_line_indices[0] + fs->kept_line_indices[1]) {
        draw_kept_lines(fs, pulled, step, per_batch, in_flight);
    } else if (prim == LC_PRIM_LINES && !pulled) {
        draw_strips(fs, lv, per_batch ? per_batch : lv->index_count, in_flight);
    } else {
        uint64_t batch = per_batch ? per_batch / (prim == LC_PRIM_TRIANGLES ? 1 : 2) : drawn;
        uint64_t lo, hi; /* params.progressive: the batches' primitives */
        lc_progressive_range(fs, drawn, &lo, &hi);
        for (uint64_t first = lo, k = 0; first < hi; first += batch, k++) {
            draw_range(fs, prim, pulled, fs->point_sprites, first, hi - first < batch ? hi - first : batch);
            if (hi - lo > batch) {
                end_batch(in_flight, k);
                if (lc_renderer_batch_yield(fs))
                    break;
            }
        }
        if (prim == LC_PRIM_POINTS && fs->kept_points && !(fs->renderer && fs->renderer->yield_cut))
            draw_point_list(fs, batch, in_flight);
    }
    for (int i = 0; i < 2; i++)
        if (in_flight[i])
            glDeleteSync(in_flight[i]);
    if (no_raster)
        glDisable(GL_RASTERIZER_DISCARD);
}

void lc_bind_coefficients(const lc_targets *t)
{
    for (int i = 0; i < LC_MAX_COEF_TARGETS; i++)
        glBindImageTexture(IMG_COEF_FIRST + i, t->tex[i < t->count ? i : 0], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
}

void lc_dispatch_linear(GLuint groups)
{
    if (!groups)
        return;
    GLuint x = groups < 65535u ? groups : 65535u;
    glDispatchCompute(x, (groups + x - 1) / x, 1);
}

/* Additive float blending for the accumulation passes. */
void lc_additive_blending(void)
{
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);
}

void lc_renderer_readback(lc_renderer *r, const lc_frame_setup *fs, uint8_t *rgba)
{
    int w = fs->width, h = fs->height;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->output.fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    /* GL rows run bottom-up; images top-down. */
    size_t row = (size_t)w * 4;
    uint8_t *tmp = malloc(row);
    if (tmp) {
        for (int y = 0; y < h / 2; y++) {
            memcpy(tmp, rgba + (size_t)y * row, row);
            memcpy(rgba + (size_t)y * row, rgba + (size_t)(h - 1 - y) * row, row);
            memcpy(rgba + (size_t)(h - 1 - y) * row, tmp, row);
        }
        free(tmp);
    }
}

void lc_renderer_resolve(lc_renderer *r, const lc_frame_setup *fs, lc_program_kind kind, const lc_targets *a,
                         GLuint second_tex, lc_error *err)
{
    GLuint prog = lc_renderer_fixed_program(r, kind, err);
    if (!prog)
        return;
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->output.fbo);
    glViewport(0, 0, fs->width, fs->height);
    glUseProgram(prog);
    glBindVertexArray(r->vao);
    glBindTextureUnit(TEX_RESOLVE_A, a->tex[0]);
    glBindTextureUnit(TEX_RESOLVE_B, second_tex);
    lc_uniform_v3(prog, "u_background", fs->params->style.background);
    lc_uniform_i(prog, "u_context", fs->context_color ? 1 : 0);
    if (fs->context_color)
        glBindTextureUnit(TEX_CONTEXT_COLOR, fs->context_color);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

void lc_renderer_bind_direct_alpha(GLuint prog, const lc_render_params *p)
{
    lc_uniform_f(prog, "u_direct_exponent", p->foo.direct_exponent);
    lc_uniform_i(prog, "u_alpha_source", (int)p->foo.alpha_source);
    lc_uniform_f(prog, "u_alpha_constant", p->foo.alpha_constant);
    lc_uniform_f(prog, "u_gamma", p->foo.gamma);
}

GLuint lc_renderer_colormap_texture(const lc_renderer *r, const lc_frame_setup *fs)
{
    return fs->colormap_texture ? fs->colormap_texture
                                : r->colormap_tex[fs->colormap < r->colormap_count ? fs->colormap : 0];
}

void lc_renderer_bind_halo(GLuint prog, const lc_frame_setup *fs)
{
    const lc_style *st = &fs->params->style;
    const double *b = fs->gs->scene->bounds;
    double diag = sqrt((b[3] - b[0]) * (b[3] - b[0]) + (b[4] - b[1]) * (b[4] - b[1]) + (b[5] - b[2]) * (b[5] - b[2]));
    int on = fs->gs->scene->type == LC_PRIM_LINES && st->halo_width > 0;
    lc_uniform_f(prog, "u_halo_px", on ? st->halo_width : 0.0);
    lc_uniform_f(prog, "u_halo_depth", st->halo_depth * (isfinite(diag) ? diag : 0.0));
    lc_uniform_f(prog, "u_halo_strength", st->halo_strength);
    lc_uniform_v3(prog, "u_halo_color", st->background);
}

size_t lc_renderer_read_targets(lc_renderer *r, int which, float *out, size_t n)
{
    const lc_targets *t = which == 0 ? &r->coef_low : &r->moments;
    if (!t->fbo || t->format != GL_RGBA32F)
        return 0;
    size_t per = (size_t)t->width * t->height * 4, total = per * (size_t)t->count;
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    for (int i = 0; i < t->count && (size_t)i * per < n; i++) {
        size_t take = n - (size_t)i * per < per ? n - (size_t)i * per : per;
        if (take == per)
            glGetTextureImage(t->tex[i], 0, GL_RGBA, GL_FLOAT, (GLsizei)(per * sizeof(float)), out + (size_t)i * per);
    }
    return total;
}
