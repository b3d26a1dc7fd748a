/* Hard filters (docs/ALGORITHM.md "Filters"): the request's predicates become
 * a visibility mask of one bit per vertex, written by a compute pass from the
 * attributes already on the GPU (a line predicate reduces the attribute over
 * the line's vertices, min/max/mean/first/last/change, and clears the bits of
 * every vertex of a line that fails). The geometry passes read the bit and
 * place a hidden vertex outside the clip volume, so a filtered line draws
 * nothing, and the compute passes that sum importance skip it. No uploaded
 * buffer changes: a new filter costs one pass over the vertices, not a reload.
 * A mask is kept while its scene and filters stay the same; a layered frame
 * holds one per filtered layer (the same dataset twice with two filter lists
 * included). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "renderer_internal.h"

typedef struct lc_filter_mask filter_mask;

static void release_mask(filter_mask *m)
{
    if (m->offsets)
        glDeleteBuffers(1, &m->offsets);
    if (m->mask)
        glDeleteBuffers(1, &m->mask);
    memset(m, 0, sizeof *m);
    m->count = -1;
}

void lc_filter_release(lc_renderer *r)
{
    for (int i = 0; i < LC_MAX_LAYERS; i++)
        release_mask(&r->filter[i]);
}

uint64_t lc_filter_bytes(const lc_renderer *r)
{
    uint64_t bytes = 0;
    for (int i = 0; i < LC_MAX_LAYERS; i++)
        if (r->filter[i].mask)
            bytes += ((uint64_t)r->filter[i].mask_words + r->filter[i].offset_words) * 4;
    return bytes;
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

static int same_filters(const filter_mask *m, const lc_frame_setup *fs, const filter_list *L)
{
    return m->scene == fs->gs->serial && m->count == L->n &&
           memcmp(m->attr, L->attr, sizeof(int) * (size_t)L->n) == 0 &&
           memcmp(m->filters, L->f, sizeof(lc_filter) * (size_t)L->n) == 0;
}

/* The mask for fs's scene and filters L: the one built for them; else one of
 * the scene's not drawn with this frame (its offsets kept), an empty one, or
 * the least recently used, to rebuild. */
static filter_mask *pick(lc_renderer *r, const lc_frame_setup *fs, const filter_list *L, int *fresh)
{
    filter_mask *best = NULL;
    int rank = 0;
    for (int i = 0; i < LC_MAX_LAYERS; i++) {
        filter_mask *m = &r->filter[i];
        if (same_filters(m, fs, L)) {
            *fresh = 0;
            return m;
        }
        if (m->used == r->filter_frame && m->scene) /* another layer of this frame draws with it */
            continue;
        int k = m->scene == fs->gs->serial ? 3 : !m->scene ? 2 : 1;
        if (k > rank || (k == rank && m->used < best->used))
            best = m, rank = k;
    }
    *fresh = 1;
    return best;
}

static float bound(double v) { return v > FLT_MAX ? FLT_MAX : v < -FLT_MAX ? -FLT_MAX : (float)v; }

static int build(lc_renderer *r, filter_mask *m, lc_frame_setup *fs, const filter_list *L, lc_error *err)
{
    const int *attr = L->attr;
    const lc_scene *s = fs->gs->scene;
    GLuint prog = lc_renderer_fixed_program(r, PROG_FILTER_MASK, err);
    if (!prog)
        return LC_ERR_GL;
    if (m->scene != fs->gs->serial) {
        release_mask(m);
        uint64_t bytes = 0;
        if (s->type == LC_PRIM_LINES) {
            m->offsets = lc_gl_buffer(s->line_offsets, ((size_t)s->line_count + 1) * sizeof(uint32_t), &bytes);
            m->offset_words = s->line_count + 1;
        }
        m->mask_words = (s->vertex_count + 31) / 32;
        glCreateBuffers(1, &m->mask);
        glNamedBufferStorage(m->mask, (GLsizeiptr)(m->mask_words ? m->mask_words : 1) * 4, NULL,
                             GL_DYNAMIC_STORAGE_BIT);
        m->scene = fs->gs->serial;
    }
    const uint32_t ones = 0xffffffffu;
    glClearNamedBufferData(m->mask, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &ones);
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
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_LINE_OFFSETS, m->offsets);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_VISIBLE_OUT, m->mask);
    lc_dispatch_linear((items + 255) / 256);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    memcpy(m->filters, L->f, sizeof(lc_filter) * (size_t)n);
    memcpy(m->attr, attr, sizeof(int) * (size_t)n);
    m->count = n;
    m->serial = ++r->filter_serial;
    return 0;
}

int lc_filter_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    fs->filtered = 0;
    fs->filter_mask = 0;
    fs->terms.mask_serial = 0;
    fs->pull_lines = r->pull_lines = 0;
    if (fs->params->filter_count <= 0 && !fs->params->time.has_window)
        return 0;
    filter_list L;
    int rc = resolve(fs, &L, err), fresh = 0;
    if (rc)
        return rc;
    filter_mask *m = pick(r, fs, &L, &fresh);
    if (!m) /* more filtered layers than masks: lc_render_check allows at most LC_MAX_LAYERS */
        return lc_err(err, LC_ERR_INTERNAL, "more filtered layers than filter masks");
    if (fresh && (rc = build(r, m, fs, &L, err)) != 0)
        return rc;
    m->used = r->filter_frame;
    fs->filtered = 1;
    fs->filter_mask = m->mask;
    fs->terms.mask_serial = m->serial;
    /* A window hides single segments of a line: ribbon strips share each
     * vertex between two segments, so lines are drawn segment by segment. */
    fs->pull_lines = r->pull_lines = L.time && fs->gs->scene->type == LC_PRIM_LINES;
    return 0;
}

void lc_filter_frame_begin(lc_renderer *r) { r->filter_frame++; }
