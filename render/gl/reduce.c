/* Combining the Fourier passes' targets over processes through the
 * lc_reducer hook (renderer.h): read back, reduce, upload. */
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"

static int active(const lc_renderer *r) { return r->desc.reducer && r->desc.reducer->size > 1; }

void lc_renderer_set_reducer(lc_renderer *r, const lc_reducer *reducer) { r->desc.reducer = reducer; }

int lc_reduce_check_method(const lc_renderer *r, lc_method method, lc_error *err)
{
    /* Opaque (depth test), WBOIT (multiplicative revealage) and the exact
     * lists do not combine by addition. */
    if (!active(r) || method == LC_METHOD_FOURIER || method == LC_METHOD_DIRECT)
        return 0;
    return lc_err_field(err, LC_ERR_INVALID, "method",
                        "method \"%s\" cannot be split over processes; use \"fourier\" or \"direct\"",
                        lc_method_name(method));
}

static float *host_buffer(lc_renderer *r, size_t n, lc_error *err)
{
    if (n <= r->reduce_cap)
        return r->reduce_buf;
    float *b = realloc(r->reduce_buf, n * sizeof *b);
    if (!b) {
        lc_err(err, LC_ERR_NOMEM, "out of memory for a %zu-float reduction buffer", n);
        return NULL;
    }
    r->reduce_buf = b, r->reduce_cap = n;
    return b;
}

static int reduce(lc_renderer *r, float *values, size_t n, lc_reduce_op op, int root_only, lc_frame_info *info,
                  lc_error *err)
{
    const lc_reducer *red = r->desc.reducer;
    double t0 = lc_now();
    int rc = red->reduce(red->ctx, values, n, op, root_only, err);
    if (info) {
        info->reduce_ms += (lc_now() - t0) * 1e3;
        info->reduce_bytes += n * sizeof(float);
        info->reductions++;
    }
    return rc;
}

int lc_reduce_targets(lc_renderer *r, const lc_targets *t, lc_reduce_op op, int root_only, lc_frame_info *info,
                      lc_error *err)
{
    if (!active(r))
        return 0;
    /* RG32F range targets carry 2 floats, everything else RGBA (RGBA16F is
     * read and written back as floats: the wire carries full precision). */
    int channels = t->format == GL_RG32F ? 2 : 4;
    GLenum layout = channels == 2 ? GL_RG : GL_RGBA;
    size_t per = (size_t)t->width * t->height * channels;
    float *buf = host_buffer(r, per * t->count, err);
    if (!buf)
        return LC_ERR_NOMEM;
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (int i = 0; i < t->count; i++)
        glGetTextureImage(t->tex[i], 0, layout, GL_FLOAT, (GLsizei)(per * sizeof(float)), buf + per * i);
    int rc = reduce(r, buf, per * t->count, op, root_only, info, err);
    if (rc)
        return rc;
    if (root_only && r->desc.reducer->rank != 0)
        return 0;
    for (int i = 0; i < t->count; i++)
        glTextureSubImage2D(t->tex[i], 0, 0, 0, t->width, t->height, layout, GL_FLOAT, buf + per * i);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    return 0;
}

int lc_reduce_element_minima(lc_renderer *r, uint32_t count, lc_frame_info *info, lc_error *err)
{
    if (!active(r) || count == 0)
        return 0;
    float *buf = host_buffer(r, count, err);
    if (!buf)
        return LC_ERR_NOMEM;
    /* The minima are non-negative floats (atomicMin on their bit patterns),
     * so a float MIN gives the same order. */
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glGetNamedBufferSubData(r->element_alpha_min, 0, (GLsizeiptr)count * 4, buf);
    int rc = reduce(r, buf, count, LC_REDUCE_MIN, 0, info, err);
    if (rc)
        return rc;
    glNamedBufferSubData(r->element_alpha_min, 0, (GLsizeiptr)count * 4, buf);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    return 0;
}

int lc_reduce_sums(lc_renderer *r, float *values, size_t n, lc_frame_info *info, lc_error *err)
{
    if (!active(r) || n == 0)
        return 0;
    return reduce(r, values, n, LC_REDUCE_SUM, 0, info, err);
}

int lc_reduce_counts(lc_renderer *r, uint32_t *values, size_t n, lc_error *err)
{
    if (!active(r) || n == 0)
        return 0;
    float *buf = host_buffer(r, n, err);
    if (!buf)
        return LC_ERR_NOMEM;
    for (size_t i = 0; i < n; i++)
        buf[i] = (float)values[i];
    int rc = reduce(r, buf, n, LC_REDUCE_SUM, 0, NULL, err);
    for (size_t i = 0; i < n && !rc; i++)
        values[i] = (uint32_t)(buf[i] + 0.5f);
    return rc;
}

int lc_reduce_context(lc_renderer *r, const GLuint depth[2], const int w[2], const int h[2], GLuint color,
                      lc_frame_info *info, lc_error *err)
{
    if (!active(r))
        return 0;
    /* One buffer: the combined depth, this process's own depth and the colour. */
    size_t n0 = (size_t)w[0] * h[0], n1 = (size_t)w[1] * h[1];
    size_t depth_n = n0 > n1 ? n0 : n1;
    float *buf = host_buffer(r, 2 * depth_n + 4 * n0, err);
    if (!buf)
        return LC_ERR_NOMEM;
    float *nearest = buf, *mine = buf + depth_n, *rgba = buf + 2 * depth_n;
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (int k = 1; k >= 0; k--) { /* the full resolution last: its own depth stays in mine for the colour */
        size_t n = k ? n1 : n0;
        if (!n) /* not drawn this time (lc_context_draw's which) */
            continue;
        glGetTextureImage(depth[k], 0, GL_DEPTH_COMPONENT, GL_FLOAT, (GLsizei)(n * sizeof(float)), nearest);
        memcpy(mine, nearest, n * sizeof(float));
        /* A depth test keeps the nearest fragment: the same fragment wins
         * whichever process's shard holds its primitive. */
        int rc = reduce(r, nearest, n, LC_REDUCE_MIN, 0, info, err);
        if (rc)
            return rc;
        glTextureSubImage2D(depth[k], 0, 0, 0, w[k], h[k], GL_DEPTH_COMPONENT, GL_FLOAT, nearest);
    }
    /* The colour: each process keeps the pixels where its depth is the
     * nearest (alpha 1 there, 0 where it drew nothing), the sums go to process
     * 0, and alpha counts the processes that held it. The context enters the
     * picture once, as in one process. */
    if (!n0)
        return 0;
    glGetTextureImage(color, 0, GL_RGBA, GL_FLOAT, (GLsizei)(4 * n0 * sizeof(float)), rgba);
    for (size_t i = 0; i < n0; i++)
        if (mine[i] != nearest[i] || rgba[4 * i + 3] <= 0.0f)
            rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = rgba[4 * i + 3] = 0.0f;
    int rc = reduce(r, rgba, 4 * n0, LC_REDUCE_SUM, 1, info, err);
    if (rc || r->desc.reducer->rank != 0)
        return rc;
    for (size_t i = 0; i < n0; i++) {
        float a = rgba[4 * i + 3];
        if (a > 1.0f)
            rgba[4 * i] /= a, rgba[4 * i + 1] /= a, rgba[4 * i + 2] /= a, rgba[4 * i + 3] = 1.0f;
    }
    glTextureSubImage2D(color, 0, 0, 0, w[0], h[0], GL_RGBA, GL_FLOAT, rgba);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    return 0;
}
