/* Built-in demo datasets, deterministic from a seed (own PRNG, never rand()):
 * tornado and ABC-flow streamlines, a clustered point cloud and a pair of nested
 * surfaces (a trefoil-knot tube inside a bumpy ellipsoid). */
#include "demo.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "field_demo.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Caps on desc->count, so a request cannot ask for tens of gigabytes. */
#define MAX_DEMO_LINES 100000u /* ~52 M tornado vertices */
#define MAX_DEMO_POINTS 100000000u
#define MAX_DEMO_SURFACE_RES 8192u

static const char *const demo_names[] = {"tornado", "abc", "points", "surface", NULL};

const char *const *lc_demo_names(void) { return demo_names; }

const char *lc_demo_description(const char *name)
{
    if (!name)
        return NULL;
    if (strcmp(name, "tornado") == 0)
        return "Crawfis tornado: RK4 streamlines in the unit cube (500 by default), importance = line curvature";
    if (strcmp(name, "abc") == 0)
        return "ABC flow (A=sqrt3, B=sqrt2, C=1): RK4 streamlines on [0,2pi]^3 (400 by default), "
               "importance = line curvature";
    if (strcmp(name, "points") == 0)
        return "Clustered point cloud: anisotropic Gaussian clusters plus noise (200k points by "
               "default), importance = local density";
    if (strcmp(name, "borromean") == 0)
        return "Borromean rings: arcs along three interlocked ellipses (600 by default), a quarter close to the "
               "ring cores (importance ~1), the rest around them (importance ~0); not in the default list";
    if (strcmp(name, "surface") == 0)
        return "Nested surfaces: a trefoil-knot tube inside a bumpy ellipsoid (~77k vertices by "
               "default), importance = mean curvature";
    return NULL;
}

/* ---- PRNG: splitmix64, a full-period 64-bit generator that is plenty for
 * seeding demo geometry and identical on every platform. */
typedef struct {
    uint64_t s;
} rng;

static uint64_t rng_next(rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1). */
static double rng_uniform(rng *r) { return (double)(rng_next(r) >> 11) * 0x1.0p-53; }

/* Standard normal (Box-Muller; one value per call keeps the state simple). */
static double rng_normal(rng *r)
{
    double u = rng_uniform(r), v = rng_uniform(r);
    return sqrt(-2.0 * log(1.0 - u)) * cos(2.0 * M_PI * v);
}

/* ---- growable float arrays for the streamline builders */
typedef struct {
    float *v;
    size_t n, cap;
} fbuf;

static int fbuf_push(fbuf *b, float x)
{
    if (b->n == b->cap) {
        size_t ncap = b->cap ? b->cap * 2 : 4096;
        float *grown = realloc(b->v, ncap * sizeof *grown);
        if (!grown)
            return -1;
        b->v = grown;
        b->cap = ncap;
    }
    b->v[b->n++] = x;
    return 0;
}

/* ---- vector fields */
typedef void (*field_fn)(const double p[3], double v[3]);

/* The flows are render/field's (field_demo.h), at t = 0. */
static void tornado_field(const double p[3], double v[3]) { lc_field_tornado(p, 0.0, v); }

static void abc_field(const double p[3], double v[3]) { lc_field_abc(p, 0.0, v); }

typedef struct {
    field_fn field;
    double lo, hi;    /* cubic domain [lo, hi]^3 */
    double step;      /* arc length per RK4 step */
    int max_steps;    /* per direction */
    double min_speed; /* below this the line ends (critical point) */
} stream_spec;

/* Unit direction of the field times dir, or 0 when the flow stalls; RK4 on
 * the normalized field gives vertices at equal arc length, which keeps the
 * derived curvature free of step-size artefacts. */
static int direction(const stream_spec *sp, const double p[3], double dir, double out[3])
{
    double v[3];
    sp->field(p, v);
    double s = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(s > sp->min_speed))
        return -1;
    for (int k = 0; k < 3; k++)
        out[k] = dir * v[k] / s;
    return 0;
}

static int inside(const stream_spec *sp, const double p[3])
{
    for (int k = 0; k < 3; k++)
        if (!(p[k] >= sp->lo && p[k] <= sp->hi))
            return 0;
    return 1;
}

/* Integrates from seed in direction dir (+1/-1), writing up to max_steps
 * points after the seed into pts (3 per point). Returns the count. */
static int trace(const stream_spec *sp, const double seed[3], double dir, double *pts)
{
    double p[3] = {seed[0], seed[1], seed[2]}, h = sp->step;
    int n = 0;
    for (int i = 0; i < sp->max_steps; i++) {
        double k1[3], k2[3], k3[3], k4[3], q[3];
        if (direction(sp, p, dir, k1))
            break;
        for (int k = 0; k < 3; k++)
            q[k] = p[k] + 0.5 * h * k1[k];
        if (direction(sp, q, dir, k2))
            break;
        for (int k = 0; k < 3; k++)
            q[k] = p[k] + 0.5 * h * k2[k];
        if (direction(sp, q, dir, k3))
            break;
        for (int k = 0; k < 3; k++)
            q[k] = p[k] + h * k3[k];
        if (direction(sp, q, dir, k4))
            break;
        for (int k = 0; k < 3; k++)
            q[k] = p[k] + h / 6.0 * (k1[k] + 2 * k2[k] + 2 * k3[k] + k4[k]);
        if (!inside(sp, q))
            break;
        memcpy(p, q, sizeof p);
        memcpy(pts + 3 * n, p, sizeof p);
        n++;
    }
    return n;
}

/* Streamlines from random seeds, traced both ways. Every line has at least
 * two vertices; seeds in stagnant regions are redrawn a bounded number of
 * times. Adds "velocity" (speed magnitude) and sets line offsets. */
static int make_streamlines(lc_scene *s, const stream_spec *sp, uint32_t lines, rng *r, lc_error *err)
{
    fbuf pos = {0}, speed = {0};
    uint32_t *offsets = malloc(((size_t)lines + 1) * sizeof(uint32_t));
    double *back = malloc((size_t)sp->max_steps * 3 * sizeof(double));
    double *fwd = malloc((size_t)sp->max_steps * 3 * sizeof(double));
    int rc = LC_ERR_NOMEM;
    if (!offsets || !back || !fwd)
        goto fail;
    offsets[0] = 0;
    uint32_t made = 0;
    uint64_t attempts = 0, max_attempts = 50ull * lines + 100;
    while (made < lines && attempts++ < max_attempts) {
        double seed[3];
        for (int k = 0; k < 3; k++)
            seed[k] = sp->lo + (sp->hi - sp->lo) * rng_uniform(r);
        double d[3];
        if (direction(sp, seed, 1.0, d))
            continue;
        int nb = trace(sp, seed, -1.0, back), nf = trace(sp, seed, 1.0, fwd);
        if (nb + nf < 4) /* a stub at the domain edge or a critical point */
            continue;
        for (int i = nb - 1; i >= -1 - nf; i--) {
            /* back[nb-1] .. back[0], seed, fwd[0] .. fwd[nf-1] */
            const double *p = i >= 0 ? back + 3 * i : i == -1 ? seed : fwd + 3 * (-2 - i);
            double v[3];
            sp->field(p, v);
            for (int k = 0; k < 3; k++)
                if (fbuf_push(&pos, (float)p[k]))
                    goto fail;
            if (fbuf_push(&speed, (float)sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])))
                goto fail;
        }
        if (speed.n > LC_MAX_VERTICES) {
            rc = lc_err(err, LC_ERR_LIMIT, "%s: too many vertices", s->name);
            goto fail_msg;
        }
        if ((made & 63) == 0 && lc_cancelled()) { /* a signal during start-up */
            rc = lc_err_cancelled(err, s->name);
            goto fail_msg;
        }
        offsets[++made] = (uint32_t)speed.n;
    }
    if (made == 0) {
        rc = lc_err(err, LC_ERR_INTERNAL, "%s: no streamline could be traced", s->name);
        goto fail_msg;
    }
    rc = lc_scene_alloc_vertices(s, (uint32_t)speed.n, 0, err);
    if (rc)
        goto fail_msg;
    memcpy(s->positions, pos.v, pos.n * sizeof(float));
    s->line_count = made;
    s->line_offsets = offsets;
    offsets = NULL;
    rc = lc_scene_add_attribute(s, "velocity", speed.v, err);
    speed.v = NULL; /* owned by the scene now, even on failure */
    free(pos.v);
    free(back);
    free(fwd);
    return rc < 0 ? rc : LC_OK;
fail:
    rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory tracing streamlines", s->name);
fail_msg:
    free(pos.v);
    free(speed.v);
    free(offsets);
    free(back);
    free(fwd);
    return rc;
}

static int gen_tornado(lc_scene *s, uint64_t count, rng *r, lc_error *err)
{
    /* step 0.003 of the unit cube, 400 steps each way: lines up to 2.4 long */
    stream_spec sp = {tornado_field, 0.0, 1.0, 0.003, 400, 1e-6};
    int rc = make_streamlines(s, &sp, count ? (uint32_t)count : 500, r, err);
    if (rc)
        return rc;
    snprintf(s->default_importance, sizeof s->default_importance, "curvature");
    snprintf(s->default_color, sizeof s->default_color, "importance");
    return LC_OK;
}

static int gen_abc(lc_scene *s, uint64_t count, rng *r, lc_error *err)
{
    stream_spec sp = {abc_field, 0.0, 2.0 * M_PI, 0.02, 400, 1e-6};
    int rc = make_streamlines(s, &sp, count ? (uint32_t)count : 400, r, err);
    if (rc)
        return rc;
    snprintf(s->default_importance, sizeof s->default_importance, "curvature");
    snprintf(s->default_color, sizeof s->default_color, "importance");
    return LC_OK;
}

/* ---- point cloud */

#define CLUSTERS 8

/* Density from a uniform grid: points per cell summed over the 3x3x3
 * neighbourhood (smoother than one cell), divided by the maximum. O(n). */
static int point_density(const float *pos, uint32_t n, float *density)
{
    double target = cbrt((double)n / 8.0); /* about 8 points per cell on average */
    int res = target < 4 ? 4 : target > 256 ? 256 : (int)target;
    size_t cells = (size_t)res * res * res;
    uint32_t *count = calloc(cells, sizeof *count);
    uint32_t *box = calloc(cells, sizeof *box);
    uint32_t *cell = malloc((size_t)n * sizeof *cell);
    if (!count || !box || !cell) {
        free(count);
        free(box);
        free(cell);
        return -1;
    }
    for (uint32_t i = 0; i < n; i++) {
        int c[3];
        for (int k = 0; k < 3; k++) {
            int x = (int)(pos[3 * (size_t)i + k] * res);
            c[k] = x < 0 ? 0 : x >= res ? res - 1 : x;
        }
        cell[i] = (uint32_t)(((size_t)c[2] * res + c[1]) * res + c[0]);
        count[cell[i]]++;
    }
    uint32_t peak = 1;
    for (int z = 0; z < res; z++)
        for (int y = 0; y < res; y++)
            for (int x = 0; x < res; x++) {
                uint32_t sum = 0;
                for (int dz = -1; dz <= 1; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int X = x + dx, Y = y + dy, Z = z + dz;
                            if (X >= 0 && Y >= 0 && Z >= 0 && X < res && Y < res && Z < res)
                                sum += count[((size_t)Z * res + Y) * res + X];
                        }
                box[((size_t)z * res + y) * res + x] = sum;
                if (sum > peak)
                    peak = sum;
            }
    for (uint32_t i = 0; i < n; i++)
        density[i] = (float)box[cell[i]] / (float)peak;
    free(count);
    free(box);
    free(cell);
    return 0;
}

/* Anisotropic Gaussian clusters (random orientation, axis scales 0.01-0.12)
 * plus 10% uniform background, all inside [0,1]^3 (samples outside are
 * redrawn). Attributes: "density" (default importance) and "cluster"
 * (0 = background, 1..8). */
static int gen_points(lc_scene *s, uint64_t count, rng *r, lc_error *err)
{
    uint32_t n = count ? (uint32_t)count : 200000;
    int rc = lc_scene_alloc_vertices(s, n, 0, err);
    if (rc)
        return rc;
    float *cluster = malloc((size_t)n * sizeof(float));
    float *density = malloc((size_t)n * sizeof(float));
    if (!cluster || !density) {
        free(cluster);
        free(density);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", s->name);
    }
    double centre[CLUSTERS][3], axes[CLUSTERS][3][3], sigma[CLUSTERS][3], weight[CLUSTERS];
    double wsum = 0;
    for (int c = 0; c < CLUSTERS; c++) {
        for (int k = 0; k < 3; k++) {
            centre[c][k] = 0.2 + 0.6 * rng_uniform(r);
            sigma[c][k] = 0.01 + 0.11 * rng_uniform(r);
        }
        /* random orthonormal frame by Gram-Schmidt on Gaussian vectors */
        for (int a = 0; a < 3; a++) {
            double v[3];
            for (;;) {
                for (int k = 0; k < 3; k++)
                    v[k] = rng_normal(r);
                for (int b = 0; b < a; b++) {
                    double d = v[0] * axes[c][b][0] + v[1] * axes[c][b][1] + v[2] * axes[c][b][2];
                    for (int k = 0; k < 3; k++)
                        v[k] -= d * axes[c][b][k];
                }
                double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                if (l > 1e-3) {
                    for (int k = 0; k < 3; k++)
                        axes[c][a][k] = v[k] / l;
                    break;
                }
            }
        }
        weight[c] = 0.5 + rng_uniform(r);
        wsum += weight[c];
    }
    float *P = s->positions;
    for (uint32_t i = 0; i < n; i++) {
        double p[3];
        int id = 0;
        if (rng_uniform(r) < 0.1) {
            for (int k = 0; k < 3; k++)
                p[k] = rng_uniform(r);
        } else {
            double pick = rng_uniform(r) * wsum;
            int c = 0;
            while (c < CLUSTERS - 1 && pick >= weight[c])
                pick -= weight[c++];
            id = c + 1;
            do {
                double g[3] = {rng_normal(r) * sigma[c][0], rng_normal(r) * sigma[c][1], rng_normal(r) * sigma[c][2]};
                for (int k = 0; k < 3; k++)
                    p[k] = centre[c][k] + g[0] * axes[c][0][k] + g[1] * axes[c][1][k] + g[2] * axes[c][2][k];
            } while (!(p[0] >= 0 && p[0] <= 1 && p[1] >= 0 && p[1] <= 1 && p[2] >= 0 && p[2] <= 1));
        }
        for (int k = 0; k < 3; k++)
            P[3 * (size_t)i + k] = (float)p[k];
        cluster[i] = (float)id;
    }
    if (point_density(P, n, density)) {
        free(cluster);
        free(density);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", s->name);
    }
    rc = lc_scene_add_attribute(s, "density", density, err);
    if (rc < 0) {
        free(cluster);
        return rc;
    }
    rc = lc_scene_add_attribute(s, "cluster", cluster, err);
    if (rc < 0)
        return rc;
    snprintf(s->default_importance, sizeof s->default_importance, "density");
    snprintf(s->default_color, sizeof s->default_color, "importance");
    return LC_OK;
}

/* ---- nested surfaces */

/* Trefoil (2,3) torus knot centre line and its Frenet frame. The Frenet frame
 * of a closed curve is periodic (a parallel-transport frame would twist at the
 * seam), and this knot's curvature never vanishes. */
static void knot_point(double t, double c[3])
{
    c[0] = (2.0 + cos(3 * t)) * cos(2 * t);
    c[1] = (2.0 + cos(3 * t)) * sin(2 * t);
    c[2] = sin(3 * t);
}

static void knot_frame(double t, double c[3], double nrm[3], double bin[3])
{
    const double h = 1e-4;
    double a[3], b[3], d1[3], d2[3];
    knot_point(t - h, a);
    knot_point(t, c);
    knot_point(t + h, b);
    for (int k = 0; k < 3; k++) {
        d1[k] = (b[k] - a[k]) / (2 * h);
        d2[k] = (b[k] - 2 * c[k] + a[k]) / (h * h);
    }
    double l = sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]);
    double T[3] = {d1[0] / l, d1[1] / l, d1[2] / l};
    double dd = d2[0] * T[0] + d2[1] * T[1] + d2[2] * T[2];
    for (int k = 0; k < 3; k++)
        nrm[k] = d2[k] - dd * T[k];
    l = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    for (int k = 0; k < 3; k++)
        nrm[k] /= l;
    bin[0] = T[1] * nrm[2] - T[2] * nrm[1];
    bin[1] = T[2] * nrm[0] - T[0] * nrm[2];
    bin[2] = T[0] * nrm[1] - T[1] * nrm[0];
}

/* Quads of a (rows x cols) vertex grid starting at base, wrapping in columns
 * and, if wrap_rows, in rows; two triangles each, wound by `flip`. */
static uint32_t grid_triangles(uint32_t *tri, uint32_t base, uint32_t rows, uint32_t cols, int wrap_rows, int flip)
{
    uint32_t k = 0;
    uint32_t row_quads = wrap_rows ? rows : rows - 1;
    for (uint32_t i = 0; i < row_quads; i++)
        for (uint32_t j = 0; j < cols; j++) {
            uint32_t i1 = (i + 1) % rows, j1 = (j + 1) % cols;
            uint32_t a = base + i * cols + j, b = base + i * cols + j1;
            uint32_t c = base + i1 * cols + j, d = base + i1 * cols + j1;
            uint32_t q[6] = {a, c, d, a, d, b};
            if (flip) {
                q[1] = d, q[2] = c, q[4] = b, q[5] = d;
            }
            memcpy(tri + 3 * (size_t)k, q, sizeof q);
            k += 2;
        }
    return k;
}

/* res (default 160) sets the resolution: knot tube 4res x res/4, ellipsoid
 * res x 2res plus two poles. */
static int gen_surface(lc_scene *s, uint64_t count, lc_error *err)
{
    uint32_t res = count ? (uint32_t)count : 160;
    if (res < 16)
        res = 16;
    uint32_t ku = 4 * res, kv = res / 4; /* knot: along x around */
    uint32_t stacks = res, slices = 2 * res;
    uint32_t knot_verts = ku * kv;
    uint32_t ell_base = knot_verts;
    uint32_t ell_verts = 2 + (stacks - 1) * slices;
    uint32_t n = knot_verts + ell_verts;
    uint32_t tris = 2 * ku * kv + 2 * slices * (stacks - 1);
    int rc = lc_scene_alloc_vertices(s, n, 0, err);
    if (rc)
        return rc;
    s->triangles = malloc((size_t)tris * 3 * sizeof(uint32_t));
    float *part = malloc((size_t)n * sizeof(float));
    if (!s->triangles || !part) {
        free(part);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", s->name);
    }
    float *P = s->positions;
    /* knot tube, radius 0.3 swelling to 0.45 three times along the knot */
    for (uint32_t i = 0; i < ku; i++) {
        double t = 2 * M_PI * i / ku, c[3], nr[3], bn[3];
        knot_frame(t, c, nr, bn);
        double rad = 0.3 + 0.15 * pow(sin(1.5 * t), 2);
        for (uint32_t j = 0; j < kv; j++) {
            double a = 2 * M_PI * j / kv;
            float *q = P + 3 * ((size_t)i * kv + j);
            for (int k = 0; k < 3; k++)
                q[k] = (float)(c[k] + rad * (cos(a) * nr[k] + sin(a) * bn[k]));
            part[i * kv + j] = 1.0f;
        }
    }
    /* bumpy ellipsoid around it: semi-axes 4.2, 4.2, 2.2, radial ripples 5% */
    float *pole = P + 3 * (size_t)ell_base;
    pole[0] = 0, pole[1] = 0, pole[2] = 2.2f;
    pole[3] = 0, pole[4] = 0, pole[5] = -2.2f;
    for (uint32_t i = 1; i < stacks; i++)
        for (uint32_t j = 0; j < slices; j++) {
            double th = M_PI * i / stacks, ph = 2 * M_PI * j / slices;
            double bump = 1.0 + 0.05 * sin(4 * th) * sin(4 * th) * cos(6 * ph);
            float *q = P + 3 * ((size_t)ell_base + 2 + (i - 1) * slices + j);
            q[0] = (float)(4.2 * bump * sin(th) * cos(ph));
            q[1] = (float)(4.2 * bump * sin(th) * sin(ph));
            q[2] = (float)(2.2 * bump * cos(th));
        }
    for (uint32_t v = ell_base; v < n; v++)
        part[v] = 0.0f;
    uint32_t *T = s->triangles, k = 0;
    /* knot rows run along the curve, columns around it; outward with flip */
    k += grid_triangles(T, 0, ku, kv, 1, 1);
    /* ellipsoid: pole fans and the band between them, wound outward */
    uint32_t top = ell_base, bottom = ell_base + 1, ring = ell_base + 2;
    for (uint32_t j = 0; j < slices; j++) {
        uint32_t j1 = (j + 1) % slices;
        uint32_t *q = T + 3 * (size_t)k;
        q[0] = top, q[1] = ring + j, q[2] = ring + j1;
        q[3] = bottom, q[4] = ring + (stacks - 2) * slices + j1, q[5] = ring + (stacks - 2) * slices + j;
        k += 2;
    }
    k += grid_triangles(T + 3 * (size_t)k, ring, stacks - 1, slices, 0, 0);
    s->triangle_count = k;
    rc = lc_scene_add_attribute(s, "part", part, err);
    if (rc < 0)
        return rc;
    snprintf(s->default_importance, sizeof s->default_importance, "mean_curvature");
    snprintf(s->default_color, sizeof s->default_color, "importance");
    return LC_OK;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* Per-vertex curvature has a heavy tail (tornado: median 4, max 90), so a
 * min/max mapping would leave almost every line near g = 0. The streamline
 * demos therefore rank whole lines: "line_curvature" is the arc-length
 * weighted mean curvature of each line divided by the 98th percentile over
 * lines and clamped to 1, constant along a line so opacity never flickers
 * along it. It becomes the default importance. Runs after finalize, which
 * derived "curvature" and "arc_length". */
static int add_line_curvature(lc_scene *s, lc_error *err)
{
    int ki = lc_scene_find_attribute(s, "curvature"), ai = lc_scene_find_attribute(s, "arc_length");
    if (ki < 0 || ai < 0)
        return lc_err(err, LC_ERR_INTERNAL, "%s: curvature not derived", s->name);
    const float *k = s->attributes[ki].values, *arc = s->attributes[ai].values;
    float *mean = malloc((size_t)s->line_count * sizeof(float));
    float *sorted = malloc((size_t)s->line_count * sizeof(float));
    float *values = malloc((size_t)s->vertex_count * sizeof(float));
    if (!mean || !sorted || !values) {
        free(mean);
        free(sorted);
        free(values);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", s->name);
    }
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t a = s->line_offsets[l], b = s->line_offsets[l + 1];
        double sum = 0, len = b > a ? arc[b - 1] : 0;
        for (uint32_t i = a + 1; i < b; i++) /* trapezoid rule over the segments */
            sum += 0.5 * (k[i - 1] + k[i]) * (arc[i] - arc[i - 1]);
        mean[l] = len > 0 ? (float)(sum / len) : 0.0f;
        sorted[l] = mean[l];
    }
    qsort(sorted, s->line_count, sizeof(float), cmp_float);
    float ref = sorted[(size_t)(0.98 * (s->line_count - 1))];
    for (uint32_t l = 0; l < s->line_count; l++) {
        float g = ref > 0 ? mean[l] / ref : 0.0f;
        mean[l] = g > 1.0f ? 1.0f : g;
    }
    for (uint32_t v = 0; v < s->vertex_count; v++)
        values[v] = 0.0f;
    for (uint32_t l = 0; l < s->line_count; l++)
        for (uint32_t i = s->line_offsets[l]; i < s->line_offsets[l + 1]; i++)
            values[i] = mean[l];
    free(mean);
    free(sorted);
    int idx = lc_scene_add_attribute(s, "line_curvature", values, err);
    if (idx < 0)
        return idx;
    /* finalize has run, so the range is ours to fill */
    lc_attribute_update_range(&s->attributes[idx], s->vertex_count);
    snprintf(s->default_importance, sizeof s->default_importance, "line_curvature");
    return LC_OK;
}

/* ---- Borromean rings (the clustering case of DLS Fig. 2) */

/* Ring i at angle t: three mutually perpendicular ellipses (semi-axes 1 and
 * 2), the classic Borromean arrangement; tangent in tan. */
static void ring_point(int ring, double t, double p[3], double tan[3])
{
    double u = cos(t), v = 2.0 * sin(t), du = -sin(t), dv = 2.0 * cos(t);
    double q[3] = {u, v, 0}, dq[3] = {du, dv, 0};
    for (int k = 0; k < 3; k++) {
        p[(k + ring) % 3] = q[k];
        tan[(k + ring) % 3] = dq[k];
    }
}

/* Arcs of a third of a turn along the rings, displaced within a tube: a
 * quarter of them by at most 0.02 (importance about 1), the others by 0.12 to
 * 0.35 (importance below 0.1). Spatially the two kinds intermingle; only the
 * importance coordinate of the clustering lift tells them apart. */
static int gen_borromean(lc_scene *s, uint64_t count, rng *r, lc_error *err)
{
    enum { STEPS = 48 };
    uint32_t lines = count ? (uint32_t)count : 600;
    int rc = lc_scene_alloc_vertices(s, lines * STEPS, 0, err);
    if (rc)
        return rc;
    float *g = malloc((size_t)lines * STEPS * sizeof *g), *which = malloc((size_t)lines * STEPS * sizeof *which);
    s->line_offsets = malloc(((size_t)lines + 1) * sizeof *s->line_offsets);
    if (!g || !which || !s->line_offsets) {
        free(g);
        free(which);
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", s->name);
    }
    s->line_count = lines;
    for (uint32_t i = 0; i <= lines; i++)
        s->line_offsets[i] = i * STEPS;
    for (uint32_t i = 0; i < lines; i++) {
        int ring = (int)(i % 3), core = (i / 3) % 4 == 0;
        double t0 = 2.0 * M_PI * rng_uniform(r), span = 2.0 * M_PI / 3.0;
        double radius = core ? 0.02 * rng_uniform(r) : 0.12 + 0.23 * rng_uniform(r);
        double phase = 2.0 * M_PI * rng_uniform(r);
        for (int j = 0; j < STEPS; j++) {
            double p[3], tan[3], n1[3], n2[3];
            ring_point(ring, t0 + span * j / (STEPS - 1), p, tan);
            /* A frame around the tangent: n1 = tangent x axis, n2 = tangent x n1. */
            double axis[3] = {0, 0, 0};
            axis[(ring + 2) % 3] = 1;
            n1[0] = tan[1] * axis[2] - tan[2] * axis[1];
            n1[1] = tan[2] * axis[0] - tan[0] * axis[2];
            n1[2] = tan[0] * axis[1] - tan[1] * axis[0];
            n2[0] = tan[1] * n1[2] - tan[2] * n1[1];
            n2[1] = tan[2] * n1[0] - tan[0] * n1[2];
            n2[2] = tan[0] * n1[1] - tan[1] * n1[0];
            double l1 = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
            double l2 = sqrt(n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]);
            uint32_t v = i * STEPS + (uint32_t)j;
            for (int k = 0; k < 3; k++)
                s->positions[3 * v + k] = (float)(p[k] + radius * (cos(phase) * n1[k] / l1 + sin(phase) * n2[k] / l2));
            g[v] = (float)exp(-(radius / 0.06) * (radius / 0.06));
            which[v] = (float)ring;
        }
    }
    rc = lc_scene_add_attribute(s, "ring_proximity", g, err);
    if (rc >= 0)
        rc = lc_scene_add_attribute(s, "ring", which, err);
    else
        free(which);
    if (rc < 0)
        return rc;
    snprintf(s->default_importance, sizeof s->default_importance, "ring_proximity");
    snprintf(s->default_color, sizeof s->default_color, "ring");
    return LC_OK;
}

static int parse_u64(const char *s, uint64_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno || end == s || (*end && *end != '&') || s[0] == '-')
        return -1;
    *out = v;
    return 0;
}

int lc_demo_create_spec(const char *spec, const lc_demo_desc *defaults, lc_scene **out, lc_error *err)
{
    *out = NULL;
    char name[64];
    const char *q = strchr(spec, '?');
    size_t n = q ? (size_t)(q - spec) : strlen(spec);
    if (n == 0 || n >= sizeof name)
        return lc_err(err, LC_ERR_INVALID, "demo:%.80s: expected demo:NAME", spec);
    memcpy(name, spec, n);
    name[n] = '\0';
    lc_demo_desc desc = defaults ? *defaults : (lc_demo_desc){0};
    for (const char *p = q; p && *p; p = strchr(p + 1, '&')) {
        const char *kv = p + 1;
        uint64_t v;
        if (strncmp(kv, "count=", 6) == 0 && parse_u64(kv + 6, &v) == 0)
            desc.count = v;
        else if (strncmp(kv, "seed=", 5) == 0 && parse_u64(kv + 5, &v) == 0)
            desc.seed = v;
        else
            return lc_err(err, LC_ERR_INVALID, "demo:%.80s: expected ?count=N&seed=S after the demo name", spec);
    }
    return lc_demo_create(name, &desc, out, err);
}

int lc_demo_create(const char *name, const lc_demo_desc *desc, lc_scene **out, lc_error *err)
{
    if (!out)
        return lc_err(err, LC_ERR_INVALID, "demo: no output scene");
    *out = NULL;
    if (!name || !lc_demo_description(name))
        return lc_err(err, LC_ERR_NOT_FOUND, "demo:%s: unknown demo (tornado, abc, points, surface, borromean)",
                      name ? name : "(null)");
    uint64_t seed = desc && desc->seed ? desc->seed : 1;
    uint64_t count = desc ? desc->count : 0;
    int is_lines = strcmp(name, "tornado") == 0 || strcmp(name, "abc") == 0 || strcmp(name, "borromean") == 0;
    uint64_t cap = is_lines ? MAX_DEMO_LINES : strcmp(name, "points") == 0 ? MAX_DEMO_POINTS : MAX_DEMO_SURFACE_RES;
    if (count > cap)
        return lc_err(err, LC_ERR_LIMIT, "demo:%s: count %llu exceeds the limit of %llu", name,
                      (unsigned long long)count, (unsigned long long)cap);
    char full[LC_NAME_LEN];
    snprintf(full, sizeof full, "demo:%s", name);
    lc_scene *s = lc_scene_create(full, strcmp(name, "points") == 0    ? LC_PRIM_POINTS
                                        : strcmp(name, "surface") == 0 ? LC_PRIM_TRIANGLES
                                                                       : LC_PRIM_LINES);
    if (!s)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", full);
    /* the seed is mixed once so that nearby seeds give unrelated streams */
    rng r = {seed * 0x9e3779b97f4a7c15ull ^ 0x5851f42d4c957f2dull};
    rng_next(&r);
    int rc;
    if (strcmp(name, "tornado") == 0)
        rc = gen_tornado(s, count, &r, err);
    else if (strcmp(name, "abc") == 0)
        rc = gen_abc(s, count, &r, err);
    else if (strcmp(name, "borromean") == 0)
        rc = gen_borromean(s, count, &r, err);
    else if (strcmp(name, "points") == 0)
        rc = gen_points(s, count, &r, err);
    else
        rc = gen_surface(s, count, err);
    if (!rc)
        rc = lc_scene_finalize(s, NULL, err);
    if (!rc && is_lines)
        rc = add_line_curvature(s, err);
    if (!rc && is_lines) {
        /* Streamlines read best from the side, with the z axis (the tornado's
         * core) up, slightly from above. */
        static const double dir_tornado[3] = {0, 1, -0.3}, dir_abc[3] = {-1, 0.6, -0.45}, up[3] = {0, 0, 1};
        static const double dir_rings[3] = {-1, -0.8, -0.6};
        s->has_view = 1;
        memcpy(s->view_direction,
               strcmp(name, "tornado") == 0 ? dir_tornado
               : strcmp(name, "abc") == 0   ? dir_abc
                                            : dir_rings,
               sizeof dir_tornado);
        memcpy(s->view_up, up, sizeof up);
    }
    if (rc) {
        lc_scene_destroy(s);
        return rc;
    }
    *out = s;
    return LC_OK;
}
