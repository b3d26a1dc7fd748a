/* Exact reference (DOO, Günther et al. 2017): per-pixel fragment linked lists
 * on the GPU, sorted per pixel, with exact front/behind importance sums and
 * exact front-to-back compositing (docs/ALGORITHM.md §12).
 *
 * Frame: list pass 0 at the optimization resolution stores (depth, g,
 * element); a compute pass sorts each pixel's list and atomic-mins FOO Eq. 10
 * with exact sums into the element opacities; P3 smooths and fades as for
 * Fourier; list pass 1 at full resolution stores (depth, alpha, colour); a
 * compute pass sorts and blends into r->output. Both per-pixel passes are
 * compute shaders that take each list in rounds of one chunk (MAX_LAYERS
 * entries, nearest first; dispatch_rounds), so no list is capped and no
 * invocation runs into llvmpipe's loop limit (docs/ALGORITHM.md §12). Both
 * list passes share one node pool of fixed size; a pass whose frame it cannot
 * hold runs in bands of rows (build_and_sort), and fragments that still do
 * not fit (a single row past the pool) are counted and reported, never
 * written out of bounds.
 *
 * Sorting (Met.3D thesis §2.4.2-2.4.4): insertion sort for short chunks, a
 * 4-ary heap sort above INSERTION_MAX in the opacity pass; the blend pops
 * long chunks from a 4-ary min-heap front to back until the pixel saturates
 * (transmittance below SATURATION). Fragment reduction (§2.4.1): list pass 1
 * leaves out fragments below REDUCE_BELOW opacity while their pixel's sum of
 * left-out opacity stays within REDUCE_BUDGET. Both bounds together keep
 * every channel within one grey level of full compositing (docs/ALGORITHM.md
 * §12). For measurements only (tests/bench/exact_bench.c):
 * LUCENT_EXACT_SORT=auto|insertion|heap|heap2|auto2 (heap2: the binary heap,
 * auto2: the sort before the 4-ary heap), LUCENT_EXACT_QUEUE=0 (sort whole
 * chunks), LUCENT_EXACT_SATURATION=T, LUCENT_EXACT_REDUCE=0. */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "equalize.h"
#include "exact.h"
#include "foo_math.h"

#define MODULE "exact"

#define NODE_BYTES 16u                    /* uvec4 per node, see exact_common.glsl */
#define DEFAULT_POOL_BYTES (256ull << 20) /* lc_renderer_desc.exact_pool_bytes = 0 */
#define MAX_LAYERS 64                     /* a chunk of a pixel's list: the sort passes' local arrays */
#define INSERTION_MAX 16                  /* longer lists are heap-sorted */
#define END_OF_LIST 0xFFFFFFFFu
#define HEADS_BYTES 28u             /* a pixel's head (4) and its state between rounds (16 + 8) */
#define SATURATION (0.5 / 255.0)    /* the blend stops below this transmittance */
#define REDUCE_BELOW (1.0 / 255.0)  /* list pass 1 may leave out fragments below this opacity ... */
#define REDUCE_BUDGET (0.5 / 255.0) /* ... while their pixel's left-out opacity stays within this */
#define REDUCE_SCALE 16777216.0     /* fixed-point units of opacity in the per-pixel budget: 2^24 */

/* Counter slots (+ list pass 0/1), must match exact_common.glsl. */
enum {
    COUNTER_NODES = 0,
    COUNTER_DROP_POOL = 2,
    COUNTER_MAX_LAYERS = 6,
    COUNTER_COVERED = 8,
    COUNTER_REDUCED = 10,
    COUNTER_LIMITED = 12,
    COUNTER_SLOTS = 16
};

/* color.equalize: 64-bit (low, high) counters of the blend pass, bins 0-255,
 * the halos, the pixels' total coverage (exact_blend.comp.glsl). */
#define EQ_SLOTS (LC_EQUALIZE_BINS + 2)
#define EQ_SCALE 1048576.0 /* fixed-point units per unit of coverage: 2^20 */

/* The list passes' programs; a set each without and with the opaque
 * context's depth test (r->context_layers). */
typedef struct build_programs {
    GLuint build[2][3];      /* [list pass][primitive type] */
    GLuint build_eq[3];      /* list pass 1 keeping colour bins (color.equalize) */
    GLuint build_pulled[3];  /* lines segment by segment (a time window), [list pass + equalize] */
    GLuint build_lines[3];   /* lines as wide line strips (line_primitive.c), the same */
    GLuint build_sprites[3]; /* points as GL points (lc_frame_point_sprites), [list pass + equalize] */
} build_programs;

typedef struct exact_state {
    build_programs programs[2]; /* [context] */
    GLuint opacity, blend, blend_eq;
    GLuint eq_counts; /* EQ_SLOTS x 2 uints */
    GLuint nodes, counters, heads, fbo;
    GLuint reduced;       /* r32ui per output pixel: opacity left out of list pass 1, REDUCE_SCALE units */
    uint32_t capacity;    /* nodes in the pool */
    uint32_t offered0;    /* list pass 0's fragments where the pool could not hold them (built in bands), else 0 */
    uint32_t low_offered; /* list pass 0's fragments, which foretell list pass 1's (composite) */
    uint64_t pool_bytes;
    int heads_w, heads_h;
    int sort_mode;       /* sort_list in exact_common.glsl: 0 auto, 1 insertion, 2 binary heap, 3 4-ary, 4 auto2 */
    int queue;           /* the blend pops long lists from the front-to-back queue */
    float saturation;    /* the blend's transmittance floor */
    int reduce;          /* list pass 1 leaves out fragments below REDUCE_BELOW */
    GLuint state, bound; /* per pixel between the sort passes' rounds (rgba32ui, rg32ui), sized like the heads */
} exact_state;

static exact_state *get_state(lc_renderer *r)
{
    if (r->exact)
        return r->exact;
    exact_state *st = calloc(1, sizeof *st);
    if (!st)
        return NULL;
    static const char *const sorts[] = {"auto", "insertion", "heap2", "heap", "auto2"};
    const char *sort = getenv("LUCENT_EXACT_SORT"), *queue = getenv("LUCENT_EXACT_QUEUE");
    const char *saturation = getenv("LUCENT_EXACT_SATURATION"), *reduce = getenv("LUCENT_EXACT_REDUCE");
    for (int i = 0; sort && i < 5; i++)
        if (strcmp(sort, sorts[i]) == 0)
            st->sort_mode = i;
    st->queue = !(queue && strcmp(queue, "0") == 0);
    st->saturation = saturation ? (float)atof(saturation) : (float)SATURATION;
    st->reduce = !(reduce && strcmp(reduce, "0") == 0);
    glCreateFramebuffers(1, &st->fbo);
    r->exact = st;
    return st;
}

static GLuint build_program(exact_state *st, int pass, int equalize, lc_prim_type prim, int pulled, int lines,
                            int sprites, int context, lc_error *err)
{
    build_programs *set = &st->programs[context != 0];
    GLuint *slot = sprites    ? &set->build_sprites[pass + equalize]
                   : lines    ? &set->build_lines[pass + equalize]
                   : pulled   ? &set->build_pulled[pass + equalize]
                   : equalize ? &set->build_eq[prim]
                              : &set->build[pass][prim];
    if (*slot)
        return *slot;
    static const char *const vs[] = {"common.glsl", "geometry.vert.glsl", NULL};
    static const char *const fs[] = {"common.glsl", "fragment_common.glsl", "exact_common.glsl",
                                     "exact_build.frag.glsl", NULL};
    char defines[224], label[64];
    /* Pass 1 reads the element opacities in the vertex shader (v_alpha). */
    snprintf(defines, sizeof defines, "#define PRIM %d\n#define EXACT_BUILD 1\n#define EXACT_PASS %d\n%s%s%s%s%s%s",
             (int)prim, pass, pass ? "#define READ_ALPHA 1\n" : "", equalize ? "#define EXACT_EQUALIZE 1\n" : "",
             pulled ? "#define PULL_PRIMITIVES 1\n" : "", lines ? "#define LINE_PRIMITIVE 1\n" : "",
             sprites ? "#define POINT_SPRITES 1\n" : "", context ? "#define CONTEXT_DEPTH 1\n" : "");
    snprintf(label, sizeof label, "exact list pass %d%s (%s%s%s)", pass, equalize ? " equalize" : "",
             lc_prim_type_name(prim),
             lines     ? ", lines"
             : pulled  ? ", pulled"
             : sprites ? ", sprites"
                       : "",
             context ? ", context" : "");
    *slot = lc_renderer_build_program(defines, vs, fs, NULL, label, err);
    return *slot;
}

static int ensure_programs(exact_state *st, lc_error *err)
{
    char defines[96];
    if (!st->opacity) {
        static const char *const cs[] = {"exact_common.glsl", "mass_common.glsl", "occluders.glsl",
                                         "exact_opacity.comp.glsl", NULL};
        snprintf(defines, sizeof defines, "#define EXACT_MAX_LAYERS %d\n#define EXACT_SUM_IMPORTANCE 1\n", MAX_LAYERS);
        st->opacity = lc_renderer_build_program(defines, NULL, NULL, cs, "exact opacity", err);
    }
    static const char *const blend_cs[] = {"exact_common.glsl", "exact_blend.comp.glsl", NULL};
    snprintf(defines, sizeof defines, "#define EXACT_MAX_LAYERS %d\n", MAX_LAYERS);
    if (!st->blend)
        st->blend = lc_renderer_build_program(defines, NULL, NULL, blend_cs, "exact blend", err);
    return st->opacity && st->blend ? 0 : LC_ERR_GL;
}

/* The blend pass that also measures the colour histogram, and its counters. */
static int ensure_equalize(exact_state *st, lc_error *err)
{
    if (!st->blend_eq) {
        static const char *const cs[] = {"exact_common.glsl", "exact_blend.comp.glsl", NULL};
        char defines[96];
        snprintf(defines, sizeof defines, "#define EXACT_MAX_LAYERS %d\n#define EXACT_EQUALIZE 1\n", MAX_LAYERS);
        st->blend_eq = lc_renderer_build_program(defines, NULL, NULL, cs, "exact blend equalize", err);
        if (!st->blend_eq)
            return LC_ERR_GL;
    }
    if (!st->eq_counts) {
        glCreateBuffers(1, &st->eq_counts);
        glNamedBufferStorage(st->eq_counts, EQ_SLOTS * 2 * 4, NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    return 0;
}

/* The share of the pool a band is sized to fill: room for rows denser than the mean. */
#define BAND_FILL 0.8
/* List pass 1 starts in bands where list pass 0 foretells this many pools (composite). */
#define FORETOLD_MARGIN 1.25

static _Atomic uint64_t configured_nodes = 0; /* lc_exact_pool_nodes */

/* The pool's nodes: the configured size clamped to what one shader storage block may address. */
static uint64_t pool_nodes(const lc_renderer *r)
{
    uint64_t want = r->desc.exact_pool_bytes ? r->desc.exact_pool_bytes : DEFAULT_POOL_BYTES;
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    if (max_block > 0 && want > (uint64_t)max_block)
        want = (uint64_t)max_block;
    uint64_t nodes = want / NODE_BYTES;
    if (nodes > END_OF_LIST - 1) /* END_OF_LIST is no index */
        nodes = END_OF_LIST - 1;
    return nodes < 1 ? 1 : nodes;
}

void lc_exact_configure(const lc_renderer *r) { lc_exact_pool_configure(pool_nodes(r)); }

void lc_exact_pool_configure(uint64_t nodes) { atomic_store(&configured_nodes, nodes); }

uint64_t lc_exact_pool_nodes(void) { return atomic_load(&configured_nodes); }

int lc_exact_foretold(double fragments, uint64_t nodes) { return nodes && fragments > FORETOLD_MARGIN * (double)nodes; }

int lc_exact_bands(double fragments, uint64_t nodes)
{
    return nodes && fragments > (double)nodes ? (int)ceil(fragments / (BAND_FILL * (double)nodes)) : 1;
}

/* Allocates the node pool once (pool_nodes). */
static int ensure_pool(lc_renderer *r, exact_state *st, lc_error *err)
{
    if (st->nodes)
        return 0;
    uint64_t nodes = pool_nodes(r);
    /* Start from a clean error state so that an out-of-memory below is the pool's (once per renderer). */
    while (glGetError() != GL_NO_ERROR) {
    }
    st->nodes = lc_scratch_buffer(nodes * NODE_BYTES, 0);
    glCreateBuffers(1, &st->counters);
    glNamedBufferStorage(st->counters, COUNTER_SLOTS * 4, NULL, GL_DYNAMIC_STORAGE_BIT);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        glDeleteBuffers(1, &st->nodes);
        glDeleteBuffers(1, &st->counters);
        st->nodes = st->counters = 0;
        return lc_err(err, LC_ERR_GL, "exact: allocating a node pool of %llu MiB failed (GL error 0x%04x)",
                      (unsigned long long)(nodes * NODE_BYTES >> 20), e);
    }
    st->capacity = (uint32_t)nodes;
    st->pool_bytes = nodes * NODE_BYTES + COUNTER_SLOTS * 4;
    /* Counted with the renderer's targets so lc_frame_info.pipeline_bytes covers the pool. */
    r->bytes_targets += st->pool_bytes;
    return 0;
}

/* The per-pixel budget of fragment reduction, sized like the heads. */
static void ensure_reduced(lc_renderer *r, exact_state *st)
{
    if (st->reduced)
        return;
    glCreateTextures(GL_TEXTURE_2D, 1, &st->reduced);
    glTextureStorage2D(st->reduced, 1, GL_R32UI, st->heads_w, st->heads_h);
    r->bytes_targets += (uint64_t)st->heads_w * st->heads_h * 4;
}

static void free_reduced(lc_renderer *r, exact_state *st)
{
    if (!st->reduced)
        return;
    glDeleteTextures(1, &st->reduced);
    r->bytes_targets -= (uint64_t)st->heads_w * st->heads_h * 4;
    st->reduced = 0;
}

/* One r32ui head pointer per output pixel; the optimization-resolution pass
 * uses its lower-left corner. Grows to the largest frame seen. */
static void ensure_heads(lc_renderer *r, exact_state *st, int w, int h)
{
    if (st->heads && st->heads_w >= w && st->heads_h >= h)
        return;
    if (st->heads) {
        free_reduced(r, st); /* sized like the heads */
        glDeleteTextures(1, &st->heads);
        glDeleteTextures(1, &st->state);
        glDeleteTextures(1, &st->bound);
        r->bytes_targets -= (uint64_t)st->heads_w * st->heads_h * HEADS_BYTES;
    }
    st->heads_w = w > st->heads_w ? w : st->heads_w;
    st->heads_h = h > st->heads_h ? h : st->heads_h;
    glCreateTextures(GL_TEXTURE_2D, 1, &st->heads);
    glTextureStorage2D(st->heads, 1, GL_R32UI, st->heads_w, st->heads_h);
    glCreateTextures(GL_TEXTURE_2D, 1, &st->state);
    glTextureStorage2D(st->state, 1, GL_RGBA32UI, st->heads_w, st->heads_h);
    glCreateTextures(GL_TEXTURE_2D, 1, &st->bound);
    glTextureStorage2D(st->bound, 1, GL_RG32UI, st->heads_w, st->heads_h);
    r->bytes_targets += (uint64_t)st->heads_w * st->heads_h * HEADS_BYTES;
}

/* Bindings and uniforms every exact program shares. */
static void bind_lists(const exact_state *st, GLuint prog, int pass)
{
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_EXACT_NODES, st->nodes);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_EXACT_COUNTERS, st->counters);
    glBindImageTexture(IMG_EXACT_HEADS, st->heads, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    lc_uniform_u(prog, "u_pool_capacity", st->capacity);
    lc_uniform_i(prog, "u_list_pass", pass);
    lc_uniform_i(prog, "u_sort_mode", st->sort_mode);
    lc_uniform_i(prog, "u_insertion_max", INSERTION_MAX);
    lc_uniform_i(prog, "u_queue", st->queue);
    lc_uniform_f(prog, "u_saturation", st->saturation);
    lc_uniform_i(prog, "u_two", 2);
    glBindImageTexture(IMG_EXACT_STATE, st->state, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
    glBindImageTexture(IMG_EXACT_BOUND, st->bound, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RG32UI);
}

static void clear_heads(const exact_state *st)
{
    const GLuint end = END_OF_LIST;
    /* The previous pass's image reads must finish before the clear overwrites them. */
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glClearTexImage(st->heads, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &end);
}

/* Draws every primitive of every layer with its list program of `pass`
 * (equalize: the variant that keeps colour bins) into the heads/pool at w x h. */
static int build_lists(lc_renderer *r, exact_state *st, const lc_frame_setup *fs, int pass, int equalize, int w, int h,
                       lc_error *err)
{
    clear_heads(st);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    /* No attachments: the fragment shader only writes the lists. */
    glNamedFramebufferParameteri(st->fbo, GL_FRAMEBUFFER_DEFAULT_WIDTH, w);
    glNamedFramebufferParameteri(st->fbo, GL_FRAMEBUFFER_DEFAULT_HEIGHT, h);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, st->fbo);
    for (int i = 0; i < lc_frame_layer_count(fs); i++) {
        lc_frame_setup tmp;
        const lc_frame_setup *lf = lc_frame_layer(fs, i, &tmp);
        if (!lf)
            continue;
        lc_prim_type prim = lf->gs->scene->type;
        GLuint prog = build_program(st, pass, equalize, prim, lc_pulls_primitives(prim, 1, lf->pull_lines),
                                    prim == LC_PRIM_LINES && lf->line_primitive && !lf->pull_lines,
                                    prim == LC_PRIM_POINTS && lf->point_sprites, r->context_layers, err);
        if (!prog)
            return LC_ERR_GL;
        lc_renderer_bind_geometry(r, prog, lf, w, h, 1);
        if (pass == 1) {
            lc_renderer_bind_halo(prog, lf);
            glBindImageTexture(IMG_EXACT_REDUCED, st->reduced, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
            lc_uniform_f(prog, "u_reduce_below", st->reduce ? (float)REDUCE_BELOW : 0.0f);
            lc_uniform_u(prog, "u_reduce_budget", (GLuint)(REDUCE_BUDGET * REDUCE_SCALE));
            lc_uniform_f(prog, "u_reduce_scale", (float)REDUCE_SCALE);
        }
        bind_lists(st, prog, pass);
        lc_renderer_draw_geometry(lf, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    return 0;
}

/* The equalize blend's counters into r->eq_hist (pixels of coverage), r->eq_cover and r->eq_halo. */
static void read_histogram(lc_renderer *r, const exact_state *st)
{
    uint32_t words[EQ_SLOTS * 2];
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glGetNamedBufferSubData(st->eq_counts, 0, sizeof words, words);
    double v[EQ_SLOTS];
    for (int k = 0; k < EQ_SLOTS; k++) /* integers below 2^53 and a power-of-two scale: exact doubles */
        v[k] = (double)((uint64_t)words[2 * k + 1] << 32 | words[2 * k]) / EQ_SCALE;
    memcpy(r->eq_hist, v, sizeof r->eq_hist);
    r->eq_halo = v[LC_EQUALIZE_BINS];
    r->eq_cover = v[LC_EQUALIZE_BINS + 1];
}

/* Dispatches a sort pass over w x rows pixels in rounds of one chunk of each
 * pixel's list (exact_common.glsl u_round): the first round takes every
 * list's nearest MAX_LAYERS fragments and counts the longest list, which says
 * how many rounds follow. */
static void dispatch_rounds(const exact_state *st, GLuint prog, int pass, int w, int rows)
{
    GLuint gx = (GLuint)(w + 7) / 8, gy = (GLuint)(rows + 7) / 8;
    lc_uniform_i(prog, "u_round", 0);
    glDispatchCompute(gx, gy, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    uint32_t longest = 0;
    glGetNamedBufferSubData(st->counters, (GLintptr)(COUNTER_MAX_LAYERS + pass) * 4, 4, &longest);
    uint32_t rounds = (longest + MAX_LAYERS - 1) / MAX_LAYERS;
    for (uint32_t k = 1; k < rounds; k++) {
        lc_uniform_i(prog, "u_round", (int)k);
        glDispatchCompute(gx, gy, 1);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    }
}

/* The list counters into info (the last composite's full-resolution pass). */
static void report(const exact_state *st, lc_frame_info *info)
{
    uint32_t c[COUNTER_SLOTS];
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(st->counters, 0, sizeof c, c);
    uint64_t dropped = (uint64_t)c[COUNTER_DROP_POOL] + c[COUNTER_DROP_POOL + 1];
    info->fragments = (uint64_t)c[COUNTER_NODES + 1] + c[COUNTER_REDUCED + 1];
    info->reduced_fragments = c[COUNTER_REDUCED + 1];
    info->dropped_fragments = dropped;
    info->max_layers = c[COUNTER_MAX_LAYERS + 1];
    info->mean_layers = c[COUNTER_COVERED + 1] ? (double)c[COUNTER_NODES + 1] / c[COUNTER_COVERED + 1] : 0.0;
    info->cut_lists = (uint64_t)c[COUNTER_LIMITED] + c[COUNTER_LIMITED + 1];
    if (c[COUNTER_LIMITED] || c[COUNTER_LIMITED + 1])
        LC_DEBUG(MODULE,
                 "the driver's loop limit stopped %u + %u list invocations part way (their pixels are not exact)",
                 c[COUNTER_LIMITED], c[COUNTER_LIMITED + 1]);
    if (dropped)
        LC_DEBUG(MODULE, "%llu fragments dropped (pool full: %u + %u of %u nodes)", (unsigned long long)dropped,
                 c[COUNTER_DROP_POOL], c[COUNTER_DROP_POOL + 1], st->capacity);
}

/* Zeroes a list pass's counters (slots `pass`, pass + 2, ...) for its next build. */
static void zero_counters(const exact_state *st, int pass)
{
    const GLuint zero = 0;
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    for (int slot = pass; slot < COUNTER_SLOTS; slot += 2)
        glClearNamedBufferSubData(st->counters, GL_R32UI, slot * 4, 4, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
}

/* Every counter into c. */
static void read_counters(const exact_state *st, uint32_t c[COUNTER_SLOTS])
{
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glGetNamedBufferSubData(st->counters, 0, COUNTER_SLOTS * 4, c);
}

/* List pass `pass` at w x h (the pool is reused from index 0) over rows
 * [y0, y1), the others scissored away where that is not all of them; its
 * counters start from 0. *offered: the fragments offered to the pool,
 * *dropped: those that found it full. */
static int build_rows(lc_renderer *r, exact_state *st, const lc_frame_setup *fs, int pass, int measure, int w, int h,
                      int y0, int y1, uint32_t *offered, uint32_t *dropped, lc_error *err)
{
    zero_counters(st, pass);
    if (pass == 1) {
        const GLuint zero = 0;
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
        glClearTexImage(st->reduced, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    }
    int band = y0 > 0 || y1 < h;
    if (band) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(0, y0, w, y1 - y0);
    }
    int rc = build_lists(r, st, fs, pass, measure, w, h, err);
    if (band)
        glDisable(GL_SCISSOR_TEST);
    uint32_t c[COUNTER_SLOTS];
    read_counters(st, c);
    *offered = c[COUNTER_NODES + pass];
    *dropped = c[COUNTER_DROP_POOL + pass];
    return rc;
}

/* What a list pass does with a band of rows once it is built: sorts it into
 * the element opacities (pass 0) or blends it into the output (pass 1). */
typedef void (*sort_rows_fn)(lc_renderer *r, exact_state *st, const lc_frame_setup *fs, int measure, int y0, int y1);

/* List pass `pass` at w x h and its sort, the whole frame at once where the
 * pool holds it. Where it does not, the pass is taken in bands of rows (the
 * scissor keeps each band's fragments alone in the pool): a pixel's list is
 * then the same as in the whole frame, the same fragments in the same order,
 * so the result is the one a pool large enough would give, where dropping
 * the fragments stored last would follow the rasterizer threads' order. The
 * bands are sized from the fragments the whole frame offered over 0.8 of the
 * pool; a band that still overflows (its rows denser than the mean) is halved
 * and built again before any of it is sorted, and the bands after it grow
 * back to the mean's size, doubling. A single row past the pool
 * keeps its drops, counted and reported. Each band costs a traversal of the
 * geometry. *offered: the whole frame's fragments offered to the pool, 0 to
 * build it whole first (else it is known or foretold to need bands); *bands:
 * how many. */
static int build_and_sort(lc_renderer *r, exact_state *st, const lc_frame_setup *fs, int pass, int measure, int w,
                          int h, sort_rows_fn sort, uint32_t *offered, int *bands, lc_error *err)
{
    uint32_t dropped = 0, band_offered = 0, c[COUNTER_SLOTS], total[COUNTER_SLOTS] = {0};
    *bands = 1;
    if (!*offered) {
        int rc = build_rows(r, st, fs, pass, measure, w, h, 0, h, offered, &dropped, err);
        if (pass == 1) /* the list's time; where it takes bands, they count as the blend's */
            lc_renderer_timestamp(r, LC_PASS_OPTICAL_DEPTH);
        if (rc || !dropped) {
            if (!rc)
                sort(r, st, fs, measure, 0, h);
            return rc;
        }
    } else if (pass == 1) /* no whole-frame build (foretold): the bands count as the blend's time */
        lc_renderer_timestamp(r, LC_PASS_OPTICAL_DEPTH);
    int n = lc_exact_bands(*offered, st->capacity), full_rows = (h + n - 1) / n, rows = full_rows, rc = 0;
    *bands = 0;
    for (int y = 0; y < h;) {
        int y1 = y + rows < h ? y + rows : h;
        if ((rc = build_rows(r, st, fs, pass, measure, w, h, y, y1, &band_offered, &dropped, err)) != 0)
            return rc;
        if (dropped && y1 - y > 1) { /* denser than the mean: half the rows */
            rows = (y1 - y + 1) / 2;
            continue;
        }
        sort(r, st, fs, measure, y, y1);
        read_counters(st, c); /* the band's, with its sort's (the next build zeroes them) */
        for (int slot = pass; slot < COUNTER_SLOTS; slot += 2)
            total[slot] = slot == COUNTER_MAX_LAYERS + pass ? (c[slot] > total[slot] ? c[slot] : total[slot])
                                                            : total[slot] + c[slot];
        (*bands)++;
        y = y1;
        rows = 2 * rows < full_rows ? 2 * rows : full_rows; /* past the dense rows, back toward the mean's size */
    }
    for (int slot = pass; slot < COUNTER_SLOTS; slot += 2) /* the whole frame's, for report() */
        glNamedBufferSubData(st->counters, slot * 4, 4, &total[slot]);
    LC_DEBUG(MODULE, "list pass %d in %d bands of rows (%u fragments offered, a pool of %u nodes)", pass, *bands,
             *offered, st->capacity);
    return 0;
}

/* Sorts and blends rows [y0, y1) front to back into the output (accumulate
 * and resolve in one pass), over the opaque context's colour where there is
 * one; measure: counts the colour histogram. */
static void blend_rows(lc_renderer *r, exact_state *st, const lc_frame_setup *fs, int measure, int y0, int y1)
{
    const lc_render_params *p = fs->params;
    GLuint blend = measure ? st->blend_eq : st->blend;
    glUseProgram(blend);
    bind_lists(st, blend, 1);
    if (measure) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_COLOR_HISTOGRAM, st->eq_counts);
        lc_uniform_f(blend, "u_eq_scale", (float)EQ_SCALE);
    }
    glBindImageTexture(IMG_EXACT_OUTPUT, r->output.tex[0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glProgramUniform2i(blend, glGetUniformLocation(blend, "u_size"), fs->width, y1);
    lc_uniform_i(blend, "u_first_row", y0);
    glProgramUniform3f(blend, glGetUniformLocation(blend, "u_background"), (float)p->style.background[0],
                       (float)p->style.background[1], (float)p->style.background[2]);
    lc_uniform_i(blend, "u_context", fs->context_color ? 1 : 0);
    if (fs->context_color)
        glBindTextureUnit(TEX_CONTEXT_COLOR, fs->context_color);
    dispatch_rounds(st, blend, 1, fs->width, y1 - y0);
}

/* List pass 1 (full resolution: depth, opacity, colour) and the blend, in
 * bands of rows where the pool cannot hold the frame (build_and_sort). */
static int composite(lc_renderer *r, exact_state *st, lc_frame_setup *fs, int measure, lc_frame_info *info,
                     lc_error *err)
{
    ensure_reduced(r, st);
    if (measure) {
        const GLuint zero = 0;
        glClearNamedBufferData(st->eq_counts, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    /* List pass 0's fragments scaled by the pixels foretell this pass's: well
     * past the pool, the bands start without building the whole frame first
     * (on the MD trajectories at 1024², 1.2 s of 4). Near it, the whole frame
     * is tried: lines thinner than a pixel at the optimization resolution
     * give fewer than the scale at full resolution, and fragment reduction
     * stores fewer still. */
    double scale = (double)fs->width * fs->height / ((double)fs->low_width * fs->low_height);
    double foretold = st->low_offered * scale;
    uint32_t offered =
        lc_exact_foretold(foretold, st->capacity) && foretold < (double)UINT32_MAX ? (uint32_t)foretold : 0;
    int rc =
        build_and_sort(r, st, fs, 1, measure, fs->width, fs->height, blend_rows, &offered, &info->exact_bands, err);
    if (rc)
        return rc;
    /* lc_render_frame reads the output back through its framebuffer. */
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);
    lc_renderer_timestamp(r, LC_PASS_ACCUMULATE);
    lc_renderer_timestamp(r, LC_PASS_RESOLVE);
    report(st, info);
    return 0;
}

/* Sorts rows [y0, y1) of list pass 0 into the element opacities: the exact
 * sums and FOO Eq. 10, atomic-min per element (as P2), with the uniforms
 * exact_optimize set. Bound again for every band: the list pass between
 * binds the geometry's buffers. */
static void opacity_rows(lc_renderer *r, exact_state *st, const lc_frame_setup *fs, int measure, int y0, int y1)
{
    (void)measure;
    lc_error ignored = {0};
    lc_element_emphasis_bind(r, fs, st->opacity, &ignored); /* made before the first band: cannot fail here */
    glUseProgram(st->opacity);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_ALPHA_MIN, r->element_alpha_min);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_MASS_HISTOGRAM, r->mass_histogram);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_ELEMENT_BEHIND, r->element_behind);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_IMPORTANT_OCCLUDED, r->important_occluded);
    bind_lists(st, st->opacity, 0);
    glProgramUniform2i(st->opacity, glGetUniformLocation(st->opacity, "u_size"), fs->low_width, y1);
    lc_uniform_i(st->opacity, "u_first_row", y0);
    dispatch_rounds(st, st->opacity, 0, fs->low_width, y1 - y0);
}

/* The exact opacities at the strength of fs->params from list pass 0, P3 and
 * the visibility report; the step params.clarity's loop repeats (clarity.c).
 * The list is built once (it does not depend on q, r or λ) where the pool
 * holds it; else each try builds it again band by band (build_and_sort). */
static int exact_optimize(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, lc_frame_info *info,
                          int moments, lc_error *err)
{
    (void)moments; /* no Fourier moments here */
    const lc_render_params *p = fs->params;
    exact_state *st = r->exact;
    int rc = lc_element_emphasis_bind(r, fs, st->opacity, err);
    if (rc)
        return rc;
    const float sentinel = 2.0f; /* > 1: "no fragment this frame" (p3_smooth.comp.glsl) */
    glClearNamedBufferData(r->element_alpha_min, GL_R32F, GL_RED, GL_FLOAT, &sentinel);
    lc_occluders_clear(r);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    lc_mass_clear(r);
    lc_uniform_f(st->opacity, "u_q", p->foo.q);
    lc_uniform_f(st->opacity, "u_r", p->foo.r);
    lc_uniform_f(st->opacity, "u_lambda", p->foo.lambda); /* the shader applies lc_foo_effective_lambda */
    lc_uniform_f(st->opacity, "u_norm_mass", lc_foo_norm_mass(&p->foo));
    lc_uniform_f(st->opacity, "u_target_opacity", lc_foo_target_opacity(&p->foo));
    lc_uniform_i(st->opacity, "u_exclude_self", p->foo.exclude_self);
    if (st->offered0) {
        int bands = 0;
        rc = build_and_sort(r, st, fs, 0, 0, fs->low_width, fs->low_height, opacity_rows, &st->offered0, &bands, err);
        if (rc)
            return rc;
    } else
        opacity_rows(r, st, fs, 0, 0, fs->low_height);
    lc_renderer_timestamp(r, LC_PASS_OPACITY);

    /* P3 exactly as the Fourier path, so the two differ only in P1/P2 and compositing. */
    lc_mass_report(r, fs, info);
    rc = lc_renderer_smooth_and_fade(r, fs, state, dt, info, err);
    if (!rc) /* layered frames: per layer and over the transparent layers together */
        rc = lc_visibility_measure(r, fs, state ? state->alpha : NULL, info, err);
    lc_renderer_timestamp(r, LC_PASS_SMOOTH);
    return rc;
}

int lc_render_exact(lc_renderer *r, lc_frame_setup *fs, lc_frame_state *state, double dt, uint8_t *rgba,
                    lc_frame_info *info, lc_error *err)
{
    (void)rgba; /* lc_render_frame reads r->output back */
    const lc_render_params *p = fs->params;
    exact_state *st = get_state(r);
    if (!st)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    int rc = ensure_pool(r, st, err);
    if (rc)
        return rc;
    if ((rc = ensure_programs(st, err)) != 0)
        return rc;
    ensure_heads(r, st, fs->width, fs->height);
    const GLuint zero = 0;
    glClearNamedBufferData(st->counters, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);

    /* List pass 0 (optimization resolution): depth, importance, element;
     * where the pool cannot hold it, each try of the loop below builds it in
     * bands (exact_optimize). */
    uint32_t dropped = 0;
    if ((rc = build_rows(r, st, fs, 0, 0, fs->low_width, fs->low_height, 0, fs->low_height, &st->low_offered, &dropped,
                         err)) != 0)
        return rc;
    st->offered0 = dropped ? st->low_offered : 0;
    lc_renderer_timestamp(r, LC_PASS_IMPORTANCE);
    /* The opacities, under params.clarity's loop when it is active. */
    if ((rc = lc_clarity_optimize(r, fs, state, dt, info, 0, exact_optimize, err)) != 0)
        return rc;

    /* List pass 1 and the blend; with color.equalize they measure the colour
     * histogram, and a one-shot frame (or a session's first) runs them again
     * with this view's equalized colormap (color_equalize.c). */
    if (!p->color.equalize)
        return composite(r, st, fs, 0, info, err);
    if ((rc = ensure_equalize(st, err)) != 0)
        return rc;
    lc_color_equalize_reset(r);
    if ((rc = composite(r, st, fs, 1, info, err)) != 0)
        return rc;
    read_histogram(r, st);
    int again = 0;
    rc = lc_color_equalize_finish(r, fs, state, dt, !(state && state->eq[0].valid), &again, err);
    return rc || !again ? rc : composite(r, st, fs, 0, info, err); /* full-precision colour */
}

void lc_exact_release(lc_renderer *r)
{
    exact_state *st = r->exact;
    if (!st)
        return;
    if (st->nodes) {
        lc_scratch_discard(&st->nodes);
        glDeleteBuffers(1, &st->counters);
        r->bytes_targets -= st->pool_bytes;
        st->nodes = st->counters = 0;
        st->capacity = 0;
        st->pool_bytes = 0;
    }
    if (st->heads) {
        free_reduced(r, st);
        glDeleteTextures(1, &st->heads);
        glDeleteTextures(1, &st->state);
        glDeleteTextures(1, &st->bound);
        r->bytes_targets -= (uint64_t)st->heads_w * st->heads_h * HEADS_BYTES;
        st->heads = 0;
        st->heads_w = st->heads_h = 0;
    }
}

void lc_exact_destroy(lc_renderer *r)
{
    exact_state *st = r->exact;
    if (!st)
        return;
    for (int c = 0; c < 2; c++) {
        const build_programs *set = &st->programs[c];
        for (int prim = 0; prim < 3; prim++) {
            for (int pass = 0; pass < 2; pass++)
                if (set->build[pass][prim])
                    glDeleteProgram(set->build[pass][prim]);
            if (set->build_eq[prim])
                glDeleteProgram(set->build_eq[prim]);
            if (set->build_pulled[prim])
                glDeleteProgram(set->build_pulled[prim]);
            if (set->build_lines[prim])
                glDeleteProgram(set->build_lines[prim]);
            if (set->build_sprites[prim])
                glDeleteProgram(set->build_sprites[prim]);
        }
    }
    if (st->blend_eq)
        glDeleteProgram(st->blend_eq);
    if (st->eq_counts)
        glDeleteBuffers(1, &st->eq_counts);
    if (st->opacity)
        glDeleteProgram(st->opacity);
    if (st->blend)
        glDeleteProgram(st->blend);
    lc_exact_release(r);
    glDeleteFramebuffers(1, &st->fbo);
    free(st);
    r->exact = NULL;
}
