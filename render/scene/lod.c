/* Polyline simplification hierarchy (lod.h). */
#include "lod.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NONE UINT32_MAX
/* Spans longer than this split at their middle rather than at the farthest
 * vertex: the farthest-vertex split can peel one vertex at a time off a long
 * spiral (quadratic time), the middle split keeps the depth logarithmic; its
 * error is still the farthest distance over the span, so the bound holds. */
#define BALANCED_SPAN 1024

typedef struct span {
    uint32_t a, b, parent;
} span;

/* Squared distance from p to the segment a-b. */
static double seg_dist2(const float *p, const float *a, const float *b)
{
    double ab[3], ap[3], t = 0, len2 = 0;
    for (int i = 0; i < 3; i++) {
        ab[i] = (double)b[i] - a[i];
        ap[i] = (double)p[i] - a[i];
        t += ab[i] * ap[i];
        len2 += ab[i] * ab[i];
    }
    t = len2 > 0 ? t / len2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double d2 = 0;
    for (int i = 0; i < 3; i++) {
        double d = ap[i] - t * ab[i];
        d2 += d * d;
    }
    return d2;
}

typedef struct builder {
    const float *pos;
    float *err;
    uint32_t *parent, *order; /* split parent of each vertex; vertices in split order */
    size_t k;
    span *stack;
    size_t top, cap;
} builder;

/* Splits the run a..b (end points kept) down to single segments, recording
 * each split vertex's span error. Returns -1 on OOM. */
static int split_run(builder *bd, uint32_t a, uint32_t b)
{
    if (b - a < 2)
        return 0;
    bd->stack[bd->top++] = (span){a, b, NONE};
    while (bd->top > 0) {
        span sp = bd->stack[--bd->top];
        double best = -1;
        uint32_t far = sp.a + 1, mid = sp.a + (sp.b - sp.a) / 2;
        for (uint32_t v = sp.a + 1; v < sp.b; v++) {
            double d2 = seg_dist2(bd->pos + 3 * (size_t)v, bd->pos + 3 * (size_t)sp.a, bd->pos + 3 * (size_t)sp.b);
            /* Vertices on the chord (repeated points, straight runs) tie at 0:
             * the one nearest the middle keeps the split balanced, where the
             * first would peel one vertex per step (quadratic time). */
            if (d2 > best ||
                (d2 == 0 && best == 0 && (v > mid ? v - mid : mid - v) < (far > mid ? far - mid : mid - far)))
                best = d2, far = v;
        }
        uint32_t v = sp.b - sp.a > BALANCED_SPAN ? sp.a + (sp.b - sp.a) / 2 : far;
        bd->err[v] = (float)sqrt(best);
        bd->parent[v] = sp.parent;
        bd->order[bd->k++] = v;
        if (bd->top + 2 > bd->cap) {
            span *grown = realloc(bd->stack, 2 * bd->cap * sizeof *grown);
            if (!grown)
                return -1;
            bd->stack = grown, bd->cap *= 2;
        }
        if (v - sp.a >= 2)
            bd->stack[bd->top++] = (span){sp.a, v, v};
        if (sp.b - v >= 2)
            bd->stack[bd->top++] = (span){v, sp.b, v};
    }
    return 0;
}

int lc_lod_vertex_errors(const lc_scene *s, float *err, lc_error *err_out)
{
    uint32_t n = s->vertex_count;
    builder bd = {.pos = s->positions, .err = err, .cap = 256};
    bd.parent = malloc((n ? n : 1) * sizeof *bd.parent);
    bd.order = malloc((n ? n : 1) * sizeof *bd.order);
    bd.stack = malloc(bd.cap * sizeof *bd.stack);
    int rc = bd.parent && bd.order && bd.stack ? 0 : -1;
    for (uint32_t v = 0; v < n; v++)
        err[v] = INFINITY; /* run end points; split_run gives every other vertex its error */
    const uint32_t *ve = s->elements.vertex_elements;
    for (uint32_t l = 0; l < s->line_count && rc == 0; l++) {
        if ((l & 1023) == 0 && lc_cancelled()) {
            rc = LC_ERR_CANCELLED;
            break;
        }
        uint32_t first = s->line_offsets[l], end = s->line_offsets[l + 1];
        for (uint32_t a = first, b; a + 1 < end && rc == 0; a = b) {
            /* Runs end where the primary element changes: that vertex stays, so
             * every element keeps a segment (a segment belongs to the element
             * of its last vertex) and the opacity field keeps its resolution. */
            for (b = a + 1; b + 1 < end && (!ve || ve[4 * (size_t)b + 3] == ve[4 * (size_t)b + 7]); b++)
                ;
            rc = split_run(&bd, a, b);
        }
    }
    /* Monotone: children come after their parent in `order`, so a reverse walk
     * lifts every parent to its largest descendant. Then a vertex is only
     * dropped with all of its descendants, which its span's chord covers. */
    for (size_t i = bd.k; rc == 0 && i-- > 0;) {
        uint32_t v = bd.order[i], p = bd.parent[v];
        if (p != NONE && err[p] < err[v])
            err[p] = err[v];
    }
    free(bd.parent), free(bd.order), free(bd.stack);
    if (rc == LC_ERR_CANCELLED)
        return lc_err_cancelled(err_out, s->name);
    if (rc)
        return lc_err(err_out, LC_ERR_NOMEM, "%s: out of memory for the level-of-detail hierarchy", s->name);
    return 0;
}

double lc_lod_threshold(const lc_scene *s, int step)
{
    double d2 = 0;
    for (int i = 0; i < 3; i++)
        d2 += (s->bounds[i + 3] - s->bounds[i]) * (s->bounds[i + 3] - s->bounds[i]);
    return sqrt(d2) * pow(2.0, -0.5 * (LC_LOD_LADDER_FINEST - step));
}

/* counts (LC_LOD_COUNTS) of s from its vertex errors. */
static void line_counts(const lc_scene *s, const float *err, uint64_t counts[LC_LOD_COUNTS])
{
    double thresholds[LC_LOD_LADDER_STEPS];
    for (int j = 0; j < LC_LOD_COUNTS; j++)
        counts[j] = 0;
    for (int j = 0; j < LC_LOD_LADDER_STEPS; j++)
        thresholds[j] = lc_lod_threshold(s, j);
    for (uint32_t v = 0; v < s->vertex_count; v++)
        for (int j = 0; j < LC_LOD_LADDER_STEPS && err[v] > thresholds[j]; j++)
            counts[j]++;
    for (uint32_t l = 0; l < s->line_count; l++)
        counts[LC_LOD_LADDER_STEPS] += s->line_offsets[l + 1] > s->line_offsets[l];
    counts[LC_LOD_LADDER_STEPS + 1] = lc_scene_primitive_count(s);
}

int lc_lod_line_counts(const lc_scene *s, uint64_t counts[LC_LOD_COUNTS], lc_error *err)
{
    float *e = malloc(((size_t)s->vertex_count + 1) * sizeof *e);
    int rc = e ? lc_lod_vertex_errors(s, e, err) : lc_err(err, LC_ERR_NOMEM, "%s: out of memory", s->name);
    if (rc == 0)
        line_counts(s, e, counts);
    free(e);
    return rc;
}

uint32_t lc_lod_line_steps(const uint64_t counts[LC_LOD_COUNTS])
{
    uint64_t lines = counts[LC_LOD_LADDER_STEPS], segments = counts[LC_LOD_LADDER_STEPS + 1];
    uint32_t steps = LC_LOD_STEPS_GIVEN;
    int levels = 1;
    for (int j = 0; j < LC_LOD_LADDER_STEPS && levels < LC_LOD_MAX_LEVELS; j++) {
        uint64_t kept_segments = counts[j] - lines;
        if ((double)kept_segments > LC_LOD_SHRINK * (double)segments)
            continue;
        steps |= 1u << j;
        segments = kept_segments;
        levels++;
    }
    return steps;
}

/* Line levels from the vertex errors (at the ladder steps s->lod_steps names,
 * or its own); with_indices fills each level's pairs. */
static int line_levels(const lc_scene *s, const float *err, lc_lod *out, int with_indices, lc_error *e)
{
    uint64_t counts[LC_LOD_COUNTS];
    line_counts(s, err, counts);
    uint64_t lines = counts[LC_LOD_LADDER_STEPS];
    uint32_t steps = s->lod_steps ? s->lod_steps : lc_lod_line_steps(counts);
    for (int j = 0; j < LC_LOD_LADDER_STEPS && out->count < LC_LOD_MAX_LEVELS; j++) {
        if (!(steps & (1u << j)))
            continue;
        out->levels[out->count].error = lc_lod_threshold(s, j);
        out->levels[out->count].primitives = counts[j] - lines;
        out->count++;
    }
    for (int i = 0; with_indices && i < out->count; i++) {
        lc_lod_level *lv = &out->levels[i];
        lv->indices = malloc((lv->primitives ? lv->primitives : 1) * 2 * sizeof(uint32_t));
        if (!lv->indices)
            return lc_err(e, LC_ERR_NOMEM, "%s: out of memory for the level-of-detail hierarchy", s->name);
        double t = i == 0 ? -1.0 : lv->error;
        uint64_t k = 0;
        for (uint32_t l = 0; l < s->line_count; l++) {
            uint32_t prev = NONE;
            for (uint32_t v = s->line_offsets[l]; v < s->line_offsets[l + 1]; v++) {
                if (!(err[v] > t))
                    continue;
                if (prev != NONE) {
                    lv->indices[2 * k] = prev;
                    lv->indices[2 * k + 1] = v;
                    k++;
                }
                prev = v;
            }
        }
        lv->primitives = k; /* equals the count above */
    }
    return 0;
}

int lc_lod_line_levels(const lc_scene *s, lc_lod *out, int with_indices, lc_error *err)
{
    float *e = malloc((s->vertex_count ? s->vertex_count : 1) * sizeof *e);
    if (!e)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory for the level-of-detail hierarchy", s->name);
    int rc = lc_lod_vertex_errors(s, e, err);
    if (!rc)
        rc = line_levels(s, e, out, with_indices, err);
    free(e);
    return rc;
}

void lc_lod_free(lc_lod *lod)
{
    for (int i = 0; i < lod->count; i++) {
        free(lod->levels[i].indices);
        lod->levels[i].indices = NULL;
    }
}

uint64_t lc_lod_extra_bytes(const lc_scene *s, const lc_lod *lod)
{
    uint64_t per = s->type == LC_PRIM_LINES ? LC_LOD_BYTES_PER_SEGMENT : LC_LOD_BYTES_PER_TRIANGLE, n = 0;
    for (int i = 1; i < lod->count; i++)
        n += lod->levels[i].primitives * per +
             (s->type == LC_PRIM_LINES ? (uint64_t)s->line_count * LC_LOD_BYTES_PER_LINE : 0);
    return n;
}
