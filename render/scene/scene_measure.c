/* A scene's measures for cost estimates (scene_measure.h). */
#include "scene_measure.h"

#include <math.h>
#include <string.h>

void lc_scene_measure(const lc_scene *s, lc_scene_measures *out)
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
        if (s->type == LC_PRIM_LINES)
            out->lines = (double)s->whole_lines;
    }
    if (!isfinite(out->line_length))
        out->line_length = 1e300;
    if (!isfinite(out->area))
        out->area = 1e300;
}
