/* Render cost estimates (see cost.h for the model). */
#include "cost.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "foo_math.h"

#define PI 3.14159265358979323846
/* Set-up of one primitive in one pass, in fragment units: on llvmpipe 200,000
 * small splats cost about as much as 2e7 fragments per pass. */
#define PRIMITIVE_UNITS 100.0

void lc_cost_stats_compute(const lc_scene *s, lc_cost_stats *out)
{
    memset(out, 0, sizeof *out);
    out->type = s->type;
    out->primitives = (double)lc_scene_primitive_count(s);
    out->vertices = s->vertex_count;
    out->lines = s->type == LC_PRIM_LINES ? s->line_count : 0;
    out->elements = s->elements.count;
    const double *b = s->bounds;
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        out->center[k] = 0.5 * (b[k] + b[k + 3]);
        d2 += (b[k + 3] - b[k]) * (b[k + 3] - b[k]);
    }
    out->radius = isfinite(d2) && d2 > 0 ? 0.5 * sqrt(d2) : 1.0;
    const float *P = s->positions;
    if (s->type == LC_PRIM_LINES && s->line_offsets) {
        for (uint32_t l = 0; l < s->line_count; l++)
            for (uint32_t i = s->line_offsets[l] + 1; i < s->line_offsets[l + 1]; i++) {
                const float *a = P + 3 * (size_t)(i - 1), *c = P + 3 * (size_t)i;
                double dx = c[0] - a[0], dy = c[1] - a[1], dz = c[2] - a[2];
                out->line_length += sqrt(dx * dx + dy * dy + dz * dz);
            }
    } else if (s->type == LC_PRIM_TRIANGLES && s->triangles) {
        for (uint32_t t = 0; t < s->triangle_count; t++) {
            const float *a = P + 3 * (size_t)s->triangles[3 * t], *c = P + 3 * (size_t)s->triangles[3 * t + 1],
                        *e = P + 3 * (size_t)s->triangles[3 * t + 2];
            double u[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, v[3] = {e[0] - a[0], e[1] - a[1], e[2] - a[2]};
            double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
            out->area += 0.5 * sqrt(x * x + y * y + z * z);
        }
    }
    if (s->part_of) { /* serve --mpi, a part read by this rank: what the whole costs */
        out->primitives = (double)s->whole_primitives;
        out->vertices = (double)s->whole_vertices;
        out->line_length = s->whole_line_length;
    }
    if (!isfinite(out->line_length))
        out->line_length = 1e300;
    if (!isfinite(out->area))
        out->area = 1e300;
}

/* Output pixels per world unit at the data centre. */
static double pixels_per_unit(const lc_cost_stats *st, const lc_render_params *p)
{
    double h = p->height;
    if (!p->has_camera)
        return h / (2.0 * st->radius); /* the fit shows the bounding sphere */
    const lc_camera *c = &p->camera;
    if (c->parallel_projection)
        return c->parallel_scale > 0 ? h / (2.0 * c->parallel_scale) : h;
    double d2 = 0;
    for (int k = 0; k < 3; k++)
        d2 += (c->position[k] - st->center[k]) * (c->position[k] - st->center[k]);
    /* A camera inside the data sees its nearest parts larger; the floor keeps
     * the scale finite (each primitive is capped at the image anyway). */
    double dist = fmax(sqrt(d2), 0.05 * st->radius);
    double half = tan(0.5 * fmin(fmax(c->view_angle, 1.0), 179.0) * PI / 180.0);
    return h / (2.0 * dist * half);
}

double lc_cost_estimate(const lc_cost_stats *st, const lc_render_params *p)
{
    double w = p->width, h = p->height, image = w * h;
    double ppu = pixels_per_unit(st, p);
    /* Fragments of one full-resolution geometry pass. */
    double frags;
    switch (st->type) {
    case LC_PRIM_POINTS: {
        double r = fmax(0.5 * p->style.point_size, 0.75);
        frags = st->primitives * fmin(PI * r * r, image);
        break;
    }
    case LC_PRIM_LINES: {
        double world = p->style.line_width > 0 ? p->style.line_width : 0.008 * st->radius; /* as render/gl/frame.c */
        double width = fmax(p->style.min_line_pixels, world * ppu);
        double ribbon = st->line_length * ppu * width + st->primitives * width; /* + the joins */
        frags = fmin(ribbon, st->primitives * image);
        /* lines.clusters draws one line per cluster (hidden ones still pass the vertex stage). */
        if (p->clusters.count > 0 && st->lines > p->clusters.count)
            frags *= p->clusters.count / st->lines;
        break;
    }
    default: frags = fmin(st->area * ppu * ppu, st->primitives * image); break;
    }
    const lc_foo_params *f = &p->foo;
    double s2 = f->resolution_scale * f->resolution_scale;
    double targets = ceil((2.0 * f->bands + 1.0) / 4.0);
    double subset = f->subset > 1 ? f->subset : 1;
    double geometry, screens;
    lc_depth_range range = lc_foo_depth_range(f);
    switch (p->method) {
    case LC_METHOD_FOURIER: /* P1 (targets, /subset) and P2 at s^2; P4 (targets, /subset) and P5 at full */
        geometry = (s2 + 1.0) * (targets / subset + 1.0);
        if (range == LC_DEPTH_RANGE_PIXEL)
            geometry += s2 + 1.0;
        else if (range == LC_DEPTH_RANGE_MOMENTS)
            geometry += s2 / subset; /* P0 "moments": one target at s^2 */
        screens = targets + 2.0;
        break;
    case LC_METHOD_EXACT: /* fragment lists at both resolutions; insertion, sort and blend per fragment */
        geometry = 4.0 * (s2 + 1.0);
        screens = 4.0;
        break;
    case LC_METHOD_OPAQUE:
        geometry = 1.0;
        screens = 1.0;
        break;
    case LC_METHOD_DIRECT:
        geometry = targets + 1.0;
        screens = targets + 2.0;
        break;
    default: /* wboit: P1, P2 at s^2, one blended pass */
        geometry = s2 * (targets + 1.0) + 2.0;
        screens = targets + 3.0;
        break;
    }
    double passes = ceil(geometry);
    return frags * geometry + image * screens + (st->vertices + PRIMITIVE_UNITS * st->primitives) * passes +
           st->elements * (f->smoothing + 1.0);
}

const char *lc_cost_field(const lc_cost_stats *st, const lc_render_params *p, double budget)
{
    lc_render_params q = *p;
    lc_style defaults;
    lc_style_default(&defaults);
    q.style.point_size = fmin(q.style.point_size, defaults.point_size);
    q.style.line_width = defaults.line_width; /* 0: derived from the bounds */
    q.style.min_line_pixels = fmin(q.style.min_line_pixels, defaults.min_line_pixels);
    if (lc_cost_estimate(st, &q) <= budget) {
        if (st->type == LC_PRIM_POINTS)
            return "style.pointSize";
        if (st->type == LC_PRIM_LINES)
            return p->style.min_line_pixels > defaults.min_line_pixels ? "style.minLinePixels" : "style.lineWidth";
    }
    lc_foo_params fd;
    lc_foo_params_default(&fd);
    q = *p;
    if (q.method != LC_METHOD_FOURIER && q.method != LC_METHOD_OPAQUE) {
        q.method = LC_METHOD_FOURIER;
        if (lc_cost_estimate(st, &q) <= budget)
            return "method";
    }
    if (lc_foo_depth_range(&p->foo) != LC_DEPTH_RANGE_GLOBAL) {
        q.foo.depth_range = LC_DEPTH_RANGE_GLOBAL;
        if (lc_cost_estimate(st, &q) <= budget)
            return "params.depthRange";
    }
    if (p->foo.bands > fd.bands) {
        q.foo.bands = fd.bands;
        if (lc_cost_estimate(st, &q) <= budget)
            return "params.bands";
    }
    if (p->foo.resolution_scale > fd.resolution_scale) {
        q.foo.resolution_scale = fd.resolution_scale;
        if (lc_cost_estimate(st, &q) <= budget)
            return "params.resolutionScale";
    }
    if (st->type == LC_PRIM_POINTS && p->style.point_size > defaults.point_size)
        return "style.pointSize";
    return "width";
}

int lc_cost_check(const lc_cost_stats *st, const lc_render_params *p, double budget, double *cost, const char **field,
                  char *msg, size_t n)
{
    *cost = lc_cost_estimate(st, p);
    if (budget <= 0 || *cost <= budget)
        return 0;
    *field = lc_cost_field(st, p, budget);
    snprintf(msg, n,
             "estimated cost %.3g exceeds this server's budget of %.3g per frame (--max-cost); lower %s "
             "(%dx%d, %s, %.0f primitives)",
             *cost, budget, *field, p->width, p->height, lc_method_name(p->method), st->primitives);
    return -1;
}
