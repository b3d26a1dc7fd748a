/* P1's fragment list (docs/ALGORITHM.md "The geometry path"): P1 appends
 * every fragment it draws, (pixel, element, g, series depth), and P2 becomes a
 * compute pass over that list instead of a second traversal of the geometry.
 *
 * Why: on llvmpipe a geometry pass costs what its vertex shading, triangle
 * set-up, binning and rasterization cost, nearly whatever its fragments
 * compute (`lucent bench --floor`: on the 891k-segment MD trajectories at
 * 1024^2, P2 with an empty fragment shader took 696 of its 765 ms), and a
 * one-shot still runs P2 once per try of the clarity loop (three on that
 * file). A fragment of P2 reads nothing but its own g, depth and element and
 * its pixel's final P1 sums, and P2 draws exactly P1's fragments (same
 * resolution, primitives and coverage) whenever P1 draws every primitive,
 * so evaluating the recorded fragments gives the same element minima, bit
 * for bit (an atomic minimum does not depend on order; the occluder sums are
 * integers).
 *
 * The list is sized from the fragments seen before (a first frame guesses);
 * a frame whose fragments do not fit draws P2 as before and the list grows
 * for the next one. llvmpipe zeroes a buffer's whole storage when it makes
 * it (lp_texture.c), so the capacity is resident memory, and its first
 * frame pays the clear.
 *
 * P1 over P0's fragments (FRAGMENT_CHAINS): where P0 "moments" runs, it
 * records the same list (with the normalized depth where P1 leaves the
 * series depth) and chains each pixel's entries in the order its fragment
 * shader ran them; P1 is then a compute pass that walks each pixel's chain
 * and adds the projections in that order (p1_list.comp.glsl). Additive
 * blending adds a pixel's fragments in primitive order, and llvmpipe shades
 * a pixel's fragments on one thread in that order, so the sums are the drawn
 * P1's bit for bit (render.test_references checks it); P2 then runs over the
 * list as after a recording P1. A frame traverses the geometry three times
 * (P0, P4, P5), twice where P4 records its fragments too (below). */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_context.h"
#include "renderer_internal.h"

/* Entries: 16 bytes each; 2^24 of them, 256 MB, at most. */
#define FRAGMENT_LIST_MAX (1ull << 24)
/* A first frame's guess: per pixel of the optimization resolution, or per
 * primitive, whichever is larger (the MD trajectories have about 13 per
 * pixel at 512^2, a million points about 3 per point at 486x381). */
#define FRAGMENTS_PER_PIXEL_GUESS 16
#define FRAGMENTS_PER_PRIMITIVE_GUESS 4

static atomic_int fragment_lists = 0;  /* lc_fragment_list_configure */
static atomic_int heads_fetch = 1;     /* LUCENT_HEADS_FETCH: 0 swaps the heads atomically (comparisons, tests) */
static atomic_int sums_in_walk = 1;    /* LUCENT_SUMS_IN_WALK: 0 walks P4's list twice (comparisons, tests) */
#define COMPOSITE_AUTO 2               /* P5 over P4's fragments in large frames (below) */
static atomic_int composite_lists = 0; /* 0 drawn, 1 listed, COMPOSITE_AUTO */

/* On software rasterizers, where a traversal costs its set-up and
 * rasterization whatever it shades; GPUs draw P2 until measured otherwise. */
void lc_fragment_list_configure(const char *gl_renderer)
{
    int software = lc_gl_renderer_is_software(gl_renderer);
    const char *e = getenv("LUCENT_FRAGMENT_LISTS"); /* 0 / 1: force off / on (comparisons, tests) */
    atomic_store(&fragment_lists, e && (e[0] == '0' || e[0] == '1') ? e[0] == '1' : software);
    const char *p5 = getenv("LUCENT_P5_LIST"); /* 0 / 1: drawn / listed wherever lists are on (comparisons, tests) */
    atomic_store(&composite_lists, p5 && (p5[0] == '0' || p5[0] == '1') ? p5[0] - '0' : COMPOSITE_AUTO);
    const char *hf = getenv("LUCENT_HEADS_FETCH");
    atomic_store(&heads_fetch, !(hf && hf[0] == '0'));
    const char *sw = getenv("LUCENT_SUMS_IN_WALK");
    atomic_store(&sums_in_walk, !(sw && sw[0] == '0'));
}

bool lc_renderer_heads_fetch(const lc_renderer *r) { return r->heads_fetch; }

void lc_fragment_heads_configure(lc_renderer *r)
{
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    r->heads_fetch = false;
    for (GLint i = 0; i < n && atomic_load(&heads_fetch); i++)
        if (strcmp((const char *)glGetStringi(GL_EXTENSIONS, (GLuint)i), "GL_EXT_shader_framebuffer_fetch") == 0)
            r->heads_fetch = true;
}

int lc_fragment_list_enabled(void) { return atomic_load(&fragment_lists); }

/* A frame whose passes weigh fragments: params.subset, a moving frame's
 * point stride, splats of a frame smaller than its view (lc_point_splat) or
 * strided lines (P4 draws the stride, P5 does not). */
static int strided(const lc_frame_setup *fs)
{
    int spread = fs->gs->scene->type == LC_PRIM_POINTS && lc_point_scale(fs->params) != 1;
    return fs->params->foo.subset > 1 || lc_renderer_subset(fs, 1) > 1 || spread ||
           (fs->kept_line_indices[1] > 0 && fs->line_stride > 1);
}

int lc_fragment_chains_wanted(const lc_renderer *r, const lc_frame_setup *fs)
{
    (void)r;
    /* Layers draw with their own parameters (a depth margin each); a tile's
     * full-resolution optimization shifts its window (bind_geometry); a
     * stride weighs fragments, which the list does not keep (params.subset,
     * a moving frame's point stride or strided lines). Those frames record
     * in P1 as before. */
    int tile_low = fs->tiled && fs->low_width == fs->width && fs->low_height == fs->height;
    /* params.progressive: P0 runs whole in its first frame, P1 one batch. */
    return lc_fragment_list_enabled() && !strided(fs) && fs->layer_count == 0 && !tile_low &&
           fs->params->foo.progressive <= 1;
}

int lc_fragment_list_wanted(const lc_renderer *r, int p1_subset)
{
    (void)r;
    return lc_fragment_list_enabled() && p1_subset <= 1;
}

static int same_camera(const lc_camera *a, const lc_camera *b)
{
    return memcmp(a->position, b->position, sizeof a->position) == 0 &&
           memcmp(a->focal_point, b->focal_point, sizeof a->focal_point) == 0 &&
           memcmp(a->view_up, b->view_up, sizeof a->view_up) == 0 && a->view_angle == b->view_angle &&
           a->parallel_projection == b->parallel_projection && a->parallel_scale == b->parallel_scale;
}

/* The fragments P0 may expect at the optimization resolution from the state's
 * hint of this scene and camera (0: none). */
static uint64_t fragment_hint(const lc_frame_setup *fs)
{
    const lc_frame_state *st = fs->state;
    if (!st || st->fragment_hint.per_pixel <= 0 || st->fragment_hint.scene != fs->gs ||
        !same_camera(&st->fragment_hint.camera, &fs->params->camera))
        return 0;
    double n = st->fragment_hint.per_pixel * (double)fs->low_width * (double)fs->low_height;
    return n < (double)FRAGMENT_LIST_MAX ? (uint64_t)n : FRAGMENT_LIST_MAX;
}

int lc_fragment_hint_begin(lc_renderer *r, const lc_frame_setup *fs)
{
    /* Frames with a state only (a session's), on software rasterizers (where
     * P0 records); one frame of one dataset, counted once (not a tile's or an
     * antialiasing sample's P4 again, nor a batch's). */
    if (!lc_fragment_list_enabled() || !fs->state || r->fragment_counting || fs->layer_count || fs->tiled ||
        fs->batch_count)
        return 0;
    if (!r->fragment_query)
        glGenQueries(1, &r->fragment_query);
    glBeginQuery(GL_SAMPLES_PASSED, r->fragment_query);
    r->fragment_counting = true;
    return 1;
}

void lc_fragment_hint_end(void) { glEndQuery(GL_SAMPLES_PASSED); }

void lc_fragment_hint_store(lc_renderer *r, const lc_frame_setup *fs, uint64_t drawn, uint64_t primitives)
{
    if (!r->fragment_counting || drawn == 0)
        return;
    r->fragment_counting = false;
    GLuint64 samples = 0;
    glGetQueryObjectui64v(r->fragment_query, GL_QUERY_RESULT, &samples);
    lc_frame_state *st = fs->state;
    st->fragment_hint.scene = fs->gs;
    st->fragment_hint.camera = fs->params->camera;
    st->fragment_hint.per_pixel =
        (double)samples * ((double)primitives / (double)drawn) / ((double)fs->width * (double)fs->height);
}

static void ensure_capacity(lc_renderer *r, uint64_t want)
{
    want = want < 4096 ? 4096 : want > FRAGMENT_LIST_MAX ? FRAGMENT_LIST_MAX : want;
    if (r->fragment_limit && want > r->fragment_limit)
        want = r->fragment_limit;
    if (r->fragment_list && r->fragment_capacity >= want)
        return;
    if (r->fragment_limit_once)
        r->fragment_limit = 0, r->fragment_limit_once = 0;
    lc_fragment_list_release(r);
    r->fragment_list = lc_scratch_buffer(16 + 16 * want, GL_DYNAMIC_STORAGE_BIT);
    r->fragment_capacity = want;
}

void lc_fragment_list_begin(lc_renderer *r, const lc_frame_setup *fs)
{
    uint64_t prims = 0;
    for (int i = 0; i < lc_frame_layer_count(fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (lf)
            prims += lf->gs->levels[lf->level].primitive_count;
    }
    uint64_t guess = (uint64_t)fs->low_width * (uint64_t)fs->low_height * FRAGMENTS_PER_PIXEL_GUESS;
    if (guess < prims * FRAGMENTS_PER_PRIMITIVE_GUESS)
        guess = prims * FRAGMENTS_PER_PRIMITIVE_GUESS;
    /* After a frame: what it needed, with room for a view that covers more. */
    if (guess < r->fragment_seen + r->fragment_seen / 4)
        guess = r->fragment_seen + r->fragment_seen / 4;
    /* A frame of this camera drew P4 (a drag's last frame, a staged still's
     * first stage): its fragments at this resolution, with the same room. */
    uint64_t hinted = fragment_hint(fs);
    if (guess < hinted + hinted / 4)
        guess = hinted + hinted / 4;
    ensure_capacity(r, guess);
    const uint32_t zero = 0;
    glClearNamedBufferSubData(r->fragment_list, GL_R32UI, 0, 4, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_LIST, r->fragment_list);
    r->fragments_ready = 0;
}

void lc_fragment_list_resume(lc_renderer *r)
{
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_LIST, r->fragment_list);
    r->fragments_ready = 0;
}

void lc_fragment_list_end(lc_renderer *r)
{
    uint32_t count = 0;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glGetNamedBufferSubData(r->fragment_list, 0, 4, &count); /* waits for P1, which P2 would wait for too */
    r->fragment_seen = count > r->fragment_seen ? count : r->fragment_seen;
    r->fragment_count = count;
    r->fragments_ready = count <= r->fragment_capacity;
}

/* A word a pixel of w x h, cleared to FRAGMENT_NONE and bound: the chains'
 * heads of P0's list or P4's. */
static void chain_heads(lc_renderer *r, int w, int h)
{
    uint64_t pixels = (uint64_t)w * (uint64_t)h;
    if (!r->fragment_chains || r->chain_words < pixels) {
        lc_scratch_discard(&r->fragment_chains);
        r->fragment_chains = lc_scratch_buffer(4 * pixels, GL_DYNAMIC_STORAGE_BIT);
        r->chain_words = pixels;
    }
    const uint32_t none = 0xFFFFFFFFu; /* FRAGMENT_NONE: no entry yet */
    if (!r->heads_fetch)               /* (else the recording's target holds them: copy_heads) */
        glClearNamedBufferSubData(r->fragment_chains, GL_R32UI, 0, (GLsizeiptr)(4 * pixels), GL_RED_INTEGER,
                                  GL_UNSIGNED_INT, &none);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_CHAINS, r->fragment_chains);
    r->chain_pixels = (uint32_t)pixels;
    r->chain_width = (uint32_t)w;
    r->fragments_chained = 0;
}

/* The framebuffer a recording pass of w x h draws into, bound: without
 * attachments, where llvmpipe generates no blending at all (masking a
 * target's writes still loaded and stored it: P4 took 0.2 s more on lj_melt
 * at 972x761); or, with framebuffer fetch (HEADS_FETCH in
 * fragment_list.glsl), the R32UI target of the chains' heads, cleared to
 * FRAGMENT_NONE (which: 0 P0's, 1 P4's, each kept at its size). */
static void bind_recording_framebuffer(lc_renderer *r, int w, int h, int which)
{
    if (!r->heads_fetch) {
        if (!r->record_fbo)
            glCreateFramebuffers(1, &r->record_fbo);
        glNamedFramebufferParameteri(r->record_fbo, GL_FRAMEBUFFER_DEFAULT_WIDTH, w);
        glNamedFramebufferParameteri(r->record_fbo, GL_FRAMEBUFFER_DEFAULT_HEIGHT, h);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->record_fbo);
        return;
    }
    lc_heads_target *t = &r->heads[which];
    if (!t->tex || t->width != w || t->height != h) {
        if (t->tex)
            glDeleteTextures(1, &t->tex);
        glCreateTextures(GL_TEXTURE_2D, 1, &t->tex);
        glTextureStorage2D(t->tex, 1, GL_R32UI, w, h);
        if (!t->fbo)
            glCreateFramebuffers(1, &t->fbo);
        glNamedFramebufferTexture(t->fbo, GL_COLOR_ATTACHMENT0, t->tex, 0);
        t->width = w, t->height = h;
    }
    const GLuint none[4] = {0xFFFFFFFFu, 0, 0, 0};
    glClearNamedFramebufferuiv(t->fbo, GL_COLOR, 0, none);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->fbo);
}

/* After a recording draw with framebuffer fetch: its heads into the chains'
 * buffer, where the walks read them (a copy of 4 bytes a pixel). */
static void copy_heads(lc_renderer *r, int which)
{
    if (!r->heads_fetch)
        return;
    const lc_heads_target *t = &r->heads[which];
    glBindBuffer(GL_PIXEL_PACK_BUFFER, r->fragment_chains);
    glGetTextureImage(t->tex, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, (GLsizei)(4 * (uint64_t)t->width * t->height), NULL);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
}

void lc_fragment_chains_begin(lc_renderer *r, const lc_frame_setup *fs, int w, int h)
{
    lc_fragment_list_begin(r, fs);
    chain_heads(r, w, h);
    bind_recording_framebuffer(r, w, h, 0);
}

void lc_fragment_chains_end(lc_renderer *r)
{
    copy_heads(r, 0);
    lc_fragment_list_end(r);
    r->fragments_chained = r->fragments_ready; /* every fragment is in the list and its chain */
    r->fragments_ready = 0;                    /* P2's depths come with P1 */
}

int lc_fragment_chains_moments(lc_renderer *r, const lc_targets *t, lc_error *err)
{
    GLuint *slot = &r->fixed_programs[PROG_P0_CHAINS - PROG_GEOMETRY_KINDS];
    if (!*slot) {
        static const char *const cs[] = {"common.glsl", "fragment_list.glsl", "p0_list.comp.glsl", NULL};
        *slot = lc_renderer_build_program("#define FRAGMENT_CHAINS 1\n", NULL, NULL, cs,
                                          "P0's moments over its fragments", err);
        if (!*slot)
            return LC_ERR_GL;
    }
    glUseProgram(*slot);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_LIST, r->fragment_list);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_CHAINS, r->fragment_chains);
    lc_uniform_u(*slot, "u_chain_pixels", r->chain_pixels);
    lc_uniform_u(*slot, "u_chain_width", r->chain_width);
    glBindImageTexture(IMG_COEF_FIRST, t->tex[0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    lc_dispatch_linear((r->chain_pixels + 63u) / 64u);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT);
    return 0;
}

/* series_depth_at's uniforms as lc_renderer_bind_geometry sets them for a
 * pass of w x h pixels (no tile: lists are never tiled). */
static void bind_series_depth(lc_renderer *r, const lc_frame_setup *fs, GLuint prog, int w, int h)
{
    lc_uniform_f(prog, "u_depth_margin", fs->pixel_depth_range ? LC_PIXEL_DEPTH_MARGIN : fs->params->foo.depth_margin);
    lc_uniform_i(prog, "u_depth_moments", fs->depth_moments);
    if (fs->depth_moments) {
        glBindTextureUnit(TEX_DEPTH_MOMENTS, r->moments.tex[0]);
        lc_uniform_v2(prog, "u_moments_scale", (double)fs->low_width / w, (double)fs->low_height / h);
        lc_uniform_v2(prog, "u_moments_offset", fs->moments_guard[0], fs->moments_guard[1]);
        lc_uniform_v2(prog, "u_pixel_origin", 0, 0);
    }
}

static GLuint chains_program(lc_renderer *r, int bands, lc_error *err)
{
    GLuint *slot = &r->fixed_programs[PROG_P1_CHAINS_FIRST + bands - 1 - PROG_GEOMETRY_KINDS];
    if (!*slot) {
        static const char *const cs[] = {"common.glsl", "fragment_list.glsl", "coefficient_store.glsl",
                                         "p1_list.comp.glsl", NULL};
        char defines[96];
        snprintf(defines, sizeof defines, "#define BANDS %d\n#define FRAGMENT_CHAINS 1\n#define SERIES_DEPTH_AT 1\n",
                 bands);
        *slot = lc_renderer_build_program(defines, NULL, NULL, cs, "P1 over P0's fragments", err);
    }
    return *slot;
}

int lc_fragment_chains_p1(lc_renderer *r, const lc_frame_setup *fs, const lc_targets *t, int bands, lc_error *err)
{
    GLuint prog = chains_program(r, bands, err);
    if (!prog)
        return LC_ERR_GL;
    glUseProgram(prog);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_LIST, r->fragment_list);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_CHAINS, r->fragment_chains);
    lc_uniform_u(prog, "u_chain_pixels", r->chain_pixels);
    lc_uniform_u(prog, "u_chain_width", r->chain_width);
    lc_uniform_f(prog, "u_weight", 1.0);
    bind_series_depth(r, fs, prog, t->width, t->height);
    for (int i = 0; i < LC_MAX_COEF_TARGETS; i++)
        glBindImageTexture(IMG_COEF_FIRST + i, t->tex[i < t->count ? i : 0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    lc_dispatch_linear((r->chain_pixels + 63u) / 64u);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT);
    r->fragments_chained = 0;
    r->fragments_ready = 1; /* the list now holds P1's fragments with their series depths */
    return 0;
}

/* ---- P4's sums and P5 over P4's fragments (COMPOSITE_LIST; docs/ALGORITHM.md
 * §27): P4 draws into its recording framebuffer (no target but its chain
 * heads'), recording each fragment's
 * normalized depth, opacity, importance and lit colour (16 bytes, one store),
 * chained per pixel from its last fragment back; compute passes walk the
 * chains for P4's coefficient sums and then for P5. On llvmpipe this
 * replaces two drawn passes whose fragment shading costs more than the
 * recording and the walks together (docs/EVALUATION.md, "The geometry
 * path"). The quantized opacity and colour and the walk's order of additions
 * move a few pixels by 1/255 from the drawn passes' image, so frames whose
 * P0 found fewer than COMPOSITE_AUTO_MIN fragments (scaled to full
 * resolution) keep the drawn passes, where they cost less and layers, tiles
 * and program variants give the same bytes. */

/* Entries: 16 bytes each; 2^24 of them, 256 MB, at most. */
#define COMPOSITE_LIST_MAX (1ull << 24)
#define COMPOSITE_PER_PIXEL_GUESS 4
#define COMPOSITE_AUTO_MIN (2ull << 20)
#define COMPOSITE_ROOM(n) ((n) + (n) / 4) /* a quarter more than expected */

/* P0's fragments at the optimization resolution scaled by the pixels to
 * the full one: what decides whether a frame takes the list (a function of
 * the frame alone, so that a one-shot render is the same bytes whatever its
 * renderer drew before: the listed and the drawn images differ by 1/255 in
 * places). */
static uint64_t p0_pixels_scaled(const lc_frame_setup *fs)
{
    if (!fs->p0_fragments || fs->low_width <= 0 || fs->low_height <= 0)
        return 0;
    double pixels = (double)fs->width * (double)fs->height;
    return (uint64_t)((double)fs->p0_fragments * pixels / ((double)fs->low_width * (double)fs->low_height));
}

/* The entries P4 will offer, for the list's capacity: P0's fragments times
 * the ratio the last recording frame of the same scene and size measured
 * between the two, else scaled by the pixels (thin lines and points need not
 * grow with the area; the MD trajectories measured 3.99 at 972x761 for the
 * pixels' 4). */
static uint64_t p0_scaled(const lc_renderer *r, const lc_frame_setup *fs)
{
    if (fs->p0_fragments && r->composite_ratio > 0 && r->composite_ratio_scene == fs->gs->scene &&
        r->composite_ratio_width == fs->width && r->composite_ratio_height == fs->height)
        return (uint64_t)((double)fs->p0_fragments * r->composite_ratio);
    return p0_pixels_scaled(fs);
}

/* The list's capacity: the expected entries (or 4 a pixel, or the most this
 * renderer has seen) with a quarter more room, at most COMPOSITE_LIST_MAX; a
 * frame that overflows it records again in a list of what it counted
 * (lc_composite_list_retry), or draws P4 and P5 where that is past the bound. */
static uint64_t composite_guess(const lc_renderer *r, const lc_frame_setup *fs)
{
    uint64_t want = (uint64_t)fs->width * (uint64_t)fs->height * COMPOSITE_PER_PIXEL_GUESS;
    uint64_t p0 = p0_scaled(r, fs);
    want = want > p0 ? want : p0;
    if (want < r->composite_seen && r->composite_seen <= COMPOSITE_LIST_MAX) /* (one huge frame must not end it) */
        want = r->composite_seen;
    want = COMPOSITE_ROOM(want);
    return want < COMPOSITE_LIST_MAX ? want : COMPOSITE_LIST_MAX;
}

/* Whether this process's mode lists a frame of `fragments` (P0's, scaled to
 * full resolution) whose list would need `entries`. */
static int composite_takes(double fragments, double entries)
{
    int mode = atomic_load(&composite_lists);
    return lc_fragment_list_enabled() && mode && (mode != COMPOSITE_AUTO || fragments >= (double)COMPOSITE_AUTO_MIN) &&
           entries <= (double)COMPOSITE_LIST_MAX;
}

int lc_composite_list_wanted(const lc_frame_setup *fs, int direct)
{
    /* Strides, layers and tiles as for P0's chains; the direct baseline keeps
     * its own programs; a list past its bound would be recorded only to be
     * drawn again. The frame alone decides (p0_pixels_scaled), not what the
     * renderer learned. */
    uint64_t expected = p0_pixels_scaled(fs);
    return !direct && !strided(fs) && fs->layer_count == 0 && !fs->tiled &&
           composite_takes((double)expected, (double)expected);
}

int lc_composite_list_expected(double fragments) { return composite_takes(fragments, fragments); }

void lc_composite_list_begin(lc_renderer *r, const lc_frame_setup *fs)
{
    uint64_t want = composite_guess(r, fs);
    if (r->composite_limit && want > r->composite_limit)
        want = r->composite_limit;
    if (!r->composite_list || r->composite_capacity < want) {
        lc_scratch_discard(&r->composite_list);
        r->composite_list = lc_scratch_buffer(16 + 16 * want, GL_DYNAMIC_STORAGE_BIT);
        r->composite_capacity = want;
        if (r->composite_limit_once)
            r->composite_limit = 0, r->composite_limit_once = 0;
    }
    const uint32_t zero = 0;
    glClearNamedBufferSubData(r->composite_list, GL_R32UI, 0, 4, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_LIST, r->composite_list);
    /* The heads in the chains' buffer (P1 is done with it). */
    chain_heads(r, fs->width, fs->height);
    bind_recording_framebuffer(r, fs->width, fs->height, 1);
}

void lc_composite_list_limit(lc_renderer *r, uint64_t entries, int once)
{
    r->composite_limit = entries;
    r->composite_limit_once = once && entries;
    lc_scratch_discard(&r->composite_list); /* the next frame sizes it anew */
    r->composite_capacity = 0;
}

void lc_fragment_list_limit(lc_renderer *r, uint64_t entries, int once)
{
    r->fragment_limit = entries;
    r->fragment_limit_once = once && entries;
    lc_fragment_list_release(r); /* the next frame sizes them anew */
}

/* Whether a list of `count` entries may be made (at most `max`, and a test's limit). */
static int list_fits(uint64_t count, uint64_t max, uint64_t limit)
{
    return count <= max && (!limit || count <= limit);
}

int lc_fragment_chains_retry(lc_renderer *r, const lc_frame_setup *fs, int w, int h)
{
    /* The count is every fragment P0 offered; begin's guess takes the most
     * seen (this count) with a quarter more. */
    if (!list_fits(r->fragment_count, FRAGMENT_LIST_MAX, r->fragment_limit))
        return 0;
    lc_fragment_chains_begin(r, fs, w, h);
    return r->fragment_capacity >= r->fragment_count;
}

int lc_composite_list_retry(lc_renderer *r, const lc_frame_setup *fs)
{
    if (!list_fits(r->composite_offered, COMPOSITE_LIST_MAX, r->composite_limit))
        return 0;
    lc_composite_list_begin(r, fs);
    return r->composite_capacity >= r->composite_offered;
}

int lc_composite_list_end(lc_renderer *r, const lc_frame_setup *fs)
{
    uint32_t count = 0;
    copy_heads(r, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glGetNamedBufferSubData(r->composite_list, 0, 4, &count);
    r->composite_seen = count > r->composite_seen ? count : r->composite_seen;
    r->composite_offered = count;
    if (fs->p0_fragments) { /* the next frame's estimate (p0_scaled) */
        r->composite_ratio = (double)count / (double)fs->p0_fragments;
        r->composite_ratio_scene = fs->gs->scene;
        r->composite_ratio_width = fs->width, r->composite_ratio_height = fs->height;
    }
    return count <= r->composite_capacity;
}

/* A compute program over P4's list (per band count), bound with the list and its heads. */
static GLuint use_composite_program(lc_renderer *r, const lc_frame_setup *fs, int first, const char *file,
                                    const char *name, lc_error *err)
{
    int bands = fs->params->foo.bands;
    GLuint *slot = &r->fixed_programs[first + bands - 1 - PROG_GEOMETRY_KINDS];
    if (!*slot) {
        /* P5 reads the coefficients that P4's pass writes, or (PROG_P45_CHAINS_FIRST) makes and writes them. */
        const char *const cs[] = {"common.glsl", "fragment_list.glsl",
                                  first == PROG_P5_CHAINS_FIRST ? "coefficients.glsl" : "coefficient_store.glsl", file,
                                  NULL};
        char defines[128];
        snprintf(defines, sizeof defines, "#define BANDS %d\n#define COMPOSITE_LIST 1\n#define SERIES_DEPTH_AT 1\n%s",
                 bands, first == PROG_P45_CHAINS_FIRST ? "#define SUMS_IN_WALK 1\n" : "");
        *slot = lc_renderer_build_program(defines, NULL, NULL, cs, name, err);
        if (!*slot)
            return 0;
    }
    glUseProgram(*slot);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_LIST, r->composite_list);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_CHAINS, r->fragment_chains);
    lc_uniform_u(*slot, "u_chain_pixels", r->chain_pixels);
    lc_uniform_u(*slot, "u_chain_width", r->chain_width);
    bind_series_depth(r, fs, *slot, fs->width, fs->height); /* the entries hold normalized depths */
    return *slot;
}

/* Whether P5's walk makes P4's sums as well: with one process (MPI adds
 * every rank's sums before any P5), unless LUCENT_SUMS_IN_WALK=0. */
static int sums_in_walk_now(const lc_renderer *r)
{
    return atomic_load(&sums_in_walk) && !(r->desc.reducer && r->desc.reducer->size > 1);
}

/* The coefficient targets t as the images a walk writes (coefficient_store.glsl). */
static void bind_coefficient_images(const lc_targets *t)
{
    for (int i = 0; i < LC_MAX_COEF_TARGETS; i++)
        glBindImageTexture(IMG_COEF_FIRST + i, t->tex[i < t->count ? i : 0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
}

int lc_composite_list_p4(lc_renderer *r, const lc_frame_setup *fs, const lc_targets *t, lc_error *err)
{
    if (sums_in_walk_now(r))
        return 0; /* lc_composite_list_p5 makes them */
    GLuint prog = use_composite_program(r, fs, PROG_P4_CHAINS_FIRST, "p4_list.comp.glsl", "P4 over its fragments", err);
    if (!prog)
        return LC_ERR_GL;
    if (fs->info)
        fs->info->composite_walks++;
    bind_coefficient_images(t);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    lc_dispatch_linear((r->chain_pixels + 63u) / 64u);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    return 0;
}

int lc_composite_list_p5(lc_renderer *r, const lc_frame_setup *fs, const lc_targets *sums, const lc_targets *t,
                         lc_error *err)
{
    int in_walk = sums_in_walk_now(r);
    GLuint prog = in_walk ? use_composite_program(r, fs, PROG_P45_CHAINS_FIRST, "p5_list.comp.glsl",
                                                  "P4's sums and P5 over P4's fragments", err)
                          : use_composite_program(r, fs, PROG_P5_CHAINS_FIRST, "p5_list.comp.glsl",
                                                  "P5 over P4's fragments", err);
    if (!prog)
        return LC_ERR_GL;
    if (fs->info)
        fs->info->composite_walks++;
    if (in_walk)
        bind_coefficient_images(sums);
    else
        lc_bind_coefficients(sums);
    lc_uniform_i(prog, "u_estimator", fs->params->foo.estimator == LC_ESTIMATOR_MIDPOINT ? 1 : 0);
    /* topDecileReach's per-pixel sums where lc_reach_begin set their target up. */
    lc_uniform_f(prog, "u_reach_g", r->reach_drawn ? r->reach_g : 2.0f);
    /* The entries' colours: looked up and shaded here where P4 recorded the colormap's coordinate and <n, l>
     * (fragment_color_word in fragment_list.glsl: lines through the colormap). */
    lc_uniform_i(prog, "u_deferred_color", fs->gs->scene->type == LC_PRIM_LINES && fs->color_mode != 2);
    lc_uniform_i(prog, "u_shading", fs->params->style.shading == LC_SHADING_NONE ? 1 : 0);
    lc_uniform_v3(prog, "u_halo_color", fs->params->style.background);
    glBindTextureUnit(TEX_COLORMAP, lc_renderer_colormap_texture(r, fs));
    glBindImageTexture(IMG_EXACT_OUTPUT, t->tex[0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    if (r->reach_drawn)
        glBindImageTexture(IMG_P5_REACH, r->reach_sums.tex[0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    lc_dispatch_linear((r->chain_pixels + 63u) / 64u);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    return 0;
}

uint64_t lc_fragment_list_bytes(const lc_renderer *r)
{
    /* The capacities (llvmpipe zeroes, so touches, a buffer's whole storage
     * when it makes it) and the chains' words. */
    uint64_t list = r->fragment_list ? 16 + 16 * r->fragment_capacity : 0;
    uint64_t chains = r->fragment_chains ? 4 * r->chain_words : 0;
    uint64_t composite = r->composite_list ? 16 + 16 * r->composite_capacity : 0;
    uint64_t heads = 0;
    for (int i = 0; i < 2; i++)
        heads += r->heads[i].tex ? 4 * (uint64_t)r->heads[i].width * (uint64_t)r->heads[i].height : 0;
    return list + chains + composite + heads;
}

GLuint lc_fragment_list_program(lc_renderer *r, int bands, lc_error *err)
{
    GLuint *slot = &r->fixed_programs[PROG_P2_LIST_FIRST + bands - 1 - PROG_GEOMETRY_KINDS];
    if (!*slot) {
        static const char *const cs[] = {"common.glsl",
                                         "coefficients.glsl",
                                         "occluders.glsl",
                                         "fragment_list.glsl",
                                         "opacity_common.glsl",
                                         "p2_list.comp.glsl",
                                         NULL};
        char defines[64];
        snprintf(defines, sizeof defines, "#define BANDS %d\n", bands);
        *slot = lc_renderer_build_program(defines, NULL, NULL, cs, "P2 over P1's fragments", err);
    }
    return *slot;
}

void lc_fragment_list_dispatch(lc_renderer *r, GLuint prog)
{
    glUseProgram(prog);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_FRAGMENT_LIST, r->fragment_list);
    lc_uniform_u(prog, "u_fragments", r->fragment_count);
    lc_dispatch_linear((r->fragment_count + 2047u) / 2048u); /* 8 entries an invocation (P2_PER_INVOCATION) */
}

void lc_fragment_list_release(lc_renderer *r)
{
    lc_scratch_discard(&r->fragment_list);
    r->fragment_capacity = 0;
    r->fragments_ready = 0;
    lc_scratch_discard(&r->fragment_chains);
    r->chain_words = 0;
    r->fragments_chained = 0;
    lc_scratch_discard(&r->composite_list);
    r->composite_capacity = 0;
    if (r->record_fbo)
        glDeleteFramebuffers(1, &r->record_fbo);
    r->record_fbo = 0;
    for (int i = 0; i < 2; i++) {
        if (r->heads[i].tex)
            glDeleteTextures(1, &r->heads[i].tex);
        if (r->heads[i].fbo)
            glDeleteFramebuffers(1, &r->heads[i].fbo);
        r->heads[i] = (lc_heads_target){0};
    }
}
