/* Importance-aware point subsets (docs/ALGORITHM.md "Level of detail"): while
 * the camera moves, a session may draw every n-th point (lc_detail.point_stride,
 * weighted n in P1/P4, FOO's subset approximation). A uniform stride thins the
 * important points as much as the clutter, so the few important ones that
 * stand alone flicker in and out. Here the most important points are kept in
 * full: the top 1/(4 n) of the points by importance g, drawn from a list with
 * weight 1, while the strided draw skips them. The cut comes from a histogram
 * of g over every point (POINT_BINS bins), built once per importance mapping;
 * the list once per cut. Both are GPU passes over the points, so nothing
 * needs the scene's CPU arrays, which are freed after the upload. */
#include <string.h>

#include "renderer_internal.h"

static int same_mapping(const lc_renderer *r, const lc_frame_setup *fs)
{
    return r->point_hist.valid && r->point_hist.gs == fs->gs && r->point_hist.attr == fs->importance_attr &&
           r->point_hist.range[0] == fs->importance_range[0] && r->point_hist.range[1] == fs->importance_range[1] &&
           r->point_hist.exponent == fs->importance_exponent &&
           memcmp(&r->point_hist.terms, &fs->terms, sizeof fs->terms) == 0;
}

static void histogram(lc_renderer *r, lc_frame_setup *fs, GLuint prog)
{
    if (!r->point_histogram) {
        glCreateBuffers(1, &r->point_histogram);
        glNamedBufferStorage(r->point_histogram, POINT_BINS * sizeof(uint32_t), NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    const uint32_t zero = 0;
    glClearNamedBufferData(r->point_histogram, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1); /* the attributes and the mapping */
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_POINT_HISTOGRAM, r->point_histogram);
    lc_uniform_i(prog, "u_mode", 0);
    lc_dispatch_linear((fs->gs->scene->vertex_count + 255) / 256);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(r->point_histogram, 0, sizeof r->point_hist.bins, r->point_hist.bins);
    r->point_hist.gs = fs->gs;
    r->point_hist.attr = fs->importance_attr;
    r->point_hist.range[0] = fs->importance_range[0];
    r->point_hist.range[1] = fs->importance_range[1];
    r->point_hist.exponent = fs->importance_exponent;
    r->point_hist.terms = fs->terms;
    r->point_hist.valid = 1;
    r->point_kept.keep_bin = -1; /* the list belongs to the old mapping */
}

/* The lowest bin whose points and those above number at least `want`,
 * without going over `most`; 0 when no such cut exists (bin 0, g < 1/1024,
 * is never kept: those points are not important). *count: how many. */
int lc_subset_choose_bin(const uint32_t *bins, uint64_t want, uint64_t most, uint32_t *count)
{
    uint64_t acc = 0;
    int best = 0;
    for (int b = POINT_BINS - 1; b >= 1; b--) {
        if (acc + bins[b] > most)
            break;
        acc += bins[b];
        if (bins[b]) {
            best = b;
            *count = (uint32_t)acc;
        }
        if (acc >= want)
            break;
    }
    return best;
}

static void list(lc_renderer *r, lc_frame_setup *fs, GLuint prog, int bin, uint32_t count)
{
    if (count > r->point_list_capacity) {
        if (r->point_list)
            glDeleteBuffers(1, &r->point_list);
        glCreateBuffers(1, &r->point_list);
        glNamedBufferStorage(r->point_list, ((GLsizeiptr)count + 1) * sizeof(uint32_t), NULL, GL_DYNAMIC_STORAGE_BIT);
        r->point_list_capacity = count;
    }
    const uint32_t zero = 0;
    glNamedBufferSubData(r->point_list, 0, sizeof zero, &zero);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_POINT_LIST, r->point_list);
    lc_uniform_i(prog, "u_mode", 1);
    lc_uniform_i(prog, "u_keep_bin", bin);
    lc_uniform_u(prog, "u_capacity", count);
    lc_dispatch_linear((fs->gs->scene->vertex_count + 255) / 256);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    r->point_kept.keep_bin = bin;
    r->point_kept.count = count;
}

int lc_point_subset_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    fs->keep_bin = POINT_BINS + 1;
    fs->kept_points = 0;
    const lc_scene *s = fs->gs->scene;
    /* Small clouds keep every point: the stride halves until the frame draws
     * a point per LC_POINT_SUBSET_PIXELS pixels, and LC_POINT_SUBSET_FLOOR. */
    uint64_t floor_points = (uint64_t)fs->width * (uint64_t)fs->height / LC_POINT_SUBSET_PIXELS;
    if (floor_points < LC_POINT_SUBSET_FLOOR)
        floor_points = LC_POINT_SUBSET_FLOOR;
    while (s->type == LC_PRIM_POINTS && fs->point_stride > 1 &&
           s->vertex_count / (uint64_t)fs->point_stride < floor_points)
        fs->point_stride /= 2;
    uint64_t n = s->vertex_count, stride = (uint64_t)fs->point_stride;
    if (stride <= 1 || s->type != LC_PRIM_POINTS || fs->importance_attr < 0 || n == 0 ||
        fs->params->detail.uniform_points)
        return 0;
    GLuint prog = lc_renderer_fixed_program(r, PROG_POINT_SELECT, err);
    if (!prog)
        return LC_ERR_GL;
    if (!same_mapping(r, fs))
        histogram(r, fs, prog);
    /* Kept in full: about n / (4 stride) points, at most n / stride (ties in
     * a bin, e.g. the values clamped to g = 1, can make a bin large). */
    uint32_t count = 0;
    int bin = lc_subset_choose_bin(r->point_hist.bins, (n + 4 * stride - 1) / (4 * stride), n / stride, &count);
    if (bin == 0)
        return 0; /* nothing stands out: a uniform stride */
    if (r->point_kept.keep_bin != bin)
        list(r, fs, prog, bin, count);
    fs->keep_bin = bin;
    fs->kept_points = count;
    return 0;
}
