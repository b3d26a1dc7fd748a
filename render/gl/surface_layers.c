/* Progressive transparent integral surfaces (PRT; docs/ALGORITHM.md §23):
 * per batch, the curves are drawn as lines into per-pixel fragment linked
 * lists (as the exact method's lists, exact.c); a compute pass merges each
 * pixel's list into that pixel's persistent, depth-sorted array of at most K
 * layers; a compute pass composites the layers front to back.
 *
 * One buffer of uints (BIND_SURFACE_PIXELS) holds the counters, the list
 * heads, the layer counts and the packed output, so that the module takes
 * three storage bindings (llvmpipe offers 32). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_context.h"
#include "renderer_internal.h"
#include "surface_layers.h"

#define MODULE "surface-layers"

#define FRAGMENT_BYTES 32u /* SurfaceFragment, surface_layers_common.glsl */
#define LAYER_BYTES 32u    /* SurfaceLayer */
#define HEADS_OFFSET 16u   /* uints before the heads: the counters */
#define DEFAULT_K 16
#define DEFAULT_POOL (2ull << 20) /* fragments of one batch (64 MiB) */
#define END_OF_LIST 0xFFFFFFFFu
#define AMBIENT 0.3 /* shade = ambient + (1 - ambient) |n.z| */
#define GROUP 64    /* local_size_x of the compute passes */

enum { COUNTER_NODES = 0, COUNTER_POOL_DROP = 1, COUNTER_MERGED = 2, COUNTER_OVERFLOW = 3 };

/* The three programs of a context. Buffers are shared by a share group, but
 * programs are used only on the context that built them (Mesa keeps compiled
 * variants per context; llvmpipe crashed drawing with another context's): a
 * thread keeps those of the context current on it, and rebuilds when another
 * context is made current there (the old ones go with their context). */
typedef struct programs {
    uint64_t serial; /* lc_gl_current_serial of their context (0: a context made current outside lc_gl) */
    GLuint build, merge, composite;
} programs;

static _Thread_local programs thread_programs;

struct lc_surface_layers {
    lc_surface_layers_desc desc;
    uint32_t pixel_count;
    uint32_t pool_capacity;
    programs own; /* under a context lc_gl does not know (serial 0): this object's own, deleted with it */
    /* Programs and buffers only: objects a context's share group shares, so
     * that the layers may grow on any of the group's contexts (the vertex
     * array and framebuffer of a batch are made per batch). */
    GLuint nodes, pixels, layers, vertices;
    GLsizeiptr vertex_bytes;
    uint64_t fragments, merged, overflow, pool_dropped, curves;
};

static int check_desc(const lc_surface_layers_desc *d, lc_error *err)
{
    if (d->width < 1 || d->width > 8192 || d->height < 1 || d->height > 8192)
        return lc_err(err, LC_ERR_INVALID, "surface layers: width and height must lie in 1..8192 (got %d x %d)",
                      d->width, d->height);
    if (d->max_layers < 0 || d->max_layers > LC_SURFACE_LAYERS_MAX_K)
        return lc_err(err, LC_ERR_INVALID, "surface layers: max_layers must lie in 0..%d (got %d)",
                      LC_SURFACE_LAYERS_MAX_K, d->max_layers);
    if (d->composite < LC_SURFACE_COMPOSITE_LAYERS || d->composite > LC_SURFACE_COMPOSITE_WEIGHTED_SUM)
        return lc_err(err, LC_ERR_INVALID, "surface layers: composite must be 0, 1 or 2 (got %d)", d->composite);
    if (!isfinite(d->epsilon) || d->epsilon < 0)
        return lc_err(err, LC_ERR_INVALID, "surface layers: epsilon must be finite and >= 0 (got %g)", d->epsilon);
    if (!isfinite(d->opacity) || d->opacity < 0 || d->opacity > 1)
        return lc_err(err, LC_ERR_INVALID, "surface layers: opacity must lie in [0, 1] (0 = 0.5; got %g)", d->opacity);
    for (int i = 0; i < 16; i++)
        if (!isfinite(d->view[i]) || !isfinite(d->projection[i]))
            return lc_err(err, LC_ERR_INVALID, "surface layers: view and projection must be finite");
    return 0;
}

static int build_programs(programs *p, lc_error *err)
{
    static const char *const vs[] = {"surface_layers_build.vert.glsl", NULL};
    static const char *const fs[] = {"surface_layers_common.glsl", "surface_layers_build.frag.glsl", NULL};
    static const char *const merge[] = {"surface_layers_common.glsl", "surface_layers_merge.comp.glsl", NULL};
    static const char *const comp[] = {"surface_layers_common.glsl", "weighted_average.glsl",
                                       "surface_layers_composite.comp.glsl", NULL};
    p->build = lc_renderer_build_program("", vs, fs, NULL, "surface layers: lists", err);
    if (p->build)
        p->merge = lc_renderer_build_program("", NULL, NULL, merge, "surface layers: merge", err);
    if (p->merge)
        p->composite = lc_renderer_build_program("", NULL, NULL, comp, "surface layers: composite", err);
    if (p->composite)
        return 0;
    GLuint progs[3] = {p->build, p->merge, p->composite};
    for (int i = 0; i < 3; i++)
        if (progs[i])
            glDeleteProgram(progs[i]);
    return LC_ERR_GL;
}

static void set_uniforms(const lc_surface_layers *sl, const programs *p)
{
    const lc_surface_layers_desc *d = &sl->desc;
    GLuint progs[3] = {p->build, p->merge, p->composite};
    for (int i = 0; i < 3; i++) {
        lc_uniform_u(progs[i], "u_pixel_count", sl->pixel_count);
        lc_uniform_u(progs[i], "u_pool_capacity", sl->pool_capacity);
    }
    glProgramUniformMatrix4fv(p->build, glGetUniformLocation(p->build, "u_view"), 1, GL_FALSE, d->view);
    glProgramUniformMatrix4fv(p->build, glGetUniformLocation(p->build, "u_projection"), 1, GL_FALSE, d->projection);
    lc_uniform_i(p->build, "u_width", d->width);
    lc_uniform_u(p->merge, "u_max_layers", (unsigned)d->max_layers);
    lc_uniform_f(p->merge, "u_epsilon", d->epsilon);
    lc_uniform_u(p->composite, "u_max_layers", (unsigned)d->max_layers);
    lc_uniform_f(p->composite, "u_opacity", d->opacity);
    lc_uniform_f(p->composite, "u_ambient", AMBIENT);
    lc_uniform_v3(p->composite, "u_background", d->background);
    lc_uniform_i(p->composite, "u_composite", d->composite);
}

/* The current context's programs with this object's uniforms (several
 * objects share a thread's programs, so they are set at every use). */
static const programs *use_programs(lc_surface_layers *sl, lc_error *err)
{
    uint64_t serial = lc_gl_current_serial();
    programs *p = serial ? &thread_programs : &sl->own;
    if (!p->composite || p->serial != serial) {
        programs fresh = {.serial = serial};
        if (build_programs(&fresh, err) != 0)
            return NULL;
        *p = fresh;
    }
    set_uniforms(sl, p);
    return p;
}

long long lc_surface_layers_block_bytes(void)
{
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    return max_block > 0 ? (long long)max_block : 0;
}

int lc_surface_layers_create(const lc_surface_layers_desc *desc, lc_surface_layers **out, lc_error *err)
{
    *out = NULL;
    int rc = check_desc(desc, err);
    if (rc)
        return rc;
    lc_surface_layers *sl = calloc(1, sizeof *sl);
    if (!sl)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    sl->desc = *desc;
    if (!sl->desc.max_layers)
        sl->desc.max_layers = DEFAULT_K;
    if (sl->desc.opacity == 0)
        sl->desc.opacity = 0.5;
    sl->pixel_count = (uint32_t)desc->width * (uint32_t)desc->height;
    uint64_t pool = desc->pool_fragments ? desc->pool_fragments : DEFAULT_POOL;
    uint64_t layer_bytes = (uint64_t)sl->pixel_count * (uint64_t)sl->desc.max_layers * LAYER_BYTES;
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    if (max_block > 0 && pool * FRAGMENT_BYTES > (uint64_t)max_block)
        pool = (uint64_t)max_block / FRAGMENT_BYTES;
    if (pool > END_OF_LIST - 1)
        pool = END_OF_LIST - 1;
    sl->pool_capacity = (uint32_t)pool;
    if (max_block > 0 && layer_bytes > (uint64_t)max_block) {
        free(sl);
        return lc_err(err, LC_ERR_INVALID,
                      "surface layers: width * height * max_layers needs %llu MiB of layers, more than one storage "
                      "block may hold (%llu MiB)",
                      (unsigned long long)(layer_bytes >> 20), (unsigned long long)(max_block >> 20));
    }
    if (!use_programs(sl, err)) { /* built now: shader errors show at creation */
        lc_surface_layers_destroy(sl);
        return LC_ERR_GL;
    }
    while (glGetError() != GL_NO_ERROR) {
    }
    /* Scratch (scratch.c): written by the fragment shader, so llvmpipe's idle
     * scenes would keep them after the destroy. */
    sl->nodes = lc_scratch_buffer(pool * FRAGMENT_BYTES, 0);
    sl->pixels = lc_scratch_buffer((HEADS_OFFSET + 3ull * sl->pixel_count) * 4, GL_DYNAMIC_STORAGE_BIT);
    sl->layers = lc_scratch_buffer(layer_bytes, 0);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        lc_surface_layers_destroy(sl);
        return lc_err(err, LC_ERR_GL, "surface layers: allocating %llu MiB of fragments and layers failed (GL 0x%04x)",
                      (unsigned long long)((pool * FRAGMENT_BYTES + layer_bytes) >> 20), e);
    }
    lc_surface_layers_reset(sl);
    *out = sl;
    return 0;
}

void lc_surface_layers_destroy(lc_surface_layers *sl)
{
    if (!sl)
        return;
    GLuint progs[3] = {sl->own.build, sl->own.merge, sl->own.composite};
    for (int i = 0; i < 3; i++)
        if (progs[i])
            glDeleteProgram(progs[i]);
    lc_scratch_discard(&sl->nodes);
    lc_scratch_discard(&sl->pixels);
    lc_scratch_discard(&sl->layers);
    if (sl->vertices)
        glDeleteBuffers(1, &sl->vertices);
    free(sl);
}

void lc_surface_layers_reset(lc_surface_layers *sl)
{
    const GLuint zero = 0;
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    /* Layer counts 0 empty every pixel; the layers' contents are then never read. */
    glClearNamedBufferData(sl->pixels, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    sl->fragments = sl->merged = sl->overflow = sl->pool_dropped = sl->curves = 0;
}

/* Uploads the curves' vertices; fills first/count per drawable curve. */
static int upload_curves(lc_surface_layers *sl, const lc_trace_curve *curves, uint32_t count, GLint *first, GLsizei *n,
                         GLsizei *draws, lc_error *err)
{
    uint64_t vertices = 0;
    for (uint32_t i = 0; i < count; i++)
        vertices += curves[i].n;
    if (vertices > (1ull << 28))
        return lc_err(err, LC_ERR_INVALID, "surface layers: %llu vertices in one batch (at most 2^28)",
                      (unsigned long long)vertices);
    float *v = malloc((size_t)(vertices ? vertices : 1) * 6 * sizeof(float));
    if (!v)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    uint64_t at = 0;
    *draws = 0;
    for (uint32_t i = 0; i < count; i++) {
        const lc_trace_curve *c = &curves[i];
        if (c->n >= 2) { /* a 1-vertex curve (seeded outside) draws nothing */
            first[*draws] = (GLint)at;
            n[*draws] = (GLsizei)c->n;
            (*draws)++;
        }
        for (uint32_t k = 0; k < c->n; k++, at++) {
            memcpy(v + 6 * at, c->xyz + 3 * k, 3 * sizeof(float));
            memcpy(v + 6 * at + 3, c->normal + 3 * k, 3 * sizeof(float));
        }
    }
    GLsizeiptr bytes = (GLsizeiptr)(vertices ? vertices : 1) * 6 * (GLsizeiptr)sizeof(float);
    if (!sl->vertices || bytes > sl->vertex_bytes) {
        if (sl->vertices)
            glDeleteBuffers(1, &sl->vertices);
        glCreateBuffers(1, &sl->vertices);
        glNamedBufferStorage(sl->vertices, bytes, NULL, GL_DYNAMIC_STORAGE_BIT);
        sl->vertex_bytes = bytes;
    }
    glNamedBufferSubData(sl->vertices, 0, bytes, v);
    free(v);
    return 0;
}

int lc_surface_layers_add(lc_surface_layers *sl, const lc_trace_curve *curves, uint32_t count, const float rgb[3],
                          lc_error *err)
{
    if (!count)
        return 0;
    for (int c = 0; c < 3; c++)
        if (!(rgb[c] >= 0.0f && rgb[c] <= 1.0f))
            return lc_err(err, LC_ERR_INVALID, "surface layers: colour components must lie in [0, 1]");
    const programs *pg = use_programs(sl, err);
    if (!pg)
        return LC_ERR_GL;
    GLint *first = malloc(count * sizeof *first);
    GLsizei *n = malloc(count * sizeof *n), draws = 0;
    int rc = first && n ? upload_curves(sl, curves, count, first, n, &draws, err)
                        : lc_err(err, LC_ERR_NOMEM, "out of memory");
    if (rc) {
        free(first);
        free(n);
        return rc;
    }
    /* Empty lists and zero the batch counters (the layer counts stay). */
    const GLuint zero = 0, end = END_OF_LIST;
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glClearNamedBufferSubData(sl->pixels, GL_R32UI, 0, HEADS_OFFSET * 4, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glClearNamedBufferSubData(sl->pixels, GL_R32UI, HEADS_OFFSET * 4, (GLsizeiptr)sl->pixel_count * 4, GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &end);
    glProgramUniform3f(pg->build, glGetUniformLocation(pg->build, "u_color"), rgb[0], rgb[1], rgb[2]);

    /* This context's vertex array and framebuffer (not shared: made per batch). */
    GLuint vao = 0, fbo = 0;
    glCreateVertexArrays(1, &vao);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferParameteri(fbo, GL_FRAMEBUFFER_DEFAULT_WIDTH, sl->desc.width);
    glNamedFramebufferParameteri(fbo, GL_FRAMEBUFFER_DEFAULT_HEIGHT, sl->desc.height);
    /* Interleaved (position, normal) floats, binding 0. */
    glEnableVertexArrayAttrib(vao, 0);
    glEnableVertexArrayAttrib(vao, 1);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribFormat(vao, 1, 3, GL_FLOAT, GL_FALSE, 12);
    glVertexArrayAttribBinding(vao, 0, 0);
    glVertexArrayAttribBinding(vao, 1, 0);
    glVertexArrayVertexBuffer(vao, 0, sl->vertices, 0, 6 * sizeof(float));
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glViewport(0, 0, sl->desc.width, sl->desc.height);
    glUseProgram(pg->build);
    glBindVertexArray(vao);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SURFACE_NODES, sl->nodes);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SURFACE_PIXELS, sl->pixels);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SURFACE_LAYERS, sl->layers);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
    if (draws)
        glMultiDrawArrays(GL_LINE_STRIP, first, n, draws);
    glBindVertexArray(0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    free(first);
    free(n);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    glUseProgram(pg->merge);
    glDispatchCompute((sl->pixel_count + GROUP - 1) / GROUP, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    uint32_t c[4];
    glGetNamedBufferSubData(sl->pixels, 0, sizeof c, c);
    sl->fragments += c[COUNTER_NODES];
    sl->pool_dropped += c[COUNTER_POOL_DROP];
    sl->merged += c[COUNTER_MERGED];
    sl->overflow += c[COUNTER_OVERFLOW];
    sl->curves += count;
    if (c[COUNTER_POOL_DROP] || c[COUNTER_OVERFLOW])
        LC_DEBUG(MODULE, "batch of %u curves: %u fragments found the pool (%u) full, %u beyond K = %d layers", count,
                 c[COUNTER_POOL_DROP], sl->pool_capacity, c[COUNTER_OVERFLOW], sl->desc.max_layers);
    GLenum e = glGetError();
    return e == GL_NO_ERROR ? 0 : lc_err(err, LC_ERR_GL, "surface layers: GL error 0x%04x in a batch", e);
}

/* Copies the section of w * h uints at offset (in uints) of the pixel words
 * into out (any alignment) with the rows flipped (GL's rows start at the bottom). */
static int read_section(lc_surface_layers *sl, uint32_t offset, void *out, lc_error *err)
{
    uint32_t *tmp = malloc((size_t)sl->pixel_count * 4);
    if (!tmp)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(sl->pixels, (GLintptr)offset * 4, (GLsizeiptr)sl->pixel_count * 4, tmp);
    int w = sl->desc.width, h = sl->desc.height;
    for (int y = 0; y < h; y++)
        memcpy((uint8_t *)out + (size_t)y * w * 4, tmp + (size_t)(h - 1 - y) * w, (size_t)w * 4);
    free(tmp);
    return 0;
}

int lc_surface_layers_composite(lc_surface_layers *sl, uint8_t *rgba, lc_error *err)
{
    const programs *pg = use_programs(sl, err);
    if (!pg)
        return LC_ERR_GL;
    glUseProgram(pg->composite);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SURFACE_PIXELS, sl->pixels);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SURFACE_LAYERS, sl->layers);
    glDispatchCompute((sl->pixel_count + GROUP - 1) / GROUP, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    /* packUnorm4x8 puts r in the low byte: little-endian words are RGBA bytes. */
    return read_section(sl, HEADS_OFFSET + 2 * sl->pixel_count, rgba, err);
}

int lc_surface_layers_read(lc_surface_layers *sl, uint32_t *layer_counts, lc_surface_layers_stats *stats, lc_error *err)
{
    uint32_t *counts = layer_counts ? layer_counts : malloc((size_t)sl->pixel_count * 4);
    if (!counts)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    int rc = read_section(sl, HEADS_OFFSET + sl->pixel_count, counts, err);
    if (!rc && stats) {
        memset(stats, 0, sizeof *stats);
        uint64_t total = 0;
        for (uint32_t i = 0; i < sl->pixel_count; i++) {
            if (counts[i]) {
                stats->covered_pixels++;
                total += counts[i];
            }
            if (counts[i] > stats->max_layers)
                stats->max_layers = counts[i];
        }
        stats->mean_layers = stats->covered_pixels ? (double)total / stats->covered_pixels : 0.0;
        stats->fragments = sl->fragments;
        stats->merged = sl->merged;
        stats->overflow = sl->overflow;
        stats->pool_dropped = sl->pool_dropped;
        stats->curves = sl->curves;
    }
    if (!layer_counts)
        free(counts);
    /* The read-back waited for the layers; finishing the rest makes them safe
     * to continue on another context of the share group (GL 4.5 §5.3). */
    glFinish();
    return rc;
}
