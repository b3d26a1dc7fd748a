/* Line clustering: resampling and 5-D lift, rMCPD, a pruned agglomerative
 * linkage with a dense top stage, and dendrogram cuts with representatives. */
#include "cluster.h"
#include "cluster_distance.h"
#include "cluster_internal.h"
#include "cluster_sample.h"
#include "lc_parallel.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define DEFAULT_NEIGHBOURS 96u
#define DEFAULT_TOP_CLUSTERS 2048u
#define DEFAULT_SAMPLE_LINES 10000u
/* Up to this many lines every pair is linked: the dense stage alone. */
#define DENSE_LINES 1200u
/* Threads of the pruned stage's sweep (at most the online processors). */
#define MAX_THREADS 8

/* ---- resampling (DLS §3.2: lines compared at a fixed number of points) */

/* k samples equally spaced in arc length along line [v0, v1): sample s lies
 * at t[s] between vertices at[s] and at[s] + 1 (at[s] + 1 = at[s] for a
 * one-vertex line). Returns the line's length. */
static double arc_samples(const float *pos, uint32_t v0, uint32_t v1, int k, uint32_t *at, float *t)
{
    double len = 0;
    for (uint32_t v = v0 + 1; v < v1; v++) {
        double dx = pos[3 * v] - pos[3 * v - 3], dy = pos[3 * v + 1] - pos[3 * v - 2],
               dz = pos[3 * v + 2] - pos[3 * v - 1];
        len += sqrt(dx * dx + dy * dy + dz * dz);
    }
    uint32_t seg = v0;
    double seg_start = 0;
    for (int s = 0; s < k; s++) {
        double target = len * s / (k - 1);
        at[s] = v0;
        t[s] = 0;
        while (v1 - v0 > 1) {
            uint32_t v = seg + 1;
            double dx = pos[3 * v] - pos[3 * seg], dy = pos[3 * v + 1] - pos[3 * seg + 1],
                   dz = pos[3 * v + 2] - pos[3 * seg + 2];
            double l = sqrt(dx * dx + dy * dy + dz * dz);
            if (seg_start + l >= target || seg + 2 == v1) {
                double u = l > 0 ? (target - seg_start) / l : 0;
                at[s] = seg;
                t[s] = (float)(u < 0 ? 0 : u > 1 ? 1 : u);
                break;
            }
            seg_start += l;
            seg++;
        }
    }
    return len;
}

static float lerp_at(const float *v, uint32_t at, float t, uint32_t end)
{
    return at + 1 < end ? v[at] * (1 - t) + v[at + 1] * t : v[at];
}

int lc_line_samples_create(const float *positions, const uint32_t *offsets, uint32_t lines, int k,
                           const float *const *attributes, int attribute_count, lc_line_samples **out, lc_error *err)
{
    *out = NULL;
    if (k == 0)
        k = LC_CLUSTER_DEFAULT_SAMPLES;
    if (!positions || !offsets || lines == 0)
        return lc_err(err, LC_ERR_INVALID, "clustering needs at least one line");
    if (k < 2 || k > LC_CLUSTER_MAX_SAMPLES)
        return lc_err(err, LC_ERR_INVALID, "clustering: samples %d outside [2, %d]", k, LC_CLUSTER_MAX_SAMPLES);
    if (lines > UINT32_MAX / 2)
        return lc_err(err, LC_ERR_LIMIT, "clustering: %u lines exceed the limit", lines);
    for (uint32_t i = 0; i < lines; i++)
        if (offsets[i + 1] <= offsets[i])
            return lc_err(err, LC_ERR_INVALID, "clustering: line %u has no vertices", i);
    lc_line_samples *ls = calloc(1, sizeof *ls);
    if (!ls)
        return lc_err(err, LC_ERR_NOMEM, "clustering: out of memory");
    ls->lines = lines;
    ls->k = k;
    ls->attributes = attribute_count;
    ls->xyz = malloc((size_t)lines * k * 3 * sizeof *ls->xyz);
    ls->values = malloc(((size_t)attribute_count * lines * k + 1) * sizeof *ls->values);
    ls->length = malloc((size_t)lines * sizeof *ls->length);
    if (!ls->xyz || !ls->values || !ls->length) {
        lc_line_samples_destroy(ls);
        return lc_err(err, LC_ERR_NOMEM, "clustering: out of memory resampling %u lines", lines);
    }
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (uint32_t v = offsets[0]; v < offsets[lines]; v++)
        for (int j = 0; j < 3; j++) {
            lo[j] = fmin(lo[j], positions[3 * v + j]);
            hi[j] = fmax(hi[j], positions[3 * v + j]);
        }
    double diag =
        sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double inv_diag = diag > 0 && isfinite(diag) ? 1.0 / diag : 1.0;
    uint32_t at[LC_CLUSTER_MAX_SAMPLES];
    float t[LC_CLUSTER_MAX_SAMPLES];
    for (uint32_t i = 0; i < lines; i++) {
        uint32_t end = offsets[i + 1];
        ls->length[i] = (float)arc_samples(positions, offsets[i], end, k, at, t);
        for (int s = 0; s < k; s++) {
            float *o = ls->xyz + ((size_t)i * k + s) * 3;
            uint32_t b = at[s] + 1 < end ? at[s] + 1 : at[s];
            for (int j = 0; j < 3; j++)
                o[j] = (float)((positions[3 * at[s] + j] * (1 - t[s]) + positions[3 * b + j] * t[s]) * inv_diag);
            for (int a = 0; a < attribute_count; a++)
                ls->values[((size_t)a * lines + i) * k + s] = lerp_at(attributes[a], at[s], t[s], end);
        }
    }
    *out = ls;
    return 0;
}

void lc_line_samples_destroy(lc_line_samples *ls)
{
    if (!ls)
        return;
    free(ls->xyz);
    free(ls->values);
    free(ls->length);
    free(ls);
}

size_t lc_line_samples_estimate(uint32_t lines, int k, int attributes)
{
    k = k ? k : LC_CLUSTER_DEFAULT_SAMPLES;
    return sizeof(lc_line_samples) + (size_t)lines * ((size_t)k * (3 + (size_t)attributes) + 1) * sizeof(float);
}

size_t lc_line_samples_bytes(const lc_line_samples *ls)
{
    return ls ? sizeof *ls + (size_t)ls->lines * ((size_t)ls->k * (3 + (size_t)ls->attributes) + 1) * sizeof(float) : 0;
}

_Static_assert(KERNEL_MAX_K == LC_CLUSTER_MAX_SAMPLES && KERNEL_FAST_K == LC_CLUSTER_DEFAULT_SAMPLES &&
                   KERNEL_DIM == DIM,
               "cluster_distance.c's sample counts");

/* DLS Eq. 3-4 on two lines as stored (AoS), through the kernel. */
float lc_cluster_rmcpd(const float *a, const float *b, int k)
{
    float sa[LC_CLUSTER_MAX_SAMPLES * DIM], sb[LC_CLUSTER_MAX_SAMPLES * DIM];
    lc_cluster_transpose(a, k, sa);
    lc_cluster_transpose(b, k, sb);
    return lc_cluster_rmcpd_soa(sa, sb, k);
}

/* ---- the linkage engine: clusters as nodes of a weighted graph whose missing
 * edges mean "at least r"; a min-heap of edges with lazy deletion (an edge
 * between two live nodes never changes: a merge creates a new node). The
 * adjacency lists delete lazily too: an entry for a merged node stays in its
 * neighbours' lists and is skipped (a linear removal per neighbour and merge
 * was most of the linkage's time at 10^4 lines). */

typedef struct edge {
    float d;
    uint32_t a, b;
} edge;

typedef struct adj {
    edge *e; /* e[i].a = neighbour, e[i].d = distance; b unused */
    uint32_t n, cap;
} adj;

typedef struct engine {
    lc_linkage linkage;
    uint32_t nodes, next; /* capacity 2m - 1; next id to create */
    float r;              /* missing edges are >= r; INFINITY in the dense stage */
    adj *adj;
    uint32_t *size;
    uint8_t *alive;
    edge *heap;
    size_t heap_n, heap_cap;
    float *mark_a, *mark_b; /* scratch per node: distance to a / b or NAN */
    uint32_t *touched;
    merge *merges;
    uint32_t merge_count;
} engine;

static int adj_push(adj *l, uint32_t to, float d)
{
    if (l->n == l->cap) {
        uint32_t cap = l->cap ? 2 * l->cap : 8;
        edge *e = realloc(l->e, cap * sizeof *e);
        if (!e)
            return -1;
        l->e = e;
        l->cap = cap;
    }
    l->e[l->n++] = (edge){d, to, 0};
    return 0;
}

static int heap_push(engine *g, edge x)
{
    if (g->heap_n == g->heap_cap) {
        size_t cap = g->heap_cap ? 2 * g->heap_cap : 1024;
        edge *h = realloc(g->heap, cap * sizeof *h);
        if (!h)
            return -1;
        g->heap = h;
        g->heap_cap = cap;
    }
    size_t i = g->heap_n++;
    /* Ties break on node ids so the order never depends on the heap's history. */
    while (i > 0) {
        size_t p = (i - 1) / 2;
        edge *q = &g->heap[p];
        if (q->d < x.d || (q->d == x.d && (q->a < x.a || (q->a == x.a && q->b <= x.b))))
            break;
        g->heap[i] = *q;
        i = p;
    }
    g->heap[i] = x;
    return 0;
}

static int edge_less(const edge *x, const edge *y)
{
    return x->d < y->d || (x->d == y->d && (x->a < y->a || (x->a == y->a && x->b < y->b)));
}

static edge heap_pop(engine *g)
{
    edge top = g->heap[0], x = g->heap[--g->heap_n];
    size_t i = 0, n = g->heap_n;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= n)
            break;
        if (c + 1 < n && edge_less(&g->heap[c + 1], &g->heap[c]))
            c++;
        if (!edge_less(&g->heap[c], &x))
            break;
        g->heap[i] = g->heap[c];
        i = c;
    }
    if (n)
        g->heap[i] = x;
    return top;
}

static int engine_init(engine *g, uint32_t m, lc_linkage linkage, merge *merges)
{
    memset(g, 0, sizeof *g);
    g->linkage = linkage;
    g->nodes = 2 * m - 1;
    g->next = m;
    g->r = INFINITY;
    g->merges = merges;
    g->adj = calloc(g->nodes, sizeof *g->adj);
    g->size = calloc(g->nodes, sizeof *g->size);
    g->alive = calloc(g->nodes, 1);
    g->mark_a = malloc(g->nodes * sizeof *g->mark_a);
    g->mark_b = malloc(g->nodes * sizeof *g->mark_b);
    g->touched = malloc(g->nodes * sizeof *g->touched);
    if (!g->adj || !g->size || !g->alive || !g->mark_a || !g->mark_b || !g->touched)
        return -1;
    for (uint32_t i = 0; i < g->nodes; i++) {
        g->mark_a[i] = g->mark_b[i] = NAN;
        g->size[i] = i < m ? 1 : 0;
        g->alive[i] = i < m;
    }
    return 0;
}

static void engine_free(engine *g)
{
    if (g->adj)
        for (uint32_t i = 0; i < g->nodes; i++)
            free(g->adj[i].e);
    free(g->adj);
    free(g->size);
    free(g->alive);
    free(g->heap);
    free(g->mark_a);
    free(g->mark_b);
    free(g->touched);
}

static int engine_edge(engine *g, uint32_t a, uint32_t b, float d)
{
    if (adj_push(&g->adj[a], b, d) || adj_push(&g->adj[b], a, d))
        return -1;
    return heap_push(g, (edge){d, a < b ? a : b, a < b ? b : a});
}

/* The Lance-Williams update of one neighbour x of the merged pair; NAN = no
 * edge (only possible when r is finite). */
static float linked(const engine *g, float da, float db, uint32_t na, uint32_t nb)
{
    int ha = !isnan(da), hb = !isnan(db);
    switch (g->linkage) {
    case LC_LINKAGE_SINGLE: return ha && hb ? fminf(da, db) : ha ? da : db;
    case LC_LINKAGE_AVERAGE: {
        /* A missing pair counts as r, the least it can be. */
        float va = ha ? da : g->r, vb = hb ? db : g->r;
        float v = (float)(((double)na * va + (double)nb * vb) / ((double)na + nb));
        return v < g->r ? v : NAN;
    }
    default: /* complete: any missing pair is >= r, so the clusters are too */ return ha && hb ? fmaxf(da, db) : NAN;
    }
}

static int engine_merge(engine *g, uint32_t a, uint32_t b, float height)
{
    uint32_t c = g->next++, nt = 0;
    g->merges[g->merge_count++] = (merge){a, b, height};
    g->alive[a] = g->alive[b] = 0;
    g->alive[c] = 1;
    g->size[c] = g->size[a] + g->size[b];
    for (uint32_t i = 0; i < g->adj[a].n; i++) {
        uint32_t x = g->adj[a].e[i].a;
        if (!g->alive[x])
            continue;
        if (isnan(g->mark_a[x]) && isnan(g->mark_b[x]))
            g->touched[nt++] = x;
        g->mark_a[x] = g->adj[a].e[i].d;
    }
    for (uint32_t i = 0; i < g->adj[b].n; i++) {
        uint32_t x = g->adj[b].e[i].a;
        if (!g->alive[x])
            continue;
        if (isnan(g->mark_a[x]) && isnan(g->mark_b[x]))
            g->touched[nt++] = x;
        g->mark_b[x] = g->adj[b].e[i].d;
    }
    int rc = 0;
    for (uint32_t i = 0; i < nt; i++) {
        uint32_t x = g->touched[i];
        float d = linked(g, g->mark_a[x], g->mark_b[x], g->size[a], g->size[b]);
        g->mark_a[x] = g->mark_b[x] = NAN;
        if (!rc && !isnan(d))
            rc = engine_edge(g, c, x, d);
    }
    free(g->adj[a].e);
    free(g->adj[b].e);
    g->adj[a] = g->adj[b] = (adj){0};
    return rc;
}

/* Merges along the heap until it is empty. */
static int engine_run(engine *g)
{
    while (g->heap_n) {
        edge e = heap_pop(g);
        if (g->alive[e.a] && g->alive[e.b] && engine_merge(g, e.a, e.b, e.d))
            return -1;
    }
    return 0;
}

/* ---- the build */

typedef struct box {
    float lo[DIM], hi[DIM];
} box;

static float box_distance(const box *p, const box *q)
{
    float s = 0;
    for (int j = 0; j < DIM; j++) {
        float gap = fmaxf(p->lo[j] - q->hi[j], q->lo[j] - p->hi[j]);
        if (gap > 0)
            s += gap * gap;
    }
    return sqrtf(s);
}

/* A line's box start on the sweep axis, sorted with its index (no global
 * state: builds may run in several threads at once). */
typedef struct sweep_key {
    float lo;
    uint32_t line;
} sweep_key;

static int cmp_sweep(const void *x, const void *y)
{
    const sweep_key *a = x, *b = y;
    return a->lo < b->lo ? -1 : a->lo > b->lo ? 1 : (a->line > b->line) - (a->line < b->line);
}

static int cmp_float(const void *x, const void *y)
{
    float a = *(const float *)x, b = *(const float *)y;
    return a < b ? -1 : a > b ? 1 : 0;
}

/* The pruning radius: the rMCPD lower bound below which a line has about
 * `neighbours` other lines, estimated from up to 128 evenly spread lines. */
static float prune_radius(const lc_dendrogram *dg, const float *soa, const box *bx, uint32_t neighbours)
{
    uint32_t m = dg->lines, s = m < 128 ? m : 128;
    size_t stride = (size_t)dg->k * DIM;
    float *d = malloc((size_t)m * sizeof *d);
    if (!d)
        return INFINITY;
    double sum = 0;
    for (uint32_t i = 0; i < s; i++) {
        uint32_t p = (uint32_t)((uint64_t)i * m / s);
        for (uint32_t j = 0; j < m; j++)
            d[j] = lc_cluster_lower_bound(soa + p * stride, bx[p].lo, bx[p].hi, soa + j * stride, bx[j].lo, bx[j].hi,
                                          dg->k, -INFINITY);
        uint32_t rank = neighbours < m ? neighbours : m - 1;
        /* nth_element would do; a sort of m floats is cheap next to the rMCPDs. */
        qsort(d, m, sizeof *d, cmp_float);
        sum += d[rank];
    }
    free(d);
    return (float)(sum / s);
}

/* Threads for a stage of `work` items: one per online core, at most MAX_THREADS, one for small work. */
static uint32_t thread_count(uint32_t work) { return work < 256 ? 1 : lc_parallel_cores(MAX_THREADS); }

/* The sparse stage: every pair whose boxes come closer than r is measured; an
 * rMCPD under r becomes an edge (a sweep along the widest spatial axis).
 * Threads take every T-th line of the sweep and collect their edges; the
 * merges do not depend on the order edges are added (the heap orders them
 * by distance, then node ids). */
typedef struct sweep {
    const lc_dendrogram *dg;
    const float *soa; /* the lines by coordinate (cluster_distance.c) */
    const box *bx;
    const sweep_key *order;
    float r;
    int axis;
    uint32_t first, step;
    edge *edges;
    size_t count, cap;
    uint64_t pairs;
    int failed;
} sweep;

static void sweep_run(void *arg)
{
    sweep *w = arg;
    const lc_dendrogram *dg = w->dg;
    const box *bx = w->bx;
    uint32_t m = dg->lines;
    size_t stride = (size_t)dg->k * DIM;
    float r = w->r;
    for (uint32_t oi = w->first; oi < m && !w->failed; oi += w->step) {
        uint32_t i = w->order[oi].line;
        for (uint32_t oj = oi + 1; oj < m; oj++) {
            uint32_t j = w->order[oj].line;
            if (bx[j].lo[w->axis] > bx[i].hi[w->axis] + r)
                break;
            const float *a = w->soa + i * stride, *b = w->soa + j * stride;
            if (box_distance(&bx[i], &bx[j]) >= r ||
                lc_cluster_lower_bound(a, bx[i].lo, bx[i].hi, b, bx[j].lo, bx[j].hi, dg->k, r) >= r)
                continue;
            float d = lc_cluster_rmcpd_below(a, b, dg->k, r);
            w->pairs++;
            if (!(d < r))
                continue;
            if (w->count == w->cap) {
                size_t cap = w->cap ? 2 * w->cap : 4096;
                edge *e = realloc(w->edges, cap * sizeof *e);
                if (!e) {
                    w->failed = 1;
                    break;
                }
                w->edges = e;
                w->cap = cap;
            }
            w->edges[w->count++] = (edge){d, i, j};
        }
    }
}

static int link_pruned(engine *g, lc_dendrogram *dg, const float *soa, const box *bx, float r)
{
    uint32_t m = dg->lines;
    sweep_key *order = malloc((size_t)m * sizeof *order);
    if (!order)
        return -1;
    int axis = 0;
    float best = -1;
    for (int j = 0; j < 3; j++) {
        float lo = FLT_MAX, hi = -FLT_MAX;
        for (uint32_t i = 0; i < m; i++) {
            lo = fminf(lo, bx[i].lo[j]);
            hi = fmaxf(hi, bx[i].hi[j]);
        }
        if (hi - lo > best) {
            best = hi - lo;
            axis = j;
        }
    }
    for (uint32_t i = 0; i < m; i++)
        order[i] = (sweep_key){bx[i].lo[axis], i};
    qsort(order, m, sizeof *order, cmp_sweep);
    uint32_t threads = thread_count(m);
    sweep w[MAX_THREADS];
    for (uint32_t t = 0; t < threads; t++)
        w[t] =
            (sweep){.dg = dg, .soa = soa, .bx = bx, .order = order, .r = r, .axis = axis, .first = t, .step = threads};
    lc_parallel_for(threads, sweep_run, w, sizeof w[0]);
    int rc = 0;
    for (uint32_t t = 0; t < threads; t++) {
        rc |= w[t].failed;
        dg->stats.pairs_tested += w[t].pairs;
        for (size_t e = 0; e < w[t].count && !rc; e++)
            rc = engine_edge(g, w[t].edges[e].a, w[t].edges[e].b, w[t].edges[e].d);
        free(w[t].edges);
    }
    free(order);
    return rc ? -1 : 0;
}

/* The top stage's rMCPDs of stand-in pairs (s < t), row s from offset
 * s * roots - s (s + 1) / 2; threads take every step-th row. */
typedef struct top_job {
    const float *soa;
    const uint32_t *stand_in;
    uint32_t roots, first, step;
    int k;
    float *d;
} top_job;

static void top_run(void *arg)
{
    top_job *j = arg;
    size_t stride = (size_t)j->k * DIM;
    for (uint32_t s = j->first; s < j->roots; s += j->step) {
        float *row = j->d + (size_t)s * j->roots - (size_t)s * (s + 1) / 2; /* pairs (s, s + 1), ... */
        for (uint32_t t = s + 1; t < j->roots; t++)
            row[t - s - 1] =
                lc_cluster_rmcpd_soa(j->soa + j->stand_in[s] * stride, j->soa + j->stand_in[t] * stride, j->k);
    }
}

/* The dense top stage: each remaining cluster is stood in for by its line
 * closest to the cluster's mean line; the clusters are linked pairwise by
 * max(r, rMCPD of those lines), so no top merge comes below a pruned one. */
static int link_top(engine *g, lc_dendrogram *dg, const float *soa, float r)
{
    uint32_t m = dg->lines, roots = 0;
    size_t stride = (size_t)dg->k * DIM;
    uint32_t *root_of = malloc((size_t)m * sizeof *root_of), *roots_list = malloc((size_t)m * sizeof *roots_list);
    uint32_t *stand_in = malloc((size_t)m * sizeof *stand_in), *slot = malloc((size_t)g->nodes * sizeof *slot);
    float *mean = NULL, *pair_d = NULL, *best = malloc((size_t)m * sizeof *best);
    int rc = -1;
    if (!root_of || !roots_list || !stand_in || !slot || !best)
        goto out;
    /* Each line's root: follow the merges forward (parent of a node). */
    uint32_t *parent = slot; /* reused: parent per node, then slot per root */
    for (uint32_t i = 0; i < g->nodes; i++)
        parent[i] = UINT32_MAX;
    for (uint32_t i = 0; i < g->merge_count; i++)
        parent[g->merges[i].a] = parent[g->merges[i].b] = m + i;
    for (uint32_t i = 0; i < m; i++) {
        uint32_t x = i;
        while (parent[x] != UINT32_MAX)
            x = parent[x];
        root_of[i] = x;
    }
    for (uint32_t i = 0; i < g->nodes; i++)
        slot[i] = UINT32_MAX;
    for (uint32_t i = 0; i < m; i++)
        if (slot[root_of[i]] == UINT32_MAX) {
            slot[root_of[i]] = roots;
            roots_list[roots++] = root_of[i];
        }
    dg->stats.top_clusters = roots;
    mean = calloc((size_t)roots * stride, sizeof *mean);
    if (!mean)
        goto out;
    for (uint32_t i = 0; i < m; i++) {
        uint32_t s = slot[root_of[i]];
        for (size_t j = 0; j < stride; j++)
            mean[s * stride + j] += dg->samples[i * stride + j] / (float)g->size[root_of[i]];
    }
    for (uint32_t s = 0; s < roots; s++)
        best[s] = FLT_MAX;
    for (uint32_t i = 0; i < m; i++) {
        uint32_t s = slot[root_of[i]];
        float e = 0;
        for (size_t j = 0; j < stride; j++) {
            float t = dg->samples[i * stride + j] - mean[s * stride + j];
            e += t * t;
        }
        if (e < best[s]) {
            best[s] = e;
            stand_in[s] = i;
        }
    }
    pair_d = malloc(((size_t)roots * (roots - 1) / 2 + 1) * sizeof *pair_d);
    if (!pair_d)
        goto out;
    uint32_t threads = thread_count(roots);
    top_job jobs[MAX_THREADS];
    for (uint32_t t = 0; t < threads; t++)
        jobs[t] = (top_job){soa, stand_in, roots, t, threads, dg->k, pair_d};
    lc_parallel_for(threads, top_run, jobs, sizeof jobs[0]);
    rc = 0; /* edges in the order of the pairs: the merges do not depend on the threads */
    for (uint32_t s = 0, e = 0; s < roots && !rc; s++)
        for (uint32_t t = s + 1; t < roots && !rc; t++, e++) {
            float d = pair_d[e];
            dg->stats.pairs_tested++;
            rc = engine_edge(g, roots_list[s], roots_list[t], isfinite(r) ? fmaxf(r, d) : d);
        }
    g->r = INFINITY;
    if (!rc)
        rc = engine_run(g);
out:
    free(root_of);
    free(roots_list);
    free(stand_in);
    free(slot);
    free(mean);
    free(pair_d);
    free(best);
    return rc;
}

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* One attempt at radius r; returns the clusters the sparse stage left (or 0
 * on OOM), with dg->merges filled when they fit the top stage's limit. */
static int build_with_radius(lc_dendrogram *dg, const float *soa, const box *bx, float r, uint32_t top_limit,
                             lc_linkage linkage, int *too_many)
{
    engine g;
    int rc = -1;
    *too_many = 0;
    if (engine_init(&g, dg->lines, linkage, dg->merges) == 0) {
        g.r = r;
        rc = link_pruned(&g, dg, soa, bx, r) || engine_run(&g) ? -1 : 0;
        if (!rc && dg->lines - g.merge_count > top_limit && isfinite(r))
            *too_many = 1;
        else if (!rc && g.merge_count < dg->lines - 1)
            rc = link_top(&g, dg, soa, r);
    }
    engine_free(&g);
    return rc;
}

/* Links dg's lines (the pruned stage at a growing radius, then the top stage). */
static int link_lines(lc_dendrogram *dg, const float *soa, const box *bx, const lc_cluster_desc *dd)
{
    uint32_t top_limit = dd->top_clusters ? dd->top_clusters : DEFAULT_TOP_CLUSTERS;
    /* Large sets need more neighbours for the pruned stage to leave at most
     * top_limit clusters; starting near that saves repeated stages (10^4
     * tornado lines needed about 1000 lower-bound neighbours). */
    uint32_t neighbours = dd->neighbours ? dd->neighbours : DEFAULT_NEIGHBOURS;
    if (!dd->neighbours && dg->lines / 16 > neighbours)
        neighbours = dg->lines / 16;
    int rc = 0;
    if (dg->lines > 1) {
        /* Small sets link every pair; larger ones prune at a radius that grows
         * until the sparse stage leaves few enough clusters for the top. */
        float r = dg->lines <= DENSE_LINES && !dd->neighbours ? INFINITY : prune_radius(dg, soa, bx, neighbours);
        for (;;) {
            int too_many;
            dg->stats.attempts++;
            dg->stats.pairs_tested = 0;
            dg->stats.prune_radius = r;
            rc = build_with_radius(dg, soa, bx, r, top_limit, dd->linkage, &too_many);
            if (rc || !too_many)
                break;
            neighbours = neighbours < dg->lines / 4 ? 4 * neighbours : dg->lines;
            float r2 = neighbours >= dg->lines ? INFINITY : prune_radius(dg, soa, bx, neighbours);
            r = r2 > 2.0f * r ? r2 : 2.0f * r;
        }
    }
    return rc;
}

/* Sampled clustering: `count` evenly spread lines are linked as a set of
 * their own, every other line attaches to its nearest sampled line
 * (cluster_sample.c), and the merges are the attachments (each joins the
 * sampled line's growing cluster, nearest first) followed by the sample's
 * merges, so a cut into k <= count clusters is the sample's cut with every
 * line in its nearest sampled line's cluster. */
static int link_sampled(lc_dendrogram *dg, const float *soa, const box *bx, const lc_cluster_desc *dd, uint32_t count)
{
    uint32_t n = dg->lines;
    size_t stride = (size_t)dg->k * DIM;
    lc_dendrogram sub = {.lines = count, .k = dg->k};
    uint32_t *pick = malloc((size_t)count * sizeof *pick), *nearest = malloc((size_t)n * sizeof *nearest);
    uint32_t *cur = malloc((size_t)count * sizeof *cur);
    float *dist = malloc((size_t)n * sizeof *dist), *ssoa = malloc((size_t)count * stride * sizeof *ssoa);
    sweep_key *order = malloc((size_t)n * sizeof *order);
    box *sbx = malloc((size_t)count * sizeof *sbx);
    sub.samples = malloc((size_t)count * stride * sizeof *sub.samples);
    sub.merges = malloc((size_t)count * sizeof *sub.merges);
    int rc = -1;
    if (!pick || !nearest || !cur || !dist || !ssoa || !order || !sbx || !sub.samples || !sub.merges)
        goto out;
    for (uint32_t i = 0; i < count; i++) {
        uint32_t l = pick[i] = (uint32_t)((uint64_t)i * n / count);
        memcpy(sub.samples + i * stride, dg->samples + l * stride, stride * sizeof *ssoa);
        memcpy(ssoa + i * stride, soa + l * stride, stride * sizeof *ssoa);
        sbx[i] = bx[l];
        cur[i] = l;
    }
    uint64_t pairs = 0;
    if (link_lines(&sub, ssoa, sbx, dd) ||
        lc_cluster_attach(soa, n, dg->k, pick, count, thread_count(n), nearest, dist, &pairs))
        goto out;
    uint32_t others = 0;
    for (uint32_t i = 0, s = 0; i < n; i++) {
        if (s < count && pick[s] == i) {
            s++;
            continue;
        }
        order[others++] = (sweep_key){dist[i], i}; /* nearest first, ties by line */
    }
    qsort(order, others, sizeof *order, cmp_sweep);
    for (uint32_t e = 0; e < others; e++) {
        uint32_t i = order[e].line, s = nearest[i];
        dg->merges[e] = (merge){cur[s], i, order[e].lo};
        cur[s] = n + e;
    }
    for (uint32_t e = 0; e + 1 < count; e++) { /* the sample's node x: its line's cluster, or a merge of its own */
        merge m = sub.merges[e];
        m.a = m.a < count ? cur[m.a] : n + others + (m.a - count);
        m.b = m.b < count ? cur[m.b] : n + others + (m.b - count);
        dg->merges[others + e] = m;
    }
    dg->stats = sub.stats;
    dg->stats.pairs_tested += pairs;
    dg->stats.sampled_lines = count;
    rc = 0;
out:
    free(pick);
    free(nearest);
    free(cur);
    free(dist);
    free(ssoa);
    free(order);
    free(sbx);
    free(sub.samples);
    free(sub.merges);
    return rc;
}

int lc_dendrogram_build_samples(const lc_line_samples *ls, const lc_cluster_desc *desc, lc_dendrogram **out,
                                lc_error *err)
{
    lc_cluster_desc dd = desc ? *desc : (lc_cluster_desc){0};
    *out = NULL;
    if (!ls || ls->lines == 0)
        return lc_err(err, LC_ERR_INVALID, "clustering needs at least one line");
    if (!(dd.lift_importance >= 0) || !(dd.lift_color >= 0) || !isfinite(dd.lift_importance) ||
        !isfinite(dd.lift_color))
        return lc_err(err, LC_ERR_INVALID, "clustering: lift weights must be finite and >= 0");
    if ((unsigned)dd.linkage > LC_LINKAGE_AVERAGE)
        return lc_err(err, LC_ERR_INVALID, "clustering: unknown linkage %d", (int)dd.linkage);
    double t0 = now_seconds();
    uint32_t line_count = ls->lines;
    int k = ls->k;
    lc_dendrogram *dg = calloc(1, sizeof *dg);
    if (!dg)
        return lc_err(err, LC_ERR_NOMEM, "clustering: out of memory");
    dg->lines = line_count;
    dg->k = k;
    size_t stride = (size_t)k * DIM;
    dg->samples = malloc((size_t)line_count * stride * sizeof *dg->samples);
    dg->mean_g = malloc((size_t)line_count * sizeof *dg->mean_g);
    dg->merges = malloc((size_t)(line_count > 1 ? line_count - 1 : 1) * sizeof *dg->merges);
    box *bx = malloc((size_t)line_count * sizeof *bx);
    float *soa = malloc((size_t)line_count * stride * sizeof *soa); /* the build's kernels read lines by coordinate */
    if (!dg->samples || !dg->mean_g || !dg->merges || !bx || !soa) {
        free(bx);
        free(soa);
        lc_dendrogram_destroy(dg);
        return lc_err(err, LC_ERR_NOMEM, "clustering: out of memory for %u lines", line_count);
    }
    /* The lift of DLS Eq. 2. */
    for (uint32_t i = 0; i < line_count; i++) {
        float *s = dg->samples + i * stride;
        double gsum = 0;
        for (int p = 0; p < k; p++) {
            size_t q = (size_t)i * k + p;
            float g = dd.importance ? dd.importance[q] : 0, c = dd.color ? dd.color[q] : 0;
            s[p * DIM + 0] = ls->xyz[3 * q];
            s[p * DIM + 1] = ls->xyz[3 * q + 1];
            s[p * DIM + 2] = ls->xyz[3 * q + 2];
            s[p * DIM + 3] = dd.lift_importance * g;
            s[p * DIM + 4] = dd.lift_color * c;
            gsum += g;
        }
        dg->mean_g[i] = dd.importance ? (float)(gsum / k) : ls->length[i];
        for (int j = 0; j < DIM; j++) {
            bx[i].lo[j] = FLT_MAX;
            bx[i].hi[j] = -FLT_MAX;
        }
        for (int p = 0; p < k; p++)
            for (int j = 0; j < DIM; j++) {
                bx[i].lo[j] = fminf(bx[i].lo[j], s[p * DIM + j]);
                bx[i].hi[j] = fmaxf(bx[i].hi[j], s[p * DIM + j]);
            }
        lc_cluster_transpose(s, k, soa + i * stride);
    }
    uint32_t limit = dd.sample_lines ? dd.sample_lines : DEFAULT_SAMPLE_LINES;
    int rc = line_count > limit && limit > 1 ? link_sampled(dg, soa, bx, &dd, limit) : link_lines(dg, soa, bx, &dd);
    free(bx);
    free(soa);
    if (rc) {
        lc_dendrogram_destroy(dg);
        return lc_err(err, LC_ERR_NOMEM, "clustering: out of memory linking %u lines", line_count);
    }
    dg->stats.seconds = now_seconds() - t0;
    LC_INFO("cluster", "%u lines, %s linkage: %.2f s, %u attempt(s), radius %.4g, %llu pairs measured, %u top clusters",
            line_count, lc_linkage_name(dd.linkage), dg->stats.seconds, dg->stats.attempts, dg->stats.prune_radius,
            (unsigned long long)dg->stats.pairs_tested, dg->stats.top_clusters);
    *out = dg;
    return 0;
}

int lc_dendrogram_build(const float *positions, const uint32_t *offsets, uint32_t line_count,
                        const lc_cluster_desc *desc, lc_dendrogram **out, lc_error *err)
{
    lc_cluster_desc dd = desc ? *desc : (lc_cluster_desc){0};
    const float *channels[2];
    int n = 0;
    if (dd.importance)
        channels[n++] = dd.importance;
    if (dd.color)
        channels[n++] = dd.color;
    lc_line_samples *ls = NULL;
    *out = NULL;
    int rc = lc_line_samples_create(positions, offsets, line_count, dd.samples, channels, n, &ls, err);
    if (rc)
        return rc;
    size_t per = (size_t)ls->lines * ls->k;
    dd.importance = desc && desc->importance ? ls->values : NULL;
    dd.color = desc && desc->color ? ls->values + (dd.importance ? per : 0) : NULL;
    rc = lc_dendrogram_build_samples(ls, &dd, out, err);
    lc_line_samples_destroy(ls);
    return rc;
}

void lc_dendrogram_destroy(lc_dendrogram *d)
{
    if (!d)
        return;
    free(d->samples);
    free(d->mean_g);
    free(d->merges);
    free(d);
}

uint32_t lc_dendrogram_lines(const lc_dendrogram *d) { return d ? d->lines : 0; }

void lc_dendrogram_stats(const lc_dendrogram *d, lc_cluster_stats *out) { *out = d->stats; }

size_t lc_dendrogram_bytes(const lc_dendrogram *d)
{
    if (!d)
        return 0;
    return sizeof *d + (size_t)d->lines * ((size_t)d->k * DIM * sizeof(float) + sizeof(float) + sizeof(merge));
}

const char *lc_linkage_name(lc_linkage l)
{
    return l == LC_LINKAGE_SINGLE ? "single" : l == LC_LINKAGE_AVERAGE ? "average" : "complete";
}
