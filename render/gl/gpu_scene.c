/* The GPU copy of a scene: vertex, attribute, element and index buffers,
 * uploaded once and shared by every context of the share group. */
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"

GLuint lc_gl_buffer(const void *data, size_t size, uint64_t *bytes)
{
    GLuint b;
    glCreateBuffers(1, &b);
    /* Zero-size storage is invalid; keep one vec4 so a binding is always valid. */
    glNamedBufferStorage(b, size ? (GLsizeiptr)size : 16, size ? data : NULL, 0);
    *bytes += size ? size : 16;
    return b;
}

int lc_gpu_scene_create(const lc_scene *s, lc_gpu_scene **out, lc_error *err)
{
    *out = NULL;
    if (!s->finalized)
        return lc_err(err, LC_ERR_INVALID, "%s: scene is not finalized", s->name);
    lc_gpu_scene *gs = calloc(1, sizeof *gs);
    if (!gs)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    gs->scene = s;
    size_t n = s->vertex_count;
    float *tmp = malloc((n ? n : 1) * 4 * sizeof(float));
    if (!tmp) {
        free(gs);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %zu vertices", s->name, n);
    }
    for (size_t i = 0; i < n; i++) {
        memcpy(tmp + 4 * i, s->positions + 3 * i, 3 * sizeof(float));
        tmp[4 * i + 3] = 1.0f;
    }
    gs->positions = lc_gl_buffer(tmp, n * 4 * sizeof(float), &gs->bytes);
    const float *frame = s->type == LC_PRIM_LINES ? s->tangents : s->type == LC_PRIM_TRIANGLES ? s->normals : NULL;
    if (frame) {
        for (size_t i = 0; i < n; i++) {
            memcpy(tmp + 4 * i, frame + 3 * i, 3 * sizeof(float));
            tmp[4 * i + 3] = 0.0f;
        }
        gs->frames = lc_gl_buffer(tmp, n * 4 * sizeof(float), &gs->bytes);
    } else {
        gs->frames = lc_gl_buffer(NULL, 0, &gs->bytes);
    }
    free(tmp);

    /* Attributes back to back: attribute a of vertex v at a * n + v. */
    size_t na = (size_t)s->attribute_count;
    glCreateBuffers(1, &gs->attributes);
    size_t attr_bytes = na * n * sizeof(float);
    glNamedBufferStorage(gs->attributes, attr_bytes ? (GLsizeiptr)attr_bytes : 16, NULL, GL_DYNAMIC_STORAGE_BIT);
    for (size_t a = 0; a < na; a++)
        glNamedBufferSubData(gs->attributes, (GLintptr)(a * n * sizeof(float)), (GLsizeiptr)(n * sizeof(float)),
                             s->attributes[a].values);
    gs->bytes += attr_bytes ? attr_bytes : 16;
    gs->colors = lc_gl_buffer(s->rgb, s->rgb ? n * 3 * sizeof(float) : 0, &gs->bytes);
    gs->vertex_elements = lc_gl_buffer(s->elements.vertex_elements, n * 4 * sizeof(uint32_t), &gs->bytes);
    gs->vertex_weights = lc_gl_buffer(s->elements.vertex_weights, n * 4 * sizeof(float), &gs->bytes);

    if (s->type == LC_PRIM_LINES) {
        uint64_t segs = lc_scene_primitive_count(s);
        uint32_t *idx = malloc((segs ? segs : 1) * 2 * sizeof(uint32_t));
        if (!idx) {
            lc_gpu_scene_destroy(gs);
            return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for segments", s->name);
        }
        uint64_t k = 0;
        for (uint32_t l = 0; l < s->line_count; l++)
            for (uint32_t v = s->line_offsets[l]; v + 1 < s->line_offsets[l + 1]; v++) {
                idx[2 * k] = v;
                idx[2 * k + 1] = v + 1;
                k++;
            }
        gs->indices = lc_gl_buffer(idx, k * 2 * sizeof(uint32_t), &gs->bytes);
        gs->primitive_count = k;
        /* Indexed ribbons: vertex 2v / 2v+1 are the two sides at line vertex v. */
        uint32_t *quads = realloc(idx, (k ? k : 1) * 6 * sizeof(uint32_t));
        if (!quads) {
            free(idx);
            lc_gpu_scene_destroy(gs);
            return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for segments", s->name);
        }
        for (uint64_t j = k; j-- > 0;) { /* backwards: pairs live in the first 2k slots */
            uint32_t a = 2 * quads[2 * j], b = 2 * quads[2 * j + 1];
            uint32_t q[6] = {a, a + 1, b, a + 1, b + 1, b};
            memcpy(quads + 6 * j, q, sizeof q);
        }
        gs->draw_indices = lc_gl_buffer(quads, k * 6 * sizeof(uint32_t), &gs->bytes);
        free(quads);
    } else if (s->type == LC_PRIM_TRIANGLES) {
        gs->indices = lc_gl_buffer(s->triangles, (size_t)s->triangle_count * 3 * sizeof(uint32_t), &gs->bytes);
        gs->draw_indices = gs->indices; /* the same buffer serves both bindings */
        gs->primitive_count = s->triangle_count;
    } else {
        gs->indices = lc_gl_buffer(NULL, 0, &gs->bytes);
        gs->primitive_count = n;
    }
    uint32_t ne = s->elements.count;
    gs->adj_offsets = lc_gl_buffer(s->elements.adjacency_offsets, ((size_t)ne + 1) * sizeof(uint32_t), &gs->bytes);
    gs->adj = lc_gl_buffer(s->elements.adjacency, (size_t)s->elements.adjacency_count * sizeof(uint32_t), &gs->bytes);
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
    GLuint bufs[] = {gs->positions,
                     gs->frames,
                     gs->attributes,
                     gs->colors,
                     gs->vertex_elements,
                     gs->vertex_weights,
                     gs->indices,
                     gs->adj_offsets,
                     gs->adj,
                     gs->draw_indices != gs->indices ? gs->draw_indices : 0};
    glDeleteBuffers(sizeof bufs / sizeof bufs[0], bufs);
    free(gs);
}

uint64_t lc_gpu_scene_bytes(const lc_gpu_scene *gs) { return gs->bytes; }
