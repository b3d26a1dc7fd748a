/* The GPU copy of a scene: vertex, attribute, element and index buffers,
 * uploaded once and shared by every context of the share group. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"
#include "vertex_pack.h"

GLuint lc_gl_buffer(const void *data, size_t size, uint64_t *bytes)
{
    GLuint b;
    glCreateBuffers(1, &b);
    /* Zero-size storage is invalid; keep one vec4 so a binding is always valid. */
    glNamedBufferStorage(b, size ? (GLsizeiptr)size : 16, size ? data : NULL, 0);
    *bytes += size ? size : 16;
    return b;
}

/* Strip indices of `segments` segments in at most `runs` runs (each run: two
 * per vertex; between runs: two restarts). */
static uint64_t strip_indices(uint64_t segments, uint64_t runs)
{
    return runs ? 2 * (segments + runs) + 2 * (runs - 1) : 0;
}

/* Estimate and upload share this: the byte count of every buffer of the
 * layout that desc gives s (attribute formats from the scene's ranges). */
static void layout_bytes(const lc_scene *s, const lc_gpu_scene_desc *desc, lc_blend_layout blend, int built,
                         lc_gpu_memory *m)
{
    memset(m, 0, sizeof *m);
    uint32_t n = s->vertex_count;
    int exact = desc && desc->exact_positions;
    int framed = s->type != LC_PRIM_POINTS;
    if (exact) {
        m->positions = (uint64_t)n * 16;
        m->frames = framed ? (uint64_t)n * 16 : 0;
        m->attributes = (uint64_t)n * 4 * (uint64_t)s->attribute_count;
        m->colors = lc_scene_has_rgb(s) ? (uint64_t)n * 12 : 0;
    } else {
        m->positions = lc_pack_positions_bytes(n) + lc_pack_chunks_bytes(n, lc_pack_chunk_phase(s));
        m->frames = framed ? (uint64_t)n * 4 : 0;
        for (int a = 0; a < s->attribute_count; a++)
            m->attributes +=
                lc_pack_attribute_is_unorm16(&s->attributes[a]) ? lc_pack_unorm16_bytes(n) : (uint64_t)n * 4;
        m->colors = lc_scene_has_rgb(s) ? (uint64_t)n * 4 : 0;
    }
    m->vertex_elements = lc_pack_blend_bytes(blend, n);
    uint64_t prims = lc_scene_primitive_count(s);
    /* Lines: ribbon strips (renderer_internal.h; the pulled subset path reads
     * the same buffer) and the line strips of half their length; triangles: the scene's own index buffer. The coarser
     * levels of detail hold at most as much again (lod.h), which an estimate
     * counts in full. */
    m->indices = s->type == LC_PRIM_LINES       ? strip_indices(prims, s->line_count) * 4 * 3 / 2
                 : s->type == LC_PRIM_TRIANGLES ? prims * 12
                                                : 0;
    if (!built)
        m->indices *= 2;
    /* Offsets, neighbour ids and their distance weights (16-bit). */
    m->adjacency = s->elements.adjacency_count ? ((uint64_t)s->elements.count + 1 + s->elements.adjacency_count) * 4 +
                                                     ((uint64_t)s->elements.adjacency_count + 1) / 2 * 4
                                               : 0;
    m->total = m->positions + m->frames + m->attributes + m->colors + m->vertex_elements + m->indices + m->adjacency;
}

void lc_gpu_scene_estimate(const lc_scene *s, const lc_gpu_scene_desc *desc, lc_gpu_memory *out)
{
    int exact = desc && desc->exact_positions;
    layout_bytes(s, desc,
                 exact ? (s->type == LC_PRIM_POINTS ? LC_BLEND_IMPLICIT : LC_BLEND_FULL)
                       : lc_pack_blend_layout_of_type(s->type),
                 0, out);
}

/* Uploads the vertex data of s in the exact (float) or compact layout. */
static int upload_vertices(lc_gpu_scene *gs, const lc_scene *s, lc_error *err)
{
    size_t n = s->vertex_count;
    const float *frame = s->type == LC_PRIM_LINES ? s->tangents : s->type == LC_PRIM_TRIANGLES ? s->normals : NULL;
    /* One scratch buffer, as large as the largest packed array. */
    size_t big = (n ? n : 1) * 16;
    uint32_t *tmp = malloc(big);
    if (!tmp)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %zu vertices", s->name, n);
    if (gs->exact) {
        float *f = (float *)tmp;
        for (size_t i = 0; i < n; i++) {
            memcpy(f + 4 * i, s->positions + 3 * i, 3 * sizeof(float));
            f[4 * i + 3] = 1.0f;
        }
        gs->positions = lc_gl_buffer(f, n * 16, &gs->bytes);
        gs->position_chunks = lc_gl_buffer(NULL, 0, &gs->bytes);
        if (frame) {
            for (size_t i = 0; i < n; i++) {
                memcpy(f + 4 * i, frame + 3 * i, 3 * sizeof(float));
                f[4 * i + 3] = 0.0f;
            }
            gs->frames = lc_gl_buffer(f, n * 16, &gs->bytes);
        } else {
            gs->frames = lc_gl_buffer(NULL, 0, &gs->bytes);
        }
    } else {
        size_t chunk_bytes = lc_pack_chunks_bytes(s->vertex_count, lc_pack_chunk_phase(s));
        float *chunks = malloc(chunk_bytes ? chunk_bytes : 16);
        if (!chunks) {
            free(tmp);
            return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %zu vertices", s->name, n);
        }
        lc_pack_positions(s->positions, s->vertex_count, lc_pack_chunk_phase(s), tmp, chunks);
        gs->positions = lc_gl_buffer(tmp, lc_pack_positions_bytes(s->vertex_count), &gs->bytes);
        gs->position_chunks = lc_gl_buffer(chunks, chunk_bytes, &gs->bytes);
        free(chunks);
        if (frame) {
            lc_pack_directions(frame, s->vertex_count, tmp);
            gs->frames = lc_gl_buffer(tmp, n * 4, &gs->bytes);
        } else {
            gs->frames = lc_gl_buffer(NULL, 0, &gs->bytes);
        }
    }

    /* Attributes back to back, each at its own word offset. */
    size_t words = 0;
    for (int a = 0; a < s->attribute_count; a++) {
        const lc_attribute *at = &s->attributes[a];
        int u16 = !gs->exact && lc_pack_attribute_is_unorm16(at);
        gs->attr_offset[a] = (uint32_t)words;
        gs->attr_format[a] = u16;
        gs->attr_decode[a][0] = u16 ? at->min : 0.0f;
        gs->attr_decode[a][1] = u16 ? (float)(((double)at->max - at->min) / 65535.0) : 1.0f;
        words += u16 ? lc_pack_unorm16_bytes(s->vertex_count) / 4 : n;
    }
    glCreateBuffers(1, &gs->attributes);
    glNamedBufferStorage(gs->attributes, words ? (GLsizeiptr)words * 4 : 16, NULL, GL_DYNAMIC_STORAGE_BIT);
    for (int a = 0; a < s->attribute_count; a++) {
        const lc_attribute *at = &s->attributes[a];
        if (gs->attr_format[a]) {
            lc_pack_attribute(at, s->vertex_count, tmp);
            glNamedBufferSubData(gs->attributes, (GLintptr)gs->attr_offset[a] * 4,
                                 (GLsizeiptr)lc_pack_unorm16_bytes(s->vertex_count), tmp);
        } else {
            glNamedBufferSubData(gs->attributes, (GLintptr)gs->attr_offset[a] * 4, (GLsizeiptr)(n * 4), at->values);
        }
    }
    gs->bytes += words ? words * 4 : 16;
    gs->attribute_bytes = words * 4;

    if (gs->exact || !s->rgb) {
        gs->colors = lc_gl_buffer(s->rgb, s->rgb ? n * 3 * sizeof(float) : 0, &gs->bytes);
    } else {
        lc_pack_colors(s->rgb, s->vertex_count, tmp);
        gs->colors = lc_gl_buffer(tmp, n * 4, &gs->bytes);
    }

    /* Vertex -> element blends: implicit for points (element = point, the
     * same opacity the exact layout's single weight of 1 gives). */
    if (gs->blend == LC_BLEND_FULL) {
        gs->vertex_elements = lc_gl_buffer(s->elements.vertex_elements, n * 4 * sizeof(uint32_t), &gs->bytes);
        gs->vertex_weights = lc_gl_buffer(s->elements.vertex_weights, n * 4 * sizeof(float), &gs->bytes);
    } else {
        if (gs->blend != LC_BLEND_IMPLICIT)
            lc_pack_blend(&s->elements, gs->blend, s->vertex_count, tmp);
        gs->vertex_elements = lc_gl_buffer(tmp, lc_pack_blend_bytes(gs->blend, s->vertex_count), &gs->bytes);
        gs->vertex_weights = lc_gl_buffer(NULL, 0, &gs->bytes);
    }
    free(tmp);
    return 0;
}

/* One level's ribbon strips from its segment pairs (in line order, so a run
 * continues while a segment starts where the previous one ended); vertex 2v /
 * 2v+1 are the two sides at line vertex v (geometry.vert.glsl). Two indices a
 * segment instead of six corners of a quad: the same triangles (diagonal from
 * side +1 of a to side -1 of b, provoking vertex at b), a third of the bytes. */
#define STRIP_BREAK_SPACING 4096u
static int upload_line_level(lc_gpu_scene *gs, const uint32_t *pairs, uint64_t k, double error, lc_error *err)
{
    uint64_t cap = strip_indices(k, k);
    uint32_t *strip = malloc((cap ? cap : 1) * sizeof(uint32_t));
    uint64_t *breaks = malloc(((cap / STRIP_BREAK_SPACING) + 2) * sizeof(uint64_t));
    uint32_t *runs = malloc((k ? 2 * k : 2) * sizeof(uint32_t)); /* at most a run per segment */
    if (!strip || !breaks || !runs) {
        free(strip);
        free(breaks);
        free(runs);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for segments", gs->scene->name);
    }
    uint64_t n = 0;
    uint32_t nb = 0, nr = 0;
    for (uint64_t j = 0; j < k; j++) {
        uint32_t a = pairs[2 * j], b = pairs[2 * j + 1];
        if (j == 0 || pairs[2 * j - 1] != a) {
            if (j > 0) {
                runs[2 * nr - 1] = (uint32_t)(n - runs[2 * nr - 2]);
                strip[n++] = LC_STRIP_RESTART;
                strip[n++] = LC_STRIP_RESTART;
            }
            runs[2 * nr++] = (uint32_t)n;
            if (nb == 0 || n - breaks[nb - 1] >= STRIP_BREAK_SPACING)
                breaks[nb++] = n;
            strip[n++] = 2 * a;
            strip[n++] = 2 * a + 1;
        }
        strip[n++] = 2 * b;
        strip[n++] = 2 * b + 1;
    }
    if (nr)
        runs[2 * nr - 1] = (uint32_t)(n - runs[2 * nr - 2]);
    lc_gpu_level *lv = &gs->levels[gs->level_count++];
    lv->indices = lc_gl_buffer(strip, n * sizeof(uint32_t), &gs->bytes);
    /* The line strip (one wide line a segment, line_primitive.c): strip
     * entry 2k is side -1 of a line vertex, or a restart. */
    for (uint64_t i = 0; i < n / 2; i++)
        strip[i] = strip[2 * i] == LC_STRIP_RESTART ? LC_STRIP_RESTART : strip[2 * i] >> 1;
    lv->line_indices = lc_gl_buffer(strip, n / 2 * sizeof(uint32_t), &gs->bytes);
    lv->runs = lc_gl_buffer(runs, (size_t)nr * 2 * sizeof(uint32_t), &gs->bytes);
    lv->run_count = nr;
    free(runs);
    lv->primitive_count = k;
    lv->error = error;
    lv->index_count = n;
    lv->breaks = breaks;
    lv->break_count = nb;
    free(strip);
    return 0;
}

/* Level 0 and the coarser levels of render/scene/lod.h: lines upload each
 * level's ribbon strips; triangles draw level 0 from the scene's own index
 * buffer and each coarser level from its triangles (one buffer serves both
 * bindings). */
static int upload_levels(lc_gpu_scene *gs, lc_error *err)
{
    const lc_scene *s = gs->scene;
    lc_lod lod;
    int rc = lc_lod_build(s, &lod, err);
    for (int i = 0; !rc && i < lod.count; i++) {
        const lc_lod_level *l = &lod.levels[i];
        uint64_t before = gs->bytes;
        if (s->type == LC_PRIM_LINES) {
            rc = upload_line_level(gs, l->indices, l->primitives, l->error, err);
        } else {
            const uint32_t *tris = i == 0 ? s->triangles : l->indices;
            GLuint b = lc_gl_buffer(tris, l->primitives * 3 * sizeof(uint32_t), &gs->bytes);
            gs->levels[gs->level_count++] =
                (lc_gpu_level){.indices = b, .primitive_count = l->primitives, .error = l->error};
        }
        if (i > 0)
            gs->lod_bytes += gs->bytes - before;
    }
    lc_lod_free(&lod);
    return rc;
}

int lc_gpu_scene_create(const lc_scene *s, lc_gpu_scene **out, lc_error *err)
{
    return lc_gpu_scene_create_ex(s, NULL, out, err);
}

int lc_gpu_scene_create_ex(const lc_scene *s, const lc_gpu_scene_desc *desc, lc_gpu_scene **out, lc_error *err)
{
    *out = NULL;
    if (!s->finalized)
        return lc_err(err, LC_ERR_INVALID, "%s: scene is not finalized", s->name);
    if (!s->positions && s->vertex_count)
        return lc_err(err, LC_ERR_INVALID, "%s: the scene's vertex arrays were released after an upload", s->name);
    lc_gpu_scene *gs = calloc(1, sizeof *gs);
    if (!gs)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    static atomic_uint_fast64_t serials;
    gs->serial = atomic_fetch_add(&serials, 1) + 1;
    gs->scene = s;
    gs->exact = desc && desc->exact_positions;
    gs->blend = lc_pack_blend_layout(s);
    if (gs->exact && gs->blend != LC_BLEND_IMPLICIT)
        gs->blend = LC_BLEND_FULL;
    int rc = upload_vertices(gs, s, err);
    if (rc) {
        free(gs);
        return rc;
    }
    if (s->type != LC_PRIM_POINTS) {
        rc = upload_levels(gs, err);
        if (rc) {
            lc_gpu_scene_destroy(gs);
            return rc;
        }
    } else {
        GLuint none = lc_gl_buffer(NULL, 0, &gs->bytes);
        gs->levels[0] = (lc_gpu_level){.indices = none, .primitive_count = s->vertex_count};
        gs->level_count = 1;
    }
    /* Without adjacency (points) P3 never reads the offsets. */
    uint32_t ne = s->elements.count, na = s->elements.adjacency_count;
    gs->adj_offsets =
        lc_gl_buffer(s->elements.adjacency_offsets, na ? ((size_t)ne + 1) * sizeof(uint32_t) : 0, &gs->bytes);
    gs->adj = lc_gl_buffer(s->elements.adjacency, (size_t)s->elements.adjacency_count * sizeof(uint32_t), &gs->bytes);
    /* Distance weights of the smoothing, 16-bit unorm (2 per word). */
    float *weights = na ? malloc((size_t)na * sizeof(float)) : NULL;
    uint16_t *packed = weights ? calloc(((size_t)na + 1) / 2 * 2, sizeof(uint16_t)) : NULL;
    if (packed) {
        lc_elements_adjacency_weights(&s->elements, s->positions, s->vertex_count, weights);
        for (uint32_t k = 0; k < na; k++)
            packed[k] = (uint16_t)lrintf(weights[k] * 65535.0f);
    }
    gs->adj_weights = lc_gl_buffer(packed, packed ? ((size_t)na + 1) / 2 * 4 : 0, &gs->bytes);
    free(weights);
    free(packed);
    rc = lc_line_clusters_create(s, &gs->clusters, err);
    if (rc) {
        lc_gpu_scene_destroy(gs);
        return rc;
    }
    layout_bytes(s, &(lc_gpu_scene_desc){.exact_positions = gs->exact}, gs->blend, 1, &gs->memory);
    gs->memory.indices += gs->lod_bytes;
    gs->memory.total = gs->bytes; /* the kinds' sum plus the 16-byte stand-ins of empty buffers */
    /* Other contexts of the share group may use the buffers right away. */
    glFinish();
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        lc_gpu_scene_destroy(gs);
        return lc_err(err, LC_ERR_GL, "%s: uploading the scene failed (GL error 0x%04x; out of GPU memory?)", s->name,
                      e);
    }
    *out = gs;
    return 0;
}

void lc_gpu_scene_destroy(lc_gpu_scene *gs)
{
    if (!gs)
        return;
    GLuint bufs[] = {gs->positions,       gs->position_chunks, gs->frames,      gs->attributes, gs->colors,
                     gs->vertex_elements, gs->vertex_weights,  gs->adj_offsets, gs->adj,        gs->adj_weights};
    glDeleteBuffers(sizeof bufs / sizeof bufs[0], bufs);
    for (int i = 0; i < gs->level_count; i++) {
        lc_gpu_level *lv = &gs->levels[i];
        glDeleteBuffers(1, &lv->indices);
        if (lv->line_indices)
            glDeleteBuffers(1, &lv->line_indices);
        glDeleteBuffers(1, &lv->runs);
        free(lv->breaks);
    }
    lc_line_clusters_destroy(gs->clusters);
    free(gs);
}

uint64_t lc_gpu_scene_bytes(const lc_gpu_scene *gs) { return gs->bytes; }

void lc_gpu_scene_memory(const lc_gpu_scene *gs, lc_gpu_memory *out) { *out = gs->memory; }

int lc_gpu_scene_levels(const lc_gpu_scene *gs) { return gs->level_count; }

uint64_t lc_gpu_scene_lod_bytes(const lc_gpu_scene *gs) { return gs->lod_bytes; }

void lc_gpu_scene_level(const lc_gpu_scene *gs, int i, double *error, double *primitives)
{
    *error = gs->levels[i].error;
    *primitives = (double)gs->levels[i].primitive_count;
}
