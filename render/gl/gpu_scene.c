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

/* The segment pairs of one level and its ribbon quads: vertex 2v / 2v+1 are
 * the two sides at line vertex v (geometry.vert.glsl). */
static int upload_level(lc_gpu_scene *gs, const uint32_t *pairs, uint64_t k, double error, lc_error *err)
{
    uint32_t *quads = malloc((k ? k : 1) * 6 * sizeof(uint32_t));
    if (!quads)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for segments", gs->scene->name);
    for (uint64_t j = 0; j < k; j++) {
        uint32_t a = 2 * pairs[2 * j], b = 2 * pairs[2 * j + 1];
        uint32_t q[6] = {a, a + 1, b, a + 1, b + 1, b};
        memcpy(quads + 6 * j, q, sizeof q);
    }
    lc_gpu_level *lv = &gs->levels[gs->level_count++];
    uint64_t before = gs->bytes;
    lv->indices = lc_gl_buffer(pairs, k * 2 * sizeof(uint32_t), &gs->bytes);
    lv->draw_indices = lc_gl_buffer(quads, k * 6 * sizeof(uint32_t), &gs->bytes);
    lv->primitive_count = k;
    lv->error = error;
    if (gs->level_count > 1)
        gs->lod_bytes += gs->bytes - before;
    free(quads);
    return 0;
}

/* Level 0 (every segment) and the coarser levels of render/scene/lod.h. */
static int upload_line_levels(lc_gpu_scene *gs, lc_error *err)
{
    lc_lod lod;
    int rc = lc_lod_build(gs->scene, &lod, err);
    for (int i = 0; !rc && i < lod.count; i++)
        rc = upload_level(gs, lod.levels[i].pairs, lod.levels[i].segments, lod.levels[i].error, err);
    lc_lod_free(&lod);
    return rc;
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
        int rc = upload_line_levels(gs, err);
        if (rc) {
            lc_gpu_scene_destroy(gs);
            return rc;
        }
    } else if (s->type == LC_PRIM_TRIANGLES) {
        GLuint tris = lc_gl_buffer(s->triangles, (size_t)s->triangle_count * 3 * sizeof(uint32_t), &gs->bytes);
        /* The same buffer serves both bindings. */
        gs->levels[0] = (lc_gpu_level){.indices = tris, .draw_indices = tris, .primitive_count = s->triangle_count};
        gs->level_count = 1;
    } else {
        GLuint none = lc_gl_buffer(NULL, 0, &gs->bytes);
        gs->levels[0] = (lc_gpu_level){.indices = none, .draw_indices = none, .primitive_count = n};
        gs->level_count = 1;
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
    GLuint bufs[] = {gs->positions,       gs->frames,         gs->attributes, gs->colors,
                     gs->vertex_elements, gs->vertex_weights, gs->adj_offsets, gs->adj};
    glDeleteBuffers(sizeof bufs / sizeof bufs[0], bufs);
    for (int i = 0; i < gs->level_count; i++) {
        lc_gpu_level *lv = &gs->levels[i];
        GLuint level_bufs[] = {lv->indices, lv->draw_indices != lv->indices ? lv->draw_indices : 0};
        glDeleteBuffers(2, level_bufs);
    }
    free(gs);
}

uint64_t lc_gpu_scene_bytes(const lc_gpu_scene *gs) { return gs->bytes; }

int lc_gpu_scene_levels(const lc_gpu_scene *gs) { return gs->level_count; }

uint64_t lc_gpu_scene_lod_bytes(const lc_gpu_scene *gs) { return gs->lod_bytes; }
