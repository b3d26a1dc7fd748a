/* Importance-aware line subsets for moving frames (docs/ALGORITHM.md §11):
 * dense real lines (MD trajectories keep every segment at any useful level of
 * detail) cost every pass per fragment, so a frame with a frame state's
 * opacities may draw whole lines thinned to about one in n
 * (lc_detail.line_stride), weighted n in P1 and P4 as FOO's subset
 * approximation weights a stride, while the most important lines, the top
 * 1/(4 n) by their mean vertex importance g, stay in full with weight 1. An
 * element of a dropped line gets no fragment, and P3 keeps its opacity, so a
 * moving frame may still re-optimize. Whole runs of the level's strip are
 * kept or dropped, never single segments, so a kept line looks as in the
 * still. A compute pass bins each run once per importance mapping and level;
 * a second copies the kept runs into one strip, once per cut, important runs
 * at the front and strided ones at the back. */
#include <string.h>

#include "renderer_internal.h"

static int same_mapping(const lc_renderer *r, const lc_frame_setup *fs)
{
    return r->line_sel.bins_valid && r->line_sel.scene == fs->gs->serial && r->line_sel.level == fs->level &&
           r->line_sel.attr == fs->importance_attr && r->line_sel.range[0] == fs->importance_range[0] &&
           r->line_sel.range[1] == fs->importance_range[1] && r->line_sel.exponent == fs->importance_exponent &&
           memcmp(&r->line_sel.terms, &fs->terms, sizeof fs->terms) == 0;
}

static void grow(GLuint *buf, uint64_t *capacity, uint64_t want)
{
    if (want <= *capacity)
        return;
    if (*buf)
        glDeleteBuffers(1, buf);
    glCreateBuffers(1, buf);
    glNamedBufferStorage(*buf, (GLsizeiptr)want, NULL, GL_DYNAMIC_STORAGE_BIT);
    *capacity = want;
}

static void bind(lc_renderer *r, lc_frame_setup *fs, GLuint prog, const lc_gpu_level *lv)
{
    lc_renderer_bind_geometry(r, prog, fs, fs->width, fs->height, 1); /* the attributes and the mapping */
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_LINE_RUNS, lv->runs);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_LINE_SELECT, r->line_select);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_POINT_HISTOGRAM, r->point_histogram);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_LINE_KEPT, r->line_kept ? r->line_kept : r->dummy_buffer);
    lc_uniform_u(prog, "u_runs", lv->run_count);
}

/* Mode 0: each run's importance bin and their histogram. */
static void histogram(lc_renderer *r, lc_frame_setup *fs, GLuint prog, const lc_gpu_level *lv)
{
    if (!r->point_histogram) {
        glCreateBuffers(1, &r->point_histogram);
        glNamedBufferStorage(r->point_histogram, POINT_BINS * sizeof(uint32_t), NULL, GL_DYNAMIC_STORAGE_BIT);
    }
    grow(&r->line_select, &r->line_select_bytes, (2 + (uint64_t)lv->run_count) * sizeof(uint32_t));
    const uint32_t zero = 0;
    glClearNamedBufferData(r->point_histogram, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    bind(r, fs, prog, lv);
    lc_uniform_i(prog, "u_mode", 0);
    lc_dispatch_linear((lv->run_count + 63) / 64);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glGetNamedBufferSubData(r->point_histogram, 0, sizeof r->line_sel.bins, r->line_sel.bins);
    r->point_hist.valid = 0; /* the points' histogram shared the buffer */
    r->line_sel.scene = fs->gs->serial;
    r->line_sel.level = fs->level;
    r->line_sel.attr = fs->importance_attr;
    r->line_sel.range[0] = fs->importance_range[0];
    r->line_sel.range[1] = fs->importance_range[1];
    r->line_sel.exponent = fs->importance_exponent;
    r->line_sel.terms = fs->terms;
    r->line_sel.bins_valid = 1;
    r->line_sel.keep_bin = -1; /* the kept strip belongs to the old bins */
}

/* Mode 1: the kept strip for a cut at keep_bin and the stride. */
static void copy(lc_renderer *r, lc_frame_setup *fs, GLuint prog, const lc_gpu_level *lv, int keep_bin, int stride)
{
    /* The runs' indices plus two restarts each bound any subset. */
    uint64_t total = lv->index_count + 2;
    grow(&r->line_kept, &r->line_kept_bytes, total * sizeof(uint32_t));
    const uint32_t zero[2] = {0, 0};
    glNamedBufferSubData(r->line_select, 0, sizeof zero, zero);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    bind(r, fs, prog, lv);
    lc_uniform_i(prog, "u_mode", 1);
    lc_uniform_i(prog, "u_keep_bin", keep_bin);
    lc_uniform_u(prog, "u_stride", (unsigned)stride);
    lc_uniform_u(prog, "u_total", (unsigned)total);
    lc_dispatch_linear((lv->run_count + 63) / 64);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    uint32_t counts[2];
    glGetNamedBufferSubData(r->line_select, 0, sizeof counts, counts);
    r->line_sel.keep_bin = keep_bin;
    r->line_sel.stride = stride;
    r->line_sel.full = counts[0];
    r->line_sel.strided = counts[1];
    r->line_sel.total = total;
}

int lc_line_subset_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    fs->kept_line_indices[0] = fs->kept_line_indices[1] = 0;
    const lc_gpu_level *lv = &fs->gs->levels[fs->level];
    /* Sparse lines keep every line: the stride halves until the frame draws
     * a segment per LC_LINE_SUBSET_PIXELS pixels, and LC_LINE_SUBSET_FLOOR. */
    uint64_t floor_segments = (uint64_t)fs->width * (uint64_t)fs->height / LC_LINE_SUBSET_PIXELS;
    if (floor_segments < LC_LINE_SUBSET_FLOOR)
        floor_segments = LC_LINE_SUBSET_FLOOR;
    while (fs->line_stride > 1 && lv->primitive_count / (uint64_t)fs->line_stride < floor_segments)
        fs->line_stride /= 2;
    int stride = fs->line_stride;
    if (stride <= 1 || fs->gs->scene->type != LC_PRIM_LINES || !lv->run_count)
        return 0;
    GLuint prog = lc_renderer_fixed_program(r, PROG_LINE_SELECT, err);
    if (!prog)
        return LC_ERR_GL;
    if (!same_mapping(r, fs))
        histogram(r, fs, prog, lv);
    /* Kept in full: about a 1/(4 stride) of the runs, at most 1/stride; with
     * no importance, or none standing out, every run is strided alike. */
    uint64_t n = lv->run_count;
    uint32_t count = 0;
    int bin = fs->importance_attr < 0
                  ? 0
                  : lc_subset_choose_bin(r->line_sel.bins, (n + 4 * (uint64_t)stride - 1) / (4 * (uint64_t)stride),
                                         n / (uint64_t)stride, &count);
    int keep_bin = bin == 0 ? POINT_BINS + 1 : bin;
    if (r->line_sel.keep_bin != keep_bin || r->line_sel.stride != stride)
        copy(r, fs, prog, lv, keep_bin, stride);
    fs->kept_line_indices[0] = r->line_sel.full;
    fs->kept_line_indices[1] = r->line_sel.strided;
    fs->kept_line_total = r->line_sel.total;
    fs->kept_line_buffer = r->line_kept;
    return 0;
}
