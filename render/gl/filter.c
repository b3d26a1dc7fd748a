/* Hard filters (docs/ALGORITHM.md "Filters"): the request's predicates become
 * a visibility mask of one bit per vertex, written by a compute pass from the
 * attributes already on the GPU (a line predicate reduces the attribute over
 * the line's vertices, min/max/mean/first/last/change, and clears the bits of
 * every vertex of a line that fails). The geometry passes read the bit and
 * place a hidden vertex outside the clip volume, so a filtered line draws
 * nothing, and the compute passes that sum importance skip it. No uploaded
 * buffer changes: a new filter costs one pass over the vertices, not a reload.
 * The mask is kept while the scene and the filters stay the same. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "renderer_internal.h"

void lc_filter_release(lc_renderer *r)
{
    if (r->filter.offsets)
        glDeleteBuffers(1, &r->filter.offsets);
    if (r->filter.mask)
        glDeleteBuffers(1, &r->filter.mask);
    r->filter.offsets = r->filter.mask = 0;
    r->filter.mask_words = r->filter.offset_words = 0;
    r->filter.scene = 0;
    r->filter.count = -1;
}

/* The frame's filters: the request's, then its time window as a vertex-level
 * filter on the time attribute (docs/ALGORITHM.md "Time windows"). */
typedef struct filter_list {
    lc_filter f[LC_MAX_FILTERS];
    int attr[LC_MAX_FILTERS];
    int n, time; /* time: the window is f[n - 1] */
} filter_list;

static int add_time(const lc_frame_setup *fs, filter_list *L, lc_error *err)
{
    const lc_time_window *t = &fs->params->time;
    const lc_scene *s = fs->gs->scene;
    L->time = 0;
    if (!t->has_window)
        return 0;
    int a = lc_scene_time_attribute(s, t->attribute);
    if (a < 0 || L->n >= LC_MAX_FILTERS) /* lc_render_check refuses both */
        return lc_err_field(err, LC_ERR_INTERNAL, "time.window", "the time window was not checked");
    lc_filter *f = &L->f[L->n];
    memset(f, 0, sizeof *f);
    snprintf(f->attribute, sizeof f->attribute, "%s", s->attributes[a].name);
    f->over = LC_FILTER_VERTEX;
    /* A compact scene keeps the attribute in 16 bits (vertex_pack.c): a vertex
     * at exactly t0 or t1 may decode half a step off, so the window widens by
     * that much (a time step is far coarser than 1/65535 of the span). */
    double slack = fs->gs->attr_format[a] == 1 ? 0.5 * fabs((double)fs->gs->attr_decode[a][1]) * (1 + 1e-3) : 0;
    f->lo = t->window[0] - slack, f->hi = t->window[1] + slack;
    L->attr[L->n++] = a;
    L->time = 1;
    return 0;
}

/* Resolves attribute names (lc_render_check refused what does not suit the scene). */
static int resolve(const lc_frame_setup *fs, filter_list *L, lc_error *err)
{
    const lc_render_params *p = fs->params;
    const lc_scene *s = fs->gs->scene;
    L->n = p->filter_count;
    memcpy(L->f, p->filters, sizeof(lc_filter) * (size_t)L->n);
    for (int i = 0; i < p->filter_count; i++)
        if ((L->attr[i] = lc_scene_find_attribute(s, p->filters[i].attribute)) < 0)
            return lc_err_field(err, LC_ERR_INTERNAL, "filter", "the filters were not checked");
    return add_time(fs, L, err);
}

static int same_filters(const lc_renderer *r, const lc_frame_setup *fs, const filter_list *L)
{
    return r->filter.scene == fs->gs->serial && r->filter.count == L->n &&
           memcmp(r->filter.attr, L->attr, sizeof(int) * (size_t)L->n) == 0 &&
           memcmp(r->filter.filters, L->f, sizeof(lc_filter) * (size_t)L->n) == 0;
}

static float bound(double v) { return v > FLT_MAX ? FLT_MAX : v < -FLT_MAX ? -FLT_MAX : (float)v; }

static int build(lc_renderer *r, lc_frame_setup *fs, const filter_list *L, lc_error *err)
{
    const int *attr = L->attr;
    const lc_scene *s = fs->gs->scene;
    GLuint prog = lc_renderer_fixed_program(r, PROG_FILTER_MASK, err);
    if (!prog)
        return LC_ERR_GL;
    if (r->filter.scene != fs->gs->serial) {
        lc_filter_release(r);
        uint64_t bytes = 0;
        if (s->type == LC_PRIM_LINES) {
            r->filter.offsets = lc_gl_buffer(s->line_offsets, ((size_t)s->line_count + 1) * sizeof(uint32_t), &bytes);
            r->filter.offset_words = s->line_count + 1;
        }
        r->filter.mask_words = (s->vertex_count + 31) / 32;
        glCreateBuffers(1, &r->filter.mask);
        glNamedBufferStorage(r->filter.mask, (GLsizeiptr)(r->filter.mask_words ? r->filter.mask_words : 1) * 4, NULL,
                             GL_DYNAMIC_STORAGE_BIT);
        r->filter.scene = fs->gs->serial;
    }
    const uint32_t ones = 0xffffffffu;
    glClearNamedBufferData(r->filter.mask, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &ones);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);

    lc_frame_setup plain = *fs;
    plain.filtered = 0;
    lc_renderer_bind_geometry(r, prog, &plain, fs->width, fs->height, 1); /* the attributes */
    int n = L->n, over[LC_MAX_FILTERS], open[LC_MAX_FILTERS][2];
    float bounds[LC_MAX_FILTERS][2];
    for (int i = 0; i < n; i++) {
        over[i] = (int)L->f[i].over;
        bounds[i][0] = bound(L->f[i].lo), bounds[i][1] = bound(L->f[i].hi);
        open[i][0] = L->f[i].lo_open, open[i][1] = L->f[i].hi_open;
    }
    lc_uniform_i(prog, "u_filters", n);
    glProgramUniform1iv(prog, glGetUniformLocation(prog, "u_filter_attr"), n, attr);
    glProgramUniform1iv(prog, glGetUniformLocation(prog, "u_filter_over"), n, over);
    glProgramUniform2fv(prog, glGetUniformLocation(prog, "u_filter_bounds"), n, &bounds[0][0]);
    glProgramUniform2iv(prog, glGetUniformLocation(prog, "u_filter_open"), n, &open[0][0]);
    int lines = s->type == LC_PRIM_LINES;
    uint32_t items = lines ? s->line_count : s->vertex_count;
    lc_uniform_i(prog, "u_per_line", lines);
    lc_uniform_u(prog, "u_items", items);
    if (lines)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_LINE_OFFSETS, r->filter.offsets);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_VISIBLE_OUT, r->filter.mask);
    lc_dispatch_linear((items + 255) / 256);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    memcpy(r->filter.filters, L->f, sizeof(lc_filter) * (size_t)n);
    memcpy(r->filter.attr, attr, sizeof(int) * (size_t)n);
    r->filter.count = n;
    r->filter.serial++;
    return 0;
}

int lc_filter_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    fs->filtered = 0;
    fs->terms.mask_serial = 0;
    fs->pull_lines = r->pull_lines = 0;
    if (fs->params->filter_count <= 0 && !fs->params->time.has_window)
        return 0;
    filter_list L;
    int rc = resolve(fs, &L, err);
    if (rc)
        return rc;
    if (!same_filters(r, fs, &L) && (rc = build(r, fs, &L, err)) != 0)
        return rc;
    fs->filtered = 1;
    fs->terms.mask_serial = r->filter.serial;
    /* A window hides single segments of a line: ribbon strips share each
     * vertex between two segments, so lines are drawn segment by segment. */
    fs->pull_lines = r->pull_lines = L.time && fs->gs->scene->type == LC_PRIM_LINES;
    return 0;
}
