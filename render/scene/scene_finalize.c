/* Scene finalize: validation, bounds, attribute ranges, default mappings, the
 * derived per-vertex data (scene_derive.c) and the elements (elements.c). */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "elements.h"
#include "lod.h"
#include "scene.h"
#include "scene_derive.h"
#include "scene_motion.h"
#include "scene_part.h"

/* Structural checks: everything later steps index with must be in range. */
static int validate(const lc_scene *s, lc_error *err)
{
    if (s->type != LC_PRIM_POINTS && s->type != LC_PRIM_LINES && s->type != LC_PRIM_TRIANGLES)
        return lc_err(err, LC_ERR_INVALID, "%s: unknown primitive type %d", s->name, (int)s->type);
    if (s->vertex_count == 0 || !s->positions)
        return lc_err(err, LC_ERR_INVALID, "%s: scene has no vertices", s->name);
    if (s->vertex_count > LC_MAX_VERTICES)
        return lc_err(err, LC_ERR_LIMIT, "%s: %u vertices exceed the limit of %u", s->name, s->vertex_count,
                      LC_MAX_VERTICES);
    const float *p = s->positions;
    for (size_t i = 0; i < (size_t)s->vertex_count * 3; i++)
        if (!isfinite(p[i]))
            return lc_err(err, LC_ERR_INVALID, "%s: vertex %zu has a non-finite coordinate", s->name, i / 3);
    if (s->type == LC_PRIM_LINES) {
        if (s->line_count == 0 || !s->line_offsets)
            return lc_err(err, LC_ERR_INVALID, "%s: line scene without lines", s->name);
        if (s->line_count > LC_MAX_PRIMITIVES)
            return lc_err(err, LC_ERR_LIMIT, "%s: %u lines exceed the limit of %u", s->name, s->line_count,
                          LC_MAX_PRIMITIVES);
        const uint32_t *off = s->line_offsets;
        for (uint32_t i = 0; i < s->line_count; i++)
            if (off[i + 1] < off[i])
                return lc_err(err, LC_ERR_INVALID, "%s: line %u: offsets decrease (%u after %u)", s->name, i,
                              off[i + 1], off[i]);
        if (off[s->line_count] > s->vertex_count)
            return lc_err(err, LC_ERR_INVALID, "%s: line offsets end at %u beyond %u vertices", s->name,
                          off[s->line_count], s->vertex_count);
    }
    if (s->type == LC_PRIM_TRIANGLES) {
        if (s->triangle_count == 0 || !s->triangles)
            return lc_err(err, LC_ERR_INVALID, "%s: triangle scene without triangles", s->name);
        if (s->triangle_count > LC_MAX_PRIMITIVES)
            return lc_err(err, LC_ERR_LIMIT, "%s: %u triangles exceed the limit of %u", s->name, s->triangle_count,
                          LC_MAX_PRIMITIVES);
        const uint32_t *t = s->triangles;
        for (size_t i = 0; i < (size_t)s->triangle_count * 3; i++)
            if (t[i] >= s->vertex_count)
                return lc_err(err, LC_ERR_INVALID, "%s: triangle %zu: vertex index %u out of range (%u vertices)",
                              s->name, i / 3, t[i], s->vertex_count);
    }
    return LC_OK;
}

static void compute_bounds(lc_scene *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const float *p = s->positions;
    for (uint32_t i = 0; i < s->vertex_count; i++)
        for (int k = 0; k < 3; k++) {
            double v = p[3 * (size_t)i + k];
            if (v < lo[k])
                lo[k] = v;
            if (v > hi[k])
                hi[k] = v;
        }
    for (int k = 0; k < 3; k++) {
        s->bounds[k] = lo[k];
        s->bounds[3 + k] = hi[k];
    }
}

#define PCT_BINS 4096

#define PCT_MAX 4 /* quantiles refined together by lc_scene_percentiles */

/* One level's histogram (counts, and each bin's least and greatest value)
 * summed over the processes of c, in place. */
static int combine_histogram(const lc_scene_collective *c, uint32_t *h, float *mn, float *mx, lc_error *err)
{
    static _Thread_local uint64_t counts[PCT_BINS];
    static _Thread_local double ends[2 * PCT_BINS];
    for (int k = 0; k < PCT_BINS; k++) {
        counts[k] = h[k];
        ends[k] = mn[k], ends[PCT_BINS + k] = -(double)mx[k]; /* one MIN for both */
    }
    if (c->sum_u64(c->ctx, counts, PCT_BINS, err) || c->min_f64(c->ctx, ends, 2 * PCT_BINS, err))
        return LC_ERR_INTERNAL;
    for (int k = 0; k < PCT_BINS; k++) {
        h[k] = (uint32_t)counts[k];
        mn[k] = (float)ends[k], mx[k] = (float)-ends[PCT_BINS + k];
    }
    return 0;
}

/* Values of ranks p[q] * (finite count - 1) among the finite values in [lo,
 * hi]: a histogram over [lo, hi], then one over the bin that holds each rank,
 * and so on until a bin is narrow against its values or the whole range (an
 * outlier that stretches the range to 1e30 costs a few more passes, not
 * precision), with no copy of the values. The first level's histogram serves
 * every rank. Each bin also keeps the least and greatest value in it, and a
 * rank's final bin is spread evenly over those: the one value itself when they
 * are all equal (integer codes, a clamped attribute), so a percentile never
 * lands between equal values. With c, the values are this process's share of
 * them: the counts and every level's histograms are summed over the processes
 * (bin extremes by min/max), so each process takes the same steps and finds
 * the values one process would find over all of them. */
static int percentiles(const float *v, uint32_t n, float lo, float hi, const double *p, int np, float *out,
                       const lc_scene_collective *c, lc_error *err)
{
    static _Thread_local uint32_t hist[PCT_MAX][PCT_BINS];
    static _Thread_local float bmin[PCT_MAX][PCT_BINS], bmax[PCT_MAX][PCT_BINS];
    double a[PCT_MAX], b[PCT_MAX], rank[PCT_MAX], narrow = 1e-7 * ((double)hi - lo);
    uint64_t below[PCT_MAX];
    int active[PCT_MAX];
    uint64_t finite = 0;
    for (uint32_t i = 0; i < n; i++)
        finite += isfinite(v[i]) != 0;
    if (c && c->sum_u64(c->ctx, &finite, 1, err))
        return LC_ERR_INTERNAL;
    for (int q = 0; q < np; q++) {
        out[q] = lo;
        a[q] = lo, b[q] = hi, below[q] = 0;
        rank[q] = p[q] * (double)(finite ? finite - 1 : 0);
        active[q] = finite > 0 && hi > lo;
    }
    for (int level = 0; level < 12; level++) {
        int shared = level == 0 ? 1 : np; /* the first window is [lo, hi] for every rank */
        for (int q = 0; q < shared; q++) {
            if (!active[q])
                continue;
            uint32_t *h = hist[q];
            float *mn = bmin[q], *mx = bmax[q];
            memset(h, 0, sizeof hist[q]);
            for (int k = 0; k < PCT_BINS; k++)
                mn[k] = INFINITY, mx[k] = -INFINITY;
            double wa = a[q], wb = b[q], scale = PCT_BINS / (wb - wa);
            for (uint32_t i = 0; i < n; i++) {
                float x = v[i];
                if (!(x >= wa && x <= wb)) /* outside, or NaN */
                    continue;
                long k = (long)((x - wa) * scale);
                k = k < PCT_BINS ? k : PCT_BINS - 1;
                h[k]++;
                mn[k] = x < mn[k] ? x : mn[k];
                mx[k] = x > mx[k] ? x : mx[k];
            }
            if (c && combine_histogram(c, h, mn, mx, err))
                return LC_ERR_INTERNAL;
        }
        for (int q = shared; q < np; q++) {
            memcpy(hist[q], hist[0], sizeof hist[q]);
            memcpy(bmin[q], bmin[0], sizeof bmin[q]);
            memcpy(bmax[q], bmax[0], sizeof bmax[q]);
        }
        int any = 0;
        for (int q = 0; q < np; q++) {
            if (!active[q])
                continue;
            uint64_t acc = below[q];
            int k = 0;
            while (k < PCT_BINS - 1 && (double)(acc + hist[q][k]) <= rank[q])
                acc += hist[q][k++];
            below[q] = acc;
            double w = (b[q] - a[q]) / PCT_BINS;
            a[q] += k * w;
            b[q] = a[q] + w;
            uint32_t count = hist[q][k];
            float vmin = bmin[q][k], vmax = bmax[q][k];
            out[q] = (float)a[q];
            if (count == 0) {
                active[q] = 0;
            } else if (vmin == vmax || w <= 1e-6 * fmax(fabs(a[q]), fabs(b[q])) || w <= narrow || level == 11) {
                double in_bin = rank[q] - (double)acc;
                out[q] = vmax > vmin ? (float)(vmin + (vmax - vmin) * ((in_bin + 0.5) / count)) : vmin;
                active[q] = 0;
            }
            any |= active[q];
        }
        if (!any)
            break;
    }
    return 0;
}

float lc_scene_percentile(const float *v, uint32_t n, float lo, float hi, double p)
{
    float out;
    percentiles(v, n, lo, hi, &p, 1, &out, NULL, NULL);
    return out;
}

/* a's statistics; with c over every process's share of its values (the
 * result is the whole scene's on every process). */
static int update_range(lc_attribute *a, uint32_t n, const lc_scene_collective *c, lc_error *err)
{
    float lo = INFINITY, hi = -INFINITY;
    for (uint32_t i = 0; i < n; i++) {
        float v = a->values[i];
        if (!isfinite(v))
            continue;
        if (v < lo)
            lo = v;
        if (v > hi)
            hi = v;
    }
    if (c) {
        double m[2] = {lo, -(double)hi}; /* one MIN for both ends */
        if (c->min_f64(c->ctx, m, 2, err))
            return LC_ERR_INTERNAL;
        lo = (float)m[0], hi = (float)-m[1];
    }
    if (lo > hi) /* no finite value at all */
        lo = hi = 0.0f;
    a->min = lo;
    a->max = hi;
    static const double ranks[4] = {0.02, 0.25, 0.75, 0.98};
    float pct[4];
    if (percentiles(a->values, n, lo, hi, ranks, 4, pct, c, err))
        return LC_ERR_INTERNAL;
    a->p02 = pct[0], a->p98 = pct[3];
    /* The auto range: each end at the farther of its percentile and the last
     * value inside Tukey's far-out fence (a box plot's whisker). */
    double q1 = pct[1], q3 = pct[2];
    double fence_lo = q1 - 3.0 * (q3 - q1), fence_hi = q3 + 3.0 * (q3 - q1);
    float whisker_lo = a->p02, whisker_hi = a->p98;
    for (uint32_t i = 0; i < n; i++) {
        float v = a->values[i];
        if (v >= fence_lo && v < whisker_lo) /* false for NaN */
            whisker_lo = v;
        if (v <= fence_hi && v > whisker_hi)
            whisker_hi = v;
    }
    if (c) {
        double m[2] = {whisker_lo, -(double)whisker_hi};
        if (c->min_f64(c->ctx, m, 2, err))
            return LC_ERR_INTERNAL;
        whisker_lo = (float)m[0], whisker_hi = (float)-m[1];
    }
    a->auto_lo = whisker_lo;
    a->auto_hi = whisker_hi;
    return 0;
}

void lc_attribute_update_range(lc_attribute *a, uint32_t n) { update_range(a, n, NULL, NULL); }

/* docs/GUIDE.md "Default attributes": the names whose smaller values matter more. */
bool lc_attribute_smaller_matters(const char *name)
{
    static const char *const words[] = {"mag",    "magnitude", "vmag", "bmag",   "gmag",
                                        "absmag", "appmag",    "rank", "pvalue", "pval"};
    char word[LC_NAME_LEN];
    int p_word = 0;
    for (const char *c = name;;) {
        size_t n = 0;
        while (*c && !isalnum((unsigned char)*c))
            c++;
        while (isalnum((unsigned char)*c) && n + 1 < sizeof word)
            word[n++] = (char)tolower((unsigned char)*c++);
        while (isalnum((unsigned char)*c)) /* a word longer than a name: cut */
            c++;
        if (n == 0)
            return false;
        word[n] = '\0';
        for (size_t i = 0; i < sizeof words / sizeof words[0]; i++)
            if (strcmp(word, words[i]) == 0)
                return true;
        if (p_word && strcmp(word, "value") == 0)
            return true;
        p_word = strcmp(word, "p") == 0;
    }
}

/* Whole values over a short span (scene.h): [0] 1 when every finite value is
 * an integer, [1] the smallest, [2] minus the largest, so that one MIN over
 * the processes agrees on all three. */
static void category_terms(const lc_attribute *a, uint32_t n, double m[3])
{
    double whole = 1, lo = INFINITY, hi = -INFINITY;
    for (uint32_t i = 0; i < n; i++) {
        float v = a->values[i];
        if (!isfinite(v))
            continue;
        if (v != floorf(v)) {
            whole = 0;
            break;
        }
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
    }
    m[0] = whole, m[1] = lo, m[2] = -hi;
}

/* n: the whole file's vertices; a label's kinds repeat (LC_CATEGORY_REPEATS
 * vertices a kind on average), so a short file of whole-number amounts (a
 * temperature in whole kelvins over six vertices) is not taken for one. */
static bool category_of(const double m[3], uint64_t n)
{
    double span = -m[2] - m[1];
    return m[0] == 1 && span > 0 && span < LC_CATEGORY_SPAN && (double)n >= LC_CATEGORY_REPEATS * (span + 1);
}

bool lc_attribute_categorical(const lc_attribute *a, uint32_t n)
{
    double m[3];
    category_terms(a, n, m);
    return category_of(m, n);
}

/* Marks the file's categorical attributes (before anything is derived) and
 * says whether one of them can be the importance. */
static int mark_categories(lc_scene *s, const lc_scene_collective *c, uint64_t whole, bool *measured, lc_error *err)
{
    double m[3 * LC_MAX_ATTRIBUTES];
    for (int i = 0; i < s->attribute_count; i++)
        category_terms(&s->attributes[i], s->vertex_count, m + 3 * i);
    if (c && s->attribute_count > 0 && c->min_f64(c->ctx, m, 3 * (size_t)s->attribute_count, err))
        return LC_ERR_INTERNAL;
    *measured = false;
    for (int i = 0; i < s->attribute_count; i++) {
        s->attributes[i].categorical = category_of(m + 3 * i, whole);
        /* one named importance stays the importance (choose_defaults) */
        *measured = *measured || !s->attributes[i].categorical || strcmp(s->attributes[i].name, "importance") == 0;
    }
    return 0;
}

/* Picks the importance and colour attributes a request without them gets
 * (docs/GUIDE.md "Default attributes"); file_attributes: how many of the scene's
 * attributes came from the file (the derived ones follow). A name that the
 * loader set but that does not exist is dropped with a warning rather than
 * failing the whole dataset; a class label the loader picked gives way to the
 * first attribute of the file that measures an amount, else to the derived
 * one (for points, density is derived when every attribute is a label). The
 * colour a loader left open: the file's own colours, else its first class
 * label (the kinds shown by colour, their importance by opacity), else the
 * importance. */
static void choose_defaults(lc_scene *s, int file_attributes)
{
    for (int i = 0; i < s->attribute_count; i++)
        s->attributes[i].smaller_matters = lc_attribute_smaller_matters(s->attributes[i].name);
    if (s->default_importance[0] && lc_scene_find_attribute(s, s->default_importance) < 0) {
        LC_WARN("scene", "%s: default importance '%s' is not an attribute; choosing another", s->name,
                s->default_importance);
        s->default_importance[0] = '\0';
    }
    const char *derived = s->type == LC_PRIM_LINES       ? "curvature"
                          : s->type == LC_PRIM_TRIANGLES ? "mean_curvature"
                                                         : "density";
    int at = s->default_importance[0] ? lc_scene_find_attribute(s, s->default_importance) : -1;
    bool label = at >= 0 && s->attributes[at].categorical && strcmp(s->default_importance, "importance") != 0;
    if (label || (!s->default_importance[0] && s->type == LC_PRIM_POINTS)) {
        char was[LC_NAME_LEN];
        snprintf(was, sizeof was, "%s", s->default_importance);
        s->default_importance[0] = '\0';
        for (int i = 0; i < file_attributes && !s->default_importance[0]; i++)
            if (!s->attributes[i].categorical)
                snprintf(s->default_importance, sizeof s->default_importance, "%s", s->attributes[i].name);
        if (!s->default_importance[0] && lc_scene_find_attribute(s, derived) >= 0)
            snprintf(s->default_importance, sizeof s->default_importance, "%s", derived);
        if (label)
            LC_INFO("scene", "%s: '%s' names classes, not amounts: importance '%s' by default", s->name, was,
                    s->default_importance[0] ? s->default_importance : "(none)");
    }
    if (!s->default_importance[0]) {
        if (s->type != LC_PRIM_POINTS && lc_scene_find_attribute(s, derived) >= 0)
            snprintf(s->default_importance, sizeof s->default_importance, "%s", derived);
        else if (s->attribute_count > 0)
            snprintf(s->default_importance, sizeof s->default_importance, "%s", s->attributes[0].name);
        /* else: no attribute at all, the renderer uses g = 1 */
    }
    if (!s->default_color[0] && s->rgb)
        snprintf(s->default_color, sizeof s->default_color, "rgb");
    for (int i = 0; i < file_attributes && !s->default_color[0]; i++)
        if (s->attributes[i].categorical && strcmp(s->attributes[i].name, s->default_importance) != 0)
            snprintf(s->default_color, sizeof s->default_color, "%s", s->attributes[i].name);
    if (!s->default_color[0])
        snprintf(s->default_color, sizeof s->default_color, "importance");
}

static lc_element_geometry element_geometry(const lc_scene *s)
{
    return (lc_element_geometry){.name = s->name,
                                 .type = s->type,
                                 .vertex_count = s->vertex_count,
                                 .positions = s->positions,
                                 .line_count = s->line_count,
                                 .line_offsets = s->line_offsets,
                                 .triangle_count = s->triangle_count,
                                 .triangles = s->triangles};
}

static int part_elements(lc_scene *s, const lc_elements_desc *desc, const lc_scene_collective *c, double *line_length,
                         lc_error *err);
static int part_lod_steps(lc_scene *s, const lc_scene_collective *c, lc_error *err);

/* Levels of detail kept from a scene cache (scene.h lod) follow the elements'
 * runs: new elements make them stale, and the upload builds them afresh. */
static void drop_levels(lc_scene *s)
{
    if (s->lod && s->lod_free)
        s->lod_free(s->lod);
    s->lod = NULL;
    s->lod_free = NULL;
}

int lc_scene_set_element_budget(lc_scene *s, uint32_t budget, lc_error *err)
{
    if (!s || !s->finalized)
        return lc_err(err, LC_ERR_INVALID, "scene: not finalized");
    if (s->released)
        return lc_err_field(err, LC_ERR_INVALID, "elements",
                            "%s: the vertex arrays were released after the upload; load the dataset again", s->name);
    if (s->type == LC_PRIM_POINTS)
        return 0;
    if (s->part_of) {
        const lc_scene_collective *c = s->collective;
        lc_elements_desc desc = {.line_budget = budget};
        int rc = c->agree(c->ctx, part_elements(s, &desc, c, NULL, err), err);
        return rc ? rc : part_lod_steps(s, c, err); /* the levels follow the elements' runs */
    }
    uint64_t most = s->type == LC_PRIM_LINES ? lc_scene_primitive_count(s) : s->vertex_count;
    if (budget > most || budget > (1u << 24))
        return lc_err_field(err, LC_ERR_INVALID, "elements",
                            "%s: %u elements requested, at most %llu (its %s, and never above 2^24)", s->name, budget,
                            (unsigned long long)(most < (1u << 24) ? most : (1u << 24)),
                            s->type == LC_PRIM_LINES ? "segments" : "vertices");
    lc_elements_desc desc = {.line_budget = budget, .patch_count = budget};
    lc_element_geometry g = element_geometry(s);
    lc_elements fresh = {0};
    int rc = lc_elements_build(&g, &desc, &fresh, err);
    if (rc)
        return rc;
    lc_elements_free(&s->elements);
    s->elements = fresh;
    drop_levels(s);
    return 0;
}

/* Frees what finalize derives, so that it can run again. */
static void drop_derived(lc_scene *s)
{
    drop_levels(s);
    free(s->normals);
    free(s->tangents);
    s->normals = s->tangents = NULL;
    lc_elements_free(&s->elements);
    s->finalized = 0;
}

int lc_scene_finalize(lc_scene *s, const lc_elements_desc *desc, lc_error *err)
{
    if (!s)
        return lc_err(err, LC_ERR_INVALID, "scene: NULL scene");
    double t0 = lc_now();
    int rc = validate(s, err);
    if (rc)
        return rc;
    drop_derived(s); /* finalize may run again (e.g. new element budget) */

    compute_bounds(s);
    bool measured;
    int file_attributes = s->attribute_count;
    if ((rc = mark_categories(s, NULL, s->vertex_count, &measured, err)) != 0)
        return rc;
    if (s->type == LC_PRIM_LINES) {
        rc = lc_scene_derive_lines(s, err);
        if (!rc)
            rc = lc_scene_derive_line_measures(s, s->vertex_count, NULL, err);
        if (!rc && s->trajectory.geographic)
            rc = lc_scene_derive_trajectories(s, err);
        int timed;
        if (!rc)
            rc = lc_scene_derive_motion(s, &timed, err);
    } else if (s->type == LC_PRIM_TRIANGLES)
        rc = lc_scene_derive_triangles(s, err);
    else if (!measured) /* no attribute, or only class labels */
        rc = lc_scene_derive_points(s, s->vertex_count, NULL, err);
    if (rc)
        return rc;
    if (lc_cancelled())
        return lc_err_cancelled(err, s->name);
    for (int i = 0; i < s->attribute_count; i++)
        lc_attribute_update_range(&s->attributes[i], s->vertex_count);
    choose_defaults(s, file_attributes);
    double t1 = lc_now();
    if (lc_cancelled())
        return lc_err_cancelled(err, s->name);
    lc_element_geometry g = element_geometry(s);
    rc = lc_elements_build(&g, desc, &s->elements, err);
    if (rc)
        return rc;
    s->finalized = 1;
    double t2 = lc_now();
    LC_INFO("scene",
            "%s: %s, %u vertices, %llu primitives, %d attributes, %u elements "
            "(derive %.0f ms, elements %.0f ms)",
            s->name, lc_prim_type_name(s->type), s->vertex_count, (unsigned long long)lc_scene_primitive_count(s),
            s->attribute_count, s->elements.count, (t1 - t0) * 1e3, (t2 - t1) * 1e3);
    return LC_OK;
}

/* part_elements for lines: (vertex count, length) pairs of every line,
 * concatenated in process order, give each process the whole's line table. */
static int part_line_elements(lc_scene *s, const lc_element_geometry *g, const lc_elements_desc *desc,
                              const lc_scene_collective *c, double *line_length, lc_elements *out, void **all,
                              uint64_t **bytes_of, lc_error *err)
{
    int rc = 0;
    uint32_t n = s->line_count;
    uint32_t *mine = malloc(((size_t)n + 1) * 2 * sizeof *mine);
    float *len = malloc(((size_t)n + 1) * sizeof *len);
    if (!mine || !len)
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %u line lengths", s->name, n);
    else
        lc_elements_line_lengths(g, len);
    for (uint32_t l = 0; !rc && l < n; l++) {
        mine[2 * l] = s->line_offsets[l + 1] - s->line_offsets[l];
        memcpy(&mine[2 * l + 1], &len[l], sizeof(float));
    }
    /* A process that failed still takes part, with nothing to add. */
    int grc = c->gather(c->ctx, mine, rc ? 0 : (size_t)n * 2 * sizeof *mine, all, bytes_of, err);
    free(mine);
    free(len);
    if (rc || grc)
        return rc ? rc : grc;
    uint64_t total_bytes = 0, first_bytes = 0;
    for (int r = 0; r < c->size; r++) {
        first_bytes += r < c->rank ? (*bytes_of)[r] : 0;
        total_bytes += (*bytes_of)[r];
    }
    uint64_t lines = total_bytes / (2 * sizeof(uint32_t));
    if (lines > LC_MAX_PRIMITIVES)
        return lc_err(err, LC_ERR_LIMIT, "%s: %llu lines over all processes exceed the limit of %u", s->name,
                      (unsigned long long)lines, (unsigned)LC_MAX_PRIMITIVES);
    uint32_t *counts = malloc((lines + 1) * sizeof *counts);
    float *lengths = malloc((lines + 1) * sizeof *lengths);
    if (!counts || !lengths)
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for the table of %llu lines", s->name,
                    (unsigned long long)lines);
    uint64_t vertices = 0;
    double length = 0;
    for (uint64_t l = 0; !rc && l < lines; l++) {
        const uint32_t *pair = (const uint32_t *)*all + 2 * l;
        counts[l] = pair[0];
        memcpy(&lengths[l], &pair[1], sizeof(float));
        vertices += pair[0];
        length += lengths[l];
    }
    uint64_t budget = desc ? desc->line_budget : 0, segments = vertices - lines;
    if (!rc && (budget > segments || budget > (1u << 24))) /* as lc_scene_set_element_budget */
        rc = lc_err_field(err, LC_ERR_INVALID, "elements",
                          "%s: %llu elements requested, at most %llu (its segments, and never above 2^24)", s->name,
                          (unsigned long long)budget,
                          (unsigned long long)(segments < (1u << 24) ? segments : (1u << 24)));
    uint32_t first_line = (uint32_t)(first_bytes / (2 * sizeof(uint32_t)));
    if (!rc) {
        lc_line_census whole = {.line_count = (uint32_t)lines,
                                .vertex_counts = counts,
                                .lengths = lengths,
                                .vertex_count = vertices,
                                .first_line = first_line};
        rc = lc_elements_build_lines_part(g, desc, &whole, out, err);
    }
    if (!rc) {
        s->vertex_base = 0;
        for (uint32_t l = 0; l < first_line; l++)
            s->vertex_base += counts[l];
        if (line_length)
            *line_length = length;
    }
    free(counts);
    free(lengths);
    return rc;
}

/* The ladder steps of the whole's line levels of detail (lod.h): each step's
 * kept vertices, the lines and the segments summed over the processes, so
 * that every rank simplifies alike. Needs the part's elements (runs end where
 * the primary element changes). Collective. */
static int part_lod_steps(lc_scene *s, const lc_scene_collective *c, lc_error *err)
{
    uint64_t counts[LC_LOD_COUNTS];
    int rc = c->agree(c->ctx, lc_lod_line_counts(s, counts, err), err);
    if (rc == 0 && c->sum_u64(c->ctx, counts, LC_LOD_COUNTS, err))
        rc = LC_ERR_INTERNAL;
    if (rc == 0)
        s->lod_steps = lc_lod_line_steps(counts);
    return rc;
}

/* The elements of a part in the whole scene's numbering: every process
 * contributes its lines' vertex counts and lengths (8 bytes a line) or its
 * point count, and each builds the same budget split from the same table. */
static int part_elements(lc_scene *s, const lc_elements_desc *desc, const lc_scene_collective *c, double *line_length,
                         lc_error *err)
{
    lc_element_geometry g = element_geometry(s);
    lc_elements fresh = {0}; /* replaces the part's elements only when every step succeeded */
    uint64_t *bytes_of = NULL;
    void *all = NULL;
    int rc = 0;
    if (s->type == LC_PRIM_POINTS) {
        uint64_t mine = s->vertex_count, first = 0, total = 0;
        rc = c->gather(c->ctx, &mine, sizeof mine, &all, &bytes_of, err);
        for (int r = 0; !rc && r < c->size; r++) {
            uint64_t n = ((const uint64_t *)all)[r];
            first += r < c->rank ? n : 0;
            total += n;
        }
        if (!rc && (rc = lc_elements_build_points_part(&g, first, total, &fresh, err)) == 0)
            s->vertex_base = first;
    } else {
        rc = part_line_elements(s, &g, desc, c, line_length, &fresh, &all, &bytes_of, err);
    }
    if (rc == 0) {
        lc_elements_free(&s->elements);
        s->elements = fresh;
    }
    free(all);
    free(bytes_of);
    return rc;
}

int lc_scene_finalize_part(lc_scene *s, const lc_elements_desc *desc, const lc_scene_collective *c, lc_error *err)
{
    if (!c)
        return lc_err(err, LC_ERR_INVALID, "scene: a part without collectives");
    double t0 = lc_now();
    int rc = 0;
    if (!s)
        rc = lc_err(err, LC_ERR_INVALID, "scene: NULL scene");
    else if (s->type == LC_PRIM_TRIANGLES)
        rc = lc_err(err, LC_ERR_UNSUPPORTED, "%s: surfaces are split after loading the whole mesh, not read in parts",
                    s->name);
    else if (s->vertex_count > 0 || s->line_count > 0) /* a part may be empty */
        rc = validate(s, err);
    if ((rc = c->agree(c->ctx, rc, err)) != 0)
        return rc;
    drop_derived(s);

    /* What must agree over the parts: the totals, the attributes, the bounds. */
    uint64_t total = s->vertex_count;
    double attrs[2] = {s->attribute_count, -(double)s->attribute_count};
    if (c->sum_u64(c->ctx, &total, 1, err) || c->min_f64(c->ctx, attrs, 2, err))
        return LC_ERR_INTERNAL;
    if (total == 0)
        return lc_err(err, LC_ERR_INVALID, "%s: no process read a vertex", s->name);
    if (total > LC_MAX_VERTICES)
        return lc_err(err, LC_ERR_LIMIT, "%s: %llu vertices over all processes exceed the limit of %u", s->name,
                      (unsigned long long)total, LC_MAX_VERTICES);
    if (attrs[0] != -attrs[1])
        return lc_err(err, LC_ERR_INVALID, "%s: the processes read different attributes (%g to %g of them)", s->name,
                      attrs[0], -attrs[1]);
    compute_bounds(s); /* an empty part: +inf .. -inf, which the minimum ignores */
    double b[6];
    for (int k = 0; k < 3; k++)
        b[k] = s->bounds[k], b[3 + k] = -s->bounds[3 + k];
    if (c->min_f64(c->ctx, b, 6, err))
        return LC_ERR_INTERNAL;
    for (int k = 0; k < 3; k++)
        s->bounds[k] = b[k], s->bounds[3 + k] = -b[3 + k];

    bool measured;
    int file_attributes = s->attribute_count;
    if (mark_categories(s, c, total, &measured, err)) /* agreed by every part */
        return LC_ERR_INTERNAL;
    if (s->type == LC_PRIM_LINES) {
        rc = lc_scene_derive_lines(s, err); /* per line, with the whole's bounds */
        if (!rc)                            /* collective: the directions' grid is summed over the processes */
            rc = lc_scene_derive_line_measures(s, total, c, err);
        if (!rc && s->trajectory.geographic)
            rc = lc_scene_derive_trajectories(s, err); /* per line */
        int timed; /* per line; every part has the same attributes, so the same names */
        if (!rc)
            rc = lc_scene_derive_motion(s, &timed, err);
    } else if (!measured)                              /* the same on every part (agreed above) */
        rc = lc_scene_derive_points(s, total, c, err); /* collective */
    if ((rc = c->agree(c->ctx, rc, err)) != 0)
        return rc;
    for (int i = 0; i < s->attribute_count; i++)
        if (update_range(&s->attributes[i], s->vertex_count, c, err))
            return LC_ERR_INTERNAL;
    choose_defaults(s, file_attributes);
    double t1 = lc_now();
    double length = 0;
    rc = part_elements(s, desc, c, &length, err);
    if ((rc = c->agree(c->ctx, rc, err)) != 0)
        return rc;
    if (s->type == LC_PRIM_LINES && (rc = part_lod_steps(s, c, err)) != 0)
        return rc;
    uint64_t counts[2] = {lc_scene_primitive_count(s), s->line_count};
    if (c->sum_u64(c->ctx, counts, 2, err))
        return LC_ERR_INTERNAL;
    s->part_of = c->size;
    s->collective = c;
    s->whole_vertices = total, s->whole_primitives = counts[0], s->whole_lines = counts[1];
    s->whole_line_length = length;
    s->finalized = 1;
    double t2 = lc_now();
    LC_INFO("scene",
            "%s: part %d of %d: %s, %u of %llu vertices, %llu primitives, %d attributes, %u elements "
            "(derive %.0f ms, elements %.0f ms)",
            s->name, c->rank, c->size, lc_prim_type_name(s->type), s->vertex_count, (unsigned long long)total,
            (unsigned long long)lc_scene_primitive_count(s), s->attribute_count, s->elements.count, (t1 - t0) * 1e3,
            (t2 - t1) * 1e3);
    return LC_OK;
}
