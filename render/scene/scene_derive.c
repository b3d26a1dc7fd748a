/* Derived per-vertex data: line tangents, arc length, curvature and line length;
 * surface normals and cotangent-Laplacian mean curvature; point density. All O(n). */
#include "scene_derive.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double x, y, z;
} dvec;

static dvec vload(const float *p, uint32_t i)
{
    const float *q = p + 3 * (size_t)i;
    return (dvec){q[0], q[1], q[2]};
}
static dvec vsub(dvec a, dvec b) { return (dvec){a.x - b.x, a.y - b.y, a.z - b.z}; }
static dvec vadd(dvec a, dvec b) { return (dvec){a.x + b.x, a.y + b.y, a.z + b.z}; }
static dvec vscale(dvec a, double k) { return (dvec){a.x * k, a.y * k, a.z * k}; }
static double vdot(dvec a, dvec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double vlen(dvec a) { return sqrt(vdot(a, a)); }
static dvec vcross(dvec a, dvec b)
{
    return (dvec){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/* Unit vector, or zero when a is (numerically) zero. */
static dvec vnorm(dvec a)
{
    double l = vlen(a);
    return l > 0 ? vscale(a, 1.0 / l) : (dvec){0, 0, 0};
}

static double bounds_diagonal(const lc_scene *s)
{
    double dx = s->bounds[3] - s->bounds[0], dy = s->bounds[4] - s->bounds[1], dz = s->bounds[5] - s->bounds[2];
    double d = sqrt(dx * dx + dy * dy + dz * dz);
    return d > 0 ? d : 1.0;
}

static void store3(float *dst, uint32_t i, dvec v)
{
    float *q = dst + 3 * (size_t)i;
    q[0] = (float)v.x;
    q[1] = (float)v.y;
    q[2] = (float)v.z;
}

/* Adds (or replaces) a derived attribute; the scene owns values either way. */
static int add_owned(lc_scene *s, const char *name, float *values, lc_error *err)
{
    int rc = lc_scene_add_attribute(s, name, values, err);
    return rc < 0 ? rc : LC_OK;
}

/* One line [a, b). Runs of coincident vertices (closer than eps) act as one
 * vertex: they share tangent and curvature, so a repeated point neither
 * produces a zero tangent nor a division by a zero segment length. */
static void derive_line(const float *p, uint32_t a, uint32_t b, double eps, float *tangents, float *arc, float *curv,
                        float *len)
{
    arc[a] = 0.0f;
    double acc = 0.0;
    for (uint32_t i = a + 1; i < b; i++) {
        acc += vlen(vsub(vload(p, i), vload(p, i - 1)));
        arc[i] = (float)acc;
    }
    for (uint32_t i = a; i < b; i++)
        len[i] = (float)acc;

    uint32_t i = a;
    while (i < b) {
        dvec pi = vload(p, i);
        uint32_t j = i;
        while (j + 1 < b && vlen(vsub(vload(p, j + 1), pi)) <= eps)
            j++;
        int has_prev = i > a, has_next = j + 1 < b;
        dvec in = {0, 0, 0}, out = {0, 0, 0};
        double lin = 0, lout = 0;
        if (has_prev) {
            in = vsub(pi, vload(p, i - 1));
            lin = vlen(in);
            in = vnorm(in);
        }
        if (has_next) {
            out = vsub(vload(p, j + 1), pi);
            lout = vlen(out);
            out = vnorm(out);
        }
        dvec t;
        double k = 0.0;
        if (has_prev && has_next) {
            /* central difference p[i+1] - p[i-1], i.e. the length-weighted mean
             * of both directions; a full reversal falls back to the outgoing one */
            t = vnorm(vadd(vscale(in, lin), vscale(out, lout)));
            if (vlen(t) < 0.5)
                t = vnorm(vadd(in, out));
            if (vlen(t) < 0.5)
                t = out;
            double angle = atan2(vlen(vcross(in, out)), vdot(in, out));
            double mean_len = 0.5 * (lin + lout);
            k = mean_len > 0 ? angle / mean_len : 0.0;
        } else if (has_next) {
            t = out;
        } else if (has_prev) {
            t = in;
        } else {
            /* a single point (or all coincident): any unit vector keeps the
             * ribbon shader's normalize() finite */
            t = (dvec){1, 0, 0};
        }
        if (vlen(t) < 0.5)
            t = (dvec){1, 0, 0};
        for (uint32_t v = i; v <= j; v++) {
            store3(tangents, v, t);
            curv[v] = (float)k;
        }
        i = j + 1;
    }
}

int lc_scene_derive_lines(lc_scene *s, lc_error *err)
{
    uint32_t n = s->vertex_count;
    s->tangents = malloc((size_t)n * 3 * sizeof(float));
    float *arc = calloc(n, sizeof(float));
    float *curv = calloc(n, sizeof(float));
    float *len = calloc(n, sizeof(float));
    if (!s->tangents || !arc || !curv || !len) {
        free(arc);
        free(curv);
        free(len);
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate line attributes", s->name);
    }
    /* vertices outside every line are never drawn; give them valid values */
    for (uint32_t i = 0; i < n; i++)
        store3(s->tangents, i, (dvec){1, 0, 0});
    /* a millionth of the dataset size: below float noise of RK4 steps that stall */
    double eps = 1e-6 * bounds_diagonal(s);
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t a = s->line_offsets[l], b = s->line_offsets[l + 1];
        if (b > a)
            derive_line(s->positions, a, b, eps, s->tangents, arc, curv, len);
    }
    int rc = add_owned(s, "arc_length", arc, err);
    if (rc) {
        free(curv);
        free(len);
        return rc;
    }
    rc = add_owned(s, "curvature", curv, err);
    if (rc) {
        free(len);
        return rc;
    }
    return add_owned(s, "line_length", len, err);
}

/* Area-weighted normals and |H| from the cotangent Laplacian with Meyer et al.'s
 * mixed Voronoi areas. |H| = |L·n| / (4A): projecting on the normal removes the
 * tangential part that one-sided fans produce at boundary vertices. Triangles
 * with (near) zero area carry no usable angles and are skipped. */
int lc_scene_derive_triangles(lc_scene *s, lc_error *err)
{
    uint32_t n = s->vertex_count;
    double *acc = calloc((size_t)n * 7, sizeof(double)); /* normal 3, laplacian 3, area 1 */
    float *mean = malloc((size_t)n * sizeof(float));
    s->normals = malloc((size_t)n * 3 * sizeof(float));
    if (!acc || !mean || !s->normals) {
        free(acc);
        free(mean);
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate normals", s->name);
    }
    const float *P = s->positions;
    for (uint32_t t = 0; t < s->triangle_count; t++) {
        const uint32_t *tri = s->triangles + 3 * (size_t)t;
        dvec p[3] = {vload(P, tri[0]), vload(P, tri[1]), vload(P, tri[2])};
        dvec c = vcross(vsub(p[1], p[0]), vsub(p[2], p[0]));
        for (int k = 0; k < 3; k++) {
            double *a = acc + 7 * (size_t)tri[k];
            a[0] += c.x;
            a[1] += c.y;
            a[2] += c.z;
        }
        double area2 = vlen(c);
        double l2[3]; /* squared length of the edge opposite corner k */
        double maxl2 = 0;
        for (int k = 0; k < 3; k++) {
            dvec e = vsub(p[(k + 2) % 3], p[(k + 1) % 3]);
            l2[k] = vdot(e, e);
            if (l2[k] > maxl2)
                maxl2 = l2[k];
        }
        if (!(area2 > 1e-12 * maxl2) || tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
            continue;
        double cot[3];
        for (int k = 0; k < 3; k++) {
            dvec u = vsub(p[(k + 1) % 3], p[k]), v = vsub(p[(k + 2) % 3], p[k]);
            cot[k] = vdot(u, v) / area2;
        }
        double area = 0.5 * area2;
        for (int k = 0; k < 3; k++) {
            int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
            /* edge (k,k1) is opposite k2, edge (k,k2) opposite k1 */
            dvec lap = vadd(vscale(vsub(p[k], p[k1]), cot[k2]), vscale(vsub(p[k], p[k2]), cot[k1]));
            double mixed;
            if (cot[0] < 0 || cot[1] < 0 || cot[2] < 0)
                mixed = cot[k] < 0 ? area / 2 : area / 4; /* obtuse: Voronoi area undefined */
            else
                mixed = (l2[k1] * cot[k1] + l2[k2] * cot[k2]) / 8; /* |p_k p_k2|² = l2[k1] */
            double *a = acc + 7 * (size_t)tri[k];
            a[3] += lap.x;
            a[4] += lap.y;
            a[5] += lap.z;
            a[6] += mixed;
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        const double *a = acc + 7 * (size_t)i;
        dvec nrm = vnorm((dvec){a[0], a[1], a[2]});
        double h = 0.0;
        if (vlen(nrm) < 0.5) {
            nrm = (dvec){0, 0, 1}; /* unreferenced or only degenerate triangles */
        } else if (a[6] > 0) {
            h = fabs(vdot((dvec){a[3], a[4], a[5]}, nrm)) / (4.0 * a[6]);
            if (!isfinite(h))
                h = 0.0;
        }
        store3(s->normals, i, nrm);
        mean[i] = (float)h;
    }
    free(acc);
    return add_owned(s, "mean_curvature", mean, err);
}

#define DENSITY_MAX_RES 128

int lc_scene_derive_points(lc_scene *s, uint64_t total, const lc_scene_collective *c, lc_error *err)
{
    const double *b = s->bounds;
    double extent[3], widest = 0;
    for (int k = 0; k < 3; k++) {
        extent[k] = b[3 + k] > b[k] ? b[3 + k] - b[k] : 0;
        widest = extent[k] > widest ? extent[k] : widest;
    }
    /* Cubic cells holding about 8 points on average over the axes the cloud
     * spans (a flat cloud: its plane), at least 4 and at most 128 across. */
    double volume = 1;
    int dims = 0, res[3];
    for (int k = 0; k < 3; k++)
        if (extent[k] > 1e-6 * widest)
            volume *= extent[k], dims++;
    double cell = dims ? pow(volume / ((double)total / 8.0 > 1 ? (double)total / 8.0 : 1), 1.0 / dims) : 1;
    if (widest > 0)
        cell = fmin(fmax(cell, widest / DENSITY_MAX_RES), widest / 4);
    for (int k = 0; k < 3; k++) {
        double r = ceil(extent[k] / cell);
        res[k] = r < 1 ? 1 : r > DENSITY_MAX_RES ? DENSITY_MAX_RES : (int)r;
    }
    size_t cells = (size_t)res[0] * res[1] * res[2];
    uint32_t n = s->vertex_count;
    uint64_t *count = calloc(cells, sizeof *count);
    uint32_t *where = malloc(((size_t)n + 1) * sizeof *where);
    float *density = malloc(((size_t)n + 1) * sizeof *density);
    int rc = count && where && density ? 0 : lc_err(err, LC_ERR_NOMEM, "%s: out of memory for point density", s->name);
    if (c) /* the grid sum below needs every process's grid */
        rc = c->agree(c->ctx, rc, err);
    for (uint32_t i = 0; !rc && i < n; i++) {
        size_t at = 0;
        for (int k = 2; k >= 0; k--) {
            int x = (int)((s->positions[3 * (size_t)i + k] - b[k]) / cell);
            at = at * (size_t)res[k] + (size_t)(x < 0 ? 0 : x >= res[k] ? res[k] - 1 : x);
        }
        where[i] = (uint32_t)at;
        count[at]++;
    }
    if (!rc && c && c->sum_u64(c->ctx, count, cells, err)) /* a part's grid joins the others' */
        rc = LC_ERR_INTERNAL;
    uint64_t *box = rc ? NULL : calloc(cells, sizeof *box);
    if (!rc && !box)
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for point density", s->name);
    uint64_t peak = 1;
    for (int z = 0; !rc && z < res[2]; z++)
        for (int y = 0; y < res[1]; y++)
            for (int x = 0; x < res[0]; x++) {
                uint64_t sum = 0;
                for (int dz = -1; dz <= 1; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int X = x + dx, Y = y + dy, Z = z + dz;
                            if (X >= 0 && Y >= 0 && Z >= 0 && X < res[0] && Y < res[1] && Z < res[2])
                                sum += count[((size_t)Z * res[1] + Y) * res[0] + X];
                        }
                box[((size_t)z * res[1] + y) * res[0] + x] = sum;
                peak = sum > peak ? sum : peak;
            }
    for (uint32_t i = 0; !rc && i < n; i++)
        density[i] = (float)((double)box[where[i]] / (double)peak);
    free(count);
    free(box);
    free(where);
    if (rc) {
        free(density);
        return rc;
    }
    return add_owned(s, "density", density, err);
}

/* ---- trajectories (docs/ALGORITHM.md "Derived trajectory attributes") */

#define KM_PER_DEGREE 111.195 /* mean Earth radius 6371 km */
#define KM_PER_LOG_HEIGHT 0.7 /* z = 10 ln(p0/p): one unit is a tenth of a 7 km scale height */
#define HPA_AT_ZERO 1013.25
#define WINDOW_HOURS 48.0

/* The metric step from vertex i to j: east, north, up in km (equirectangular
 * at the mean latitude: exact enough for the steps of a trajectory). */
static dvec metric_step(const float *p, uint32_t i, uint32_t j)
{
    dvec a = vload(p, i), b = vload(p, j);
    double coslat = cos(0.5 * (a.y + b.y) * M_PI / 180.0);
    return (dvec){(b.x - a.x) * KM_PER_DEGREE * coslat, (b.y - a.y) * KM_PER_DEGREE, (b.z - a.z) * KM_PER_LOG_HEIGHT};
}

static double degrees_between(dvec u, dvec v) { return atan2(vlen(vcross(u, v)), vdot(u, v)) * 180.0 / M_PI; }

/* One trajectory [a, b): values at every vertex into out[0..5] (pressure,
 * line change, 48 h change, speed, turning angle, ascent angle). */
static void derive_trajectory(const float *p, uint32_t a, uint32_t b, double step_hours, float *out[6])
{
    for (uint32_t i = a; i < b; i++)
        out[0][i] = (float)(HPA_AT_ZERO * exp(-(double)p[3 * (size_t)i + 2] / 10.0));
    double change = (double)out[0][b - 1] - out[0][a];
    uint32_t window = step_hours > 0 ? (uint32_t)floor(WINDOW_HOURS / step_hours + 1e-9) : 0;
    for (uint32_t i = a; i < b; i++) {
        out[1][i] = (float)change;
        if (out[2]) {
            uint32_t j = b - 1 - i > window ? i + window : b - 1;
            out[2][i] = (float)((double)out[0][j] - out[0][i]);
        }
        int has_in = i > a, has_out = i + 1 < b;
        dvec in = has_in ? metric_step(p, i - 1, i) : (dvec){0, 0, 0};
        dvec on = has_out ? metric_step(p, i, i + 1) : (dvec){0, 0, 0};
        /* speed: the mean length of the segments that meet here, per time step */
        double len = has_in && has_out ? 0.5 * (vlen(in) + vlen(on)) : vlen(has_in ? in : on);
        out[3][i] = (float)(step_hours > 0 ? len / step_hours : len);
        out[4][i] = has_in && has_out && vlen(in) > 0 && vlen(on) > 0 ? (float)degrees_between(in, on) : 0.0f;
        /* ascent: the angle of the outgoing segment (the last vertex: the incoming) over the ground */
        dvec d = has_out ? on : in;
        out[5][i] = (float)(atan2(d.z, sqrt(d.x * d.x + d.y * d.y)) * 180.0 / M_PI);
    }
}

int lc_scene_derive_trajectories(lc_scene *s, lc_error *err)
{
    static const char *const names[6] = {"pressure", "pressure_change", "pressure_change_48h",
                                         "speed",    "turning_angle",   "ascent_angle"};
    double step = s->trajectory.step_hours;
    uint32_t n = s->vertex_count;
    float *out[6];
    int ok = 1;
    for (int k = 0; k < 6; k++) {
        out[k] = k == 2 && !(step > 0) ? NULL : calloc(n ? n : 1, sizeof(float));
        ok &= out[k] != NULL || (k == 2 && !(step > 0));
    }
    if (!ok) {
        for (int k = 0; k < 6; k++)
            free(out[k]);
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate trajectory attributes", s->name);
    }
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t a = s->line_offsets[l], b = s->line_offsets[l + 1];
        if (b > a)
            derive_trajectory(s->positions, a, b, step, out);
    }
    int rc = 0;
    for (int k = 0; k < 6; k++) {
        const char *name = k == 3 && !(step > 0) ? "segment_length" : names[k];
        if (!out[k])
            continue;
        if (rc) {
            free(out[k]);
            continue;
        }
        if (s->attribute_count >= LC_MAX_ATTRIBUTES && lc_scene_find_attribute(s, name) < 0) {
            LC_WARN("scene", "%s: no room for the derived attribute %s", s->name, name);
            free(out[k]);
            continue;
        }
        rc = add_owned(s, name, out[k], err);
    }
    return rc;
}
