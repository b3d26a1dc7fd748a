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

/* Resolves attribute names and checks that each predicate suits the scene. */
static int resolve(const lc_frame_setup *fs, int attr[LC_MAX_FILTERS], lc_error *err)
{
    const lc_render_params *p = fs->params;
    const lc_scene *s = fs->gs->scene;
    for (int i = 0; i < p->filter_count; i++) {
        const lc_filter *f = &p->filters[i];
        char field[40];
        snprintf(field, sizeof field, "filter[%d].attribute", i);
        attr[i] = lc_scene_find_attribute(s, f->attribute);
        if (attr[i] < 0)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s has no attribute \"%s\"", s->name, f->attribute);
        snprintf(field, sizeof field, "filter[%d].over", i);
        if (s->type == LC_PRIM_TRIANGLES)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s is a surface: only lines and points can be filtered",
                                s->name);
        if (s->type == LC_PRIM_POINTS && f->over != LC_FILTER_VERTEX)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s has points, not lines: use \"vertex\"", s->name);
        if (s->type == LC_PRIM_LINES && f->over == LC_FILTER_VERTEX)
            return lc_err_field(err, LC_ERR_INVALID, field,
                                "%s has lines: filter them by min, max, mean, first, last or change", s->name);
        if (s->type == LC_PRIM_LINES && !s->line_offsets)
            return lc_err_field(err, LC_ERR_INVALID, field, "%s keeps no line offsets", s->name);
    }
    return 0;
}

static int same_filters(const lc_renderer *r, const lc_frame_setup *fs, const int *attr)
{
    const lc_render_params *p = fs->params;
    return r->filter.scene == fs->gs->serial && r->filter.count == p->filter_count &&
           memcmp(r->filter.attr, attr, sizeof(int) * (size_t)p->filter_count) == 0 &&
           memcmp(r->filter.filters, p->filters, sizeof(lc_filter) * (size_t)p->filter_count) == 0;
}

static float bound(double v) { return v > FLT_MAX ? FLT_MAX : v < -FLT_MAX ? -FLT_MAX : (float)v; }

static int build(lc_renderer *r, lc_frame_setup *fs, const int *attr, lc_error *err)
{
    const lc_render_params *p = fs->params;
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
    int n = p->filter_count, over[LC_MAX_FILTERS], open[LC_MAX_FILTERS][2];
    float bounds[LC_MAX_FILTERS][2];
    for (int i = 0; i < n; i++) {
        over[i] = (int)p->filters[i].over;
        bounds[i][0] = bound(p->filters[i].lo), bounds[i][1] = bound(p->filters[i].hi);
        open[i][0] = p->filters[i].lo_open, open[i][1] = p->filters[i].hi_open;
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

    memcpy(r->filter.filters, p->filters, sizeof(lc_filter) * (size_t)n);
    memcpy(r->filter.attr, attr, sizeof(int) * (size_t)n);
    r->filter.count = n;
    r->filter.serial++;
    return 0;
}

int lc_filter_prepare(lc_renderer *r, lc_frame_setup *fs, lc_error *err)
{
    fs->filtered = 0;
    fs->terms.mask_serial = 0;
    if (fs->params->filter_count <= 0)
        return 0;
    int attr[LC_MAX_FILTERS];
    int rc = resolve(fs, attr, err);
    if (rc)
        return rc;
    if (!same_filters(r, fs, attr) && (rc = build(r, fs, attr, err)) != 0)
        return rc;
    fs->filtered = 1;
    fs->terms.mask_serial = r->filter.serial;
    return 0;
}
