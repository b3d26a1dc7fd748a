/* Optimization elements (docs/ALGORITHM.md): the element table (per-vertex
 * (element, weight) blend, the element adjacency for smoothing), the default
 * counts, and the surfaces' geodesic patches around sampled centres. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "elements.h"

/* Default element counts grow with the data (docs/ALGORITHM.md "Elements"):
 * lines get at least DEFAULT_LINE_BUDGET, MIN_ELEMENTS_PER_LINE per line and
 * one element per SEGMENTS_PER_ELEMENT segments; surfaces one patch per 8
 * vertices, at most the larger of MAX_DEFAULT_PATCHES and one per
 * VERTICES_PER_PATCH_CAP vertices. MAX_DERIVED_ELEMENTS caps both, which
 * bounds every session's per-element state (4 bytes an element). */
#define DEFAULT_LINE_BUDGET 10000u
#define MIN_ELEMENTS_PER_LINE 4u
#define SEGMENTS_PER_ELEMENT 32u
#define MAX_DEFAULT_PATCHES 4000u
#define VERTICES_PER_PATCH_CAP 64u
#define MAX_DERIVED_ELEMENTS (1u << 20)
#define NONE UINT32_MAX

int lc_elements_alloc(lc_elements *e, uint32_t vertices, uint32_t count, const char *name, lc_error *err)
{
    e->count = count;
    e->vertex_elements = malloc((size_t)(vertices ? vertices : 1) * 4 * sizeof(uint32_t));
    e->vertex_weights = malloc((size_t)(vertices ? vertices : 1) * 4 * sizeof(float));
    e->adjacency_offsets = calloc((size_t)count + 1, sizeof(uint32_t));
    if (!e->vertex_elements || !e->vertex_weights || !e->adjacency_offsets)
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate %u elements", name, count);
    return LC_OK;
}

void lc_elements_set_vertex(lc_elements *e, uint32_t v, int n, const uint32_t *ids, const float *w, uint32_t primary)
{
    uint32_t *ve = e->vertex_elements + 4 * (size_t)v;
    float *vw = e->vertex_weights + 4 * (size_t)v;
    for (int k = 0; k < 3; k++) {
        ve[k] = k < n ? ids[k] : ids[0];
        vw[k] = k < n ? w[k] : 0.0f;
    }
    ve[3] = primary;
    vw[3] = 0.0f;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

int lc_elements_adjacency_from_pairs(lc_elements *e, uint64_t *pairs, size_t n, const char *name, lc_error *err)
{
    qsort(pairs, n, sizeof *pairs, cmp_u64);
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t a = (uint32_t)(pairs[i] >> 32), b = (uint32_t)pairs[i];
        if (a == b || (m > 0 && pairs[m - 1] == pairs[i]))
            continue;
        pairs[m++] = pairs[i];
    }
    e->adjacency = malloc((m ? m : 1) * sizeof(uint32_t));
    if (!e->adjacency) {
        free(pairs);
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate element adjacency", name);
    }
    memset(e->adjacency_offsets, 0, ((size_t)e->count + 1) * sizeof(uint32_t));
    for (size_t i = 0; i < m; i++) {
        e->adjacency_offsets[(pairs[i] >> 32) + 1]++;
        e->adjacency[i] = (uint32_t)pairs[i];
    }
    for (uint32_t i = 0; i < e->count; i++)
        e->adjacency_offsets[i + 1] += e->adjacency_offsets[i];
    e->adjacency_count = (uint32_t)m;
    free(pairs);
    return LC_OK;
}

/* ---- surfaces */

/* Vertex graph of the mesh in CSR form, edge weights = Euclidean lengths. */
typedef struct {
    uint32_t *off; /* vertex_count + 1 */
    uint32_t *nbr;
    float *len;
} mesh_graph;

static void graph_free(mesh_graph *g)
{
    free(g->off);
    free(g->nbr);
    free(g->len);
}

static int build_graph(const lc_element_geometry *s, mesh_graph *g)
{
    uint32_t n = s->vertex_count;
    size_t half = (size_t)s->triangle_count * 6;
    g->off = calloc((size_t)n + 2, sizeof(uint32_t));
    g->nbr = malloc(half * sizeof(uint32_t));
    g->len = NULL;
    if (!g->off || !g->nbr)
        return -1;
    const uint32_t *T = s->triangles;
    for (size_t t = 0; t < s->triangle_count; t++)
        for (int k = 0; k < 3; k++)
            g->off[T[3 * t + k] + 2] += 2;
    for (uint32_t v = 0; v < n; v++)
        g->off[v + 2] += g->off[v + 1];
    for (size_t t = 0; t < s->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = T[3 * t + k], b = T[3 * t + (k + 1) % 3], c = T[3 * t + (k + 2) % 3];
            g->nbr[g->off[a + 1]++] = b;
            g->nbr[g->off[a + 1]++] = c;
        }
    /* off[v+1] now ends v's list; drop duplicates (an interior edge appears in
     * two triangles) with a last-seen mark instead of sorting, compacting in place */
    uint32_t *mark = malloc((size_t)(n ? n : 1) * sizeof(uint32_t));
    if (!mark)
        return -1;
    for (uint32_t v = 0; v < n; v++)
        mark[v] = NONE;
    uint32_t w = 0, start = 0;
    for (uint32_t v = 0; v < n; v++) {
        uint32_t end = g->off[v + 1];
        g->off[v] = w;
        for (uint32_t i = start; i < end; i++) {
            uint32_t u = g->nbr[i];
            if (u == v || mark[u] == v)
                continue;
            mark[u] = v;
            g->nbr[w++] = u;
        }
        start = end;
    }
    free(mark);
    g->off[n] = w;
    g->len = malloc((w ? w : 1) * sizeof(float));
    if (!g->len)
        return -1;
    const float *P = s->positions;
    for (uint32_t v = 0; v < n; v++)
        for (uint32_t i = g->off[v]; i < g->off[v + 1]; i++) {
            const float *a = P + 3 * (size_t)v, *b = P + 3 * (size_t)g->nbr[i];
            double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
            g->len[i] = (float)sqrt(dx * dx + dy * dy + dz * dz);
        }
    return 0;
}

/* Indexed binary heap over vertex ids keyed by dist[]: a min-heap for Dijkstra
 * and a max-heap for picking the farthest vertex, both with decrease-key.
 * Ties break by vertex id so results do not depend on insertion order. */
typedef struct {
    uint32_t *h, *pos, n;
    const float *key;
    int max;
} iheap;

static int ih_before(const iheap *q, uint32_t a, uint32_t b)
{
    float ka = q->key[a], kb = q->key[b];
    if (ka != kb)
        return q->max ? ka > kb : ka < kb;
    return a < b;
}

static void ih_place(iheap *q, uint32_t i, uint32_t v)
{
    q->h[i] = v;
    q->pos[v] = i;
}

static void ih_up(iheap *q, uint32_t i)
{
    uint32_t v = q->h[i];
    while (i > 0) {
        uint32_t p = (i - 1) / 2;
        if (!ih_before(q, v, q->h[p]))
            break;
        ih_place(q, i, q->h[p]);
        i = p;
    }
    ih_place(q, i, v);
}

static void ih_down(iheap *q, uint32_t i)
{
    uint32_t v = q->h[i];
    for (;;) {
        uint32_t c = 2 * i + 1;
        if (c >= q->n)
            break;
        if (c + 1 < q->n && ih_before(q, q->h[c + 1], q->h[c]))
            c++;
        if (!ih_before(q, q->h[c], v))
            break;
        ih_place(q, i, q->h[c]);
        i = c;
    }
    ih_place(q, i, v);
}

static void ih_push(iheap *q, uint32_t v)
{
    ih_place(q, q->n++, v);
    ih_up(q, q->n - 1);
}

static uint32_t ih_pop(iheap *q)
{
    uint32_t top = q->h[0];
    q->pos[top] = NONE;
    if (--q->n > 0) {
        ih_place(q, 0, q->h[q->n]);
        ih_down(q, 0);
    }
    return top;
}

/* Farthest-point sampling with graph distances. dist[] holds the distance to
 * the nearest centre so far; a new centre runs a Dijkstra that only expands
 * vertices it brings closer, so later centres touch ever smaller regions.
 * Unreached components have infinite distance and are picked first, hence
 * sampling continues past `want` until every component has a centre. */
static int farthest_point_sampling(const lc_element_geometry *s, const mesh_graph *g, const uint8_t *used,
                                   uint32_t want, uint32_t **centres_out, uint32_t *count_out)
{
    uint32_t n = s->vertex_count;
    float *dist = malloc((size_t)n * sizeof(float));
    uint32_t *hmax = malloc((size_t)n * sizeof(uint32_t)), *pmax = malloc((size_t)n * sizeof(uint32_t));
    uint32_t *hmin = malloc((size_t)n * sizeof(uint32_t)), *pmin = malloc((size_t)n * sizeof(uint32_t));
    uint32_t cap = want, count = 0;
    uint32_t *centres = malloc((size_t)cap * sizeof(uint32_t));
    int rc = -1;
    if (!dist || !hmax || !pmax || !hmin || !pmin || !centres)
        goto done;
    iheap far = {hmax, pmax, 0, dist, 1}, near = {hmin, pmin, 0, dist, 0};
    for (uint32_t v = 0; v < n; v++) {
        dist[v] = INFINITY;
        pmin[v] = NONE;
        pmax[v] = NONE;
    }
    /* all at +inf: vertex order is already a valid heap order */
    for (uint32_t v = 0; v < n; v++)
        if (used[v])
            ih_place(&far, far.n++, v);
    while (far.n > 0) {
        uint32_t c = far.h[0];
        if (count >= want && isfinite(dist[c]))
            break;
        if (count == cap) {
            uint32_t ncap = cap * 2;
            uint32_t *grown = realloc(centres, (size_t)ncap * sizeof(uint32_t));
            if (!grown)
                goto done;
            centres = grown;
            cap = ncap;
        }
        centres[count++] = c;
        ih_pop(&far); /* a centre stays at distance 0 forever */
        dist[c] = 0.0f;
        ih_push(&near, c);
        while (near.n > 0) {
            uint32_t u = ih_pop(&near);
            float du = dist[u];
            for (uint32_t i = g->off[u]; i < g->off[u + 1]; i++) {
                uint32_t w = g->nbr[i];
                float nd = du + g->len[i];
                if (!(nd < dist[w]))
                    continue;
                dist[w] = nd;
                if (pmin[w] == NONE)
                    ih_push(&near, w);
                else
                    ih_up(&near, pmin[w]);
                if (pmax[w] != NONE)
                    ih_down(&far, pmax[w]);
            }
        }
    }
    rc = 0;
done:
    free(dist);
    free(hmax);
    free(pmax);
    free(hmin);
    free(pmin);
    if (rc) {
        free(centres);
        centres = NULL;
    }
    *centres_out = centres;
    *count_out = count;
    return rc;
}

static uint32_t uf_find(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

typedef struct {
    uint64_t key; /* cell: x | y << 21 | z << 42 */
    uint32_t part, v;
} cell_item;

static int cmp_cell_item(const void *pa, const void *pb)
{
    const cell_item *a = pa, *b = pb;
    if (a->part != b->part)
        return a->part < b->part ? -1 : 1;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return a->v < b->v ? -1 : a->v > b->v;
}

/* Grid sampling (lc_patch_sampling): one centre per occupied cell of a cubic
 * grid and connected part of the mesh (so every part has one), the vertex
 * nearest the cell's middle. A surface of area A meets about A / h^2 cells of
 * size h, so h starts at sqrt(A / want) and grows while a pass yields more
 * than 5/4 of want (oblique surfaces meet more cells). */
static int grid_sampling(const lc_element_geometry *s, const uint8_t *used, uint32_t want, uint32_t **centres_out,
                         uint32_t *count_out)
{
    uint32_t n = s->vertex_count, m = 0;
    const float *P = s->positions;
    uint32_t *parent = malloc((size_t)(n ? n : 1) * sizeof(uint32_t));
    cell_item *items = NULL;
    uint32_t *centres = NULL;
    if (!parent)
        goto oom;
    for (uint32_t v = 0; v < n; v++)
        parent[v] = v;
    double area = 0, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t t = 0; t < s->triangle_count; t++) {
        const uint32_t *T = s->triangles + 3 * t;
        for (int k = 1; k < 3; k++) {
            uint32_t a = uf_find(parent, T[0]), b = uf_find(parent, T[k]);
            if (a != b)
                parent[a < b ? b : a] = a < b ? a : b;
        }
        const float *p0 = P + 3 * (size_t)T[0], *p1 = P + 3 * (size_t)T[1], *p2 = P + 3 * (size_t)T[2];
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++)
            e1[k] = p1[k] - p0[k], e2[k] = p2[k] - p0[k];
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
        area += 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
    }
    for (uint32_t v = 0; v < n; v++)
        if (used[v]) {
            m++;
            for (int k = 0; k < 3; k++) {
                lo[k] = P[3 * (size_t)v + k] < lo[k] ? P[3 * (size_t)v + k] : lo[k];
                hi[k] = P[3 * (size_t)v + k] > hi[k] ? P[3 * (size_t)v + k] : hi[k];
            }
        }
    items = malloc((size_t)(m ? m : 1) * sizeof *items);
    if (!items)
        goto oom;
    double extent = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    double h = sqrt(area / want);
    if (!(h > 0) || !isfinite(h))
        h = extent > 0 ? extent / cbrt((double)want) : 1.0;
    h = fmax(h, extent / 2097151.0); /* 21 bits a coordinate */
    uint32_t count = 0;
    for (int pass = 0; pass < 4; pass++) {
        uint32_t i = 0;
        for (uint32_t v = 0; v < n; v++) {
            if (!used[v])
                continue;
            uint64_t key = 0;
            for (int k = 0; k < 3; k++) {
                double c = floor((P[3 * (size_t)v + k] - lo[k]) / h);
                key |= (uint64_t)(c < 0 ? 0 : c > 2097151 ? 2097151 : c) << (21 * k);
            }
            items[i++] = (cell_item){key, uf_find(parent, v), v};
        }
        qsort(items, m, sizeof *items, cmp_cell_item);
        count = 0;
        for (uint32_t j = 0; j < m; j++)
            count += j == 0 || items[j].key != items[j - 1].key || items[j].part != items[j - 1].part;
        if ((uint64_t)count * 4 <= (uint64_t)want * 5 || pass == 3)
            break;
        h *= sqrt((double)count / want);
    }
    centres = malloc((size_t)(count ? count : 1) * sizeof(uint32_t));
    if (!centres)
        goto oom;
    uint32_t c = 0;
    double best = INFINITY;
    for (uint32_t j = 0; j < m; j++) {
        if (j > 0 && (items[j].key != items[j - 1].key || items[j].part != items[j - 1].part))
            c++, best = INFINITY;
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            double mid = lo[k] + h * ((double)((items[j].key >> (21 * k)) & 2097151u) + 0.5);
            double dk = P[3 * (size_t)items[j].v + k] - mid;
            d2 += dk * dk;
        }
        if (d2 < best) {
            best = d2;
            centres[c] = items[j].v;
        }
    }
    free(parent);
    free(items);
    *centres_out = centres;
    *count_out = count;
    return 0;
oom:
    free(parent);
    free(items);
    free(centres);
    return -1;
}

/* Multi-source Dijkstra that keeps the 3 nearest centres per vertex. A centre
 * can be among a vertex's 3 nearest only if it is among the 3 nearest of the
 * previous vertex on the shortest path, so only settled top-3 labels expand. */
typedef struct {
    float d;
    uint32_t v, c;
} label;

typedef struct {
    label *a;
    size_t n, cap;
} lheap;

static int label_before(label x, label y)
{
    if (x.d != y.d)
        return x.d < y.d;
    if (x.v != y.v)
        return x.v < y.v;
    return x.c < y.c;
}

static int lh_push(lheap *q, label x)
{
    if (q->n == q->cap) {
        size_t ncap = q->cap ? q->cap * 2 : 1024;
        label *grown = realloc(q->a, ncap * sizeof *grown);
        if (!grown)
            return -1;
        q->a = grown;
        q->cap = ncap;
    }
    size_t i = q->n++;
    while (i > 0) {
        size_t p = (i - 1) / 2;
        if (!label_before(x, q->a[p]))
            break;
        q->a[i] = q->a[p];
        i = p;
    }
    q->a[i] = x;
    return 0;
}

static label lh_pop(lheap *q)
{
    label top = q->a[0], x = q->a[--q->n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= q->n)
            break;
        if (c + 1 < q->n && label_before(q->a[c + 1], q->a[c]))
            c++;
        if (!label_before(q->a[c], x))
            break;
        q->a[i] = q->a[c];
        i = c;
    }
    if (q->n > 0)
        q->a[i] = x;
    return top;
}

typedef struct {
    uint32_t c[3];
    float d[3];
    uint8_t n, settled; /* settled: bit k = slot k final */
} nearest3;

/* Offers (c, d) to v's tentative list; returns 1 if it changed. */
static int offer(nearest3 *t, uint32_t c, float d)
{
    for (int k = 0; k < t->n; k++)
        if (t->c[k] == c) {
            if (d < t->d[k] && !(t->settled & (1u << k))) {
                t->d[k] = d;
                return 1;
            }
            return 0;
        }
    if (t->n < 3) {
        t->c[t->n] = c;
        t->d[t->n] = d;
        t->n++;
        return 1;
    }
    int worst = 0;
    for (int k = 1; k < 3; k++)
        if (t->d[k] > t->d[worst])
            worst = k;
    if (d < t->d[worst] && !(t->settled & (1u << worst))) {
        t->c[worst] = c;
        t->d[worst] = d;
        return 1;
    }
    return 0;
}

static int nearest_centres(const lc_element_geometry *s, const mesh_graph *g, const uint32_t *centres, uint32_t count,
                           nearest3 *near)
{
    lheap q = {0};
    for (uint32_t i = 0; i < count; i++) {
        offer(&near[centres[i]], i, 0.0f);
        if (lh_push(&q, (label){0.0f, centres[i], i}))
            goto oom;
    }
    while (q.n > 0) {
        label x = lh_pop(&q);
        nearest3 *t = &near[x.v];
        int k = 0;
        while (k < t->n && t->c[k] != x.c)
            k++;
        if (k == t->n || t->d[k] != x.d || (t->settled & (1u << k)))
            continue; /* stale: improved or evicted since it was pushed */
        t->settled |= (uint8_t)(1u << k);
        for (uint32_t i = g->off[x.v]; i < g->off[x.v + 1]; i++) {
            uint32_t w = g->nbr[i];
            float nd = x.d + g->len[i];
            if (offer(&near[w], x.c, nd) && lh_push(&q, (label){nd, w, x.c}))
                goto oom;
        }
    }
    (void)s;
    free(q.a);
    return 0;
oom:
    free(q.a);
    return -1;
}

int lc_elements_build_patches(const lc_element_geometry *s, lc_elements *e, uint32_t want, lc_patch_sampling sampling,
                              lc_error *err)
{
    uint32_t n = s->vertex_count;
    mesh_graph g = {0};
    uint8_t *used = calloc(n, 1);
    nearest3 *near = calloc(n, sizeof *near);
    uint32_t *centres = NULL, count = 0;
    uint64_t *pairs = NULL;
    int rc = LC_ERR_NOMEM;
    double tg = lc_now();
    if (!used || !near || build_graph(s, &g))
        goto fail;
    LC_DEBUG("scene", "%s: mesh graph %.0f ms", s->name, (lc_now() - tg) * 1e3);
    for (size_t i = 0; i < (size_t)s->triangle_count * 3; i++)
        used[s->triangles[i]] = 1;
    uint32_t used_count = 0;
    for (uint32_t v = 0; v < n; v++)
        used_count += used[v];
    if (want > used_count)
        want = used_count;
    if (want < 1)
        want = 1;
    double t0 = lc_now();
    if (sampling == LC_PATCH_SAMPLING_AUTO)
        sampling = n > LC_GRID_SAMPLING_VERTICES ? LC_PATCH_SAMPLING_GRID : LC_PATCH_SAMPLING_FARTHEST;
    if (sampling == LC_PATCH_SAMPLING_GRID ? grid_sampling(s, used, want, &centres, &count)
                                           : farthest_point_sampling(s, &g, used, want, &centres, &count))
        goto fail;
    double t1 = lc_now();
    if (count > want && sampling == LC_PATCH_SAMPLING_FARTHEST)
        LC_INFO("scene", "%s: %u disconnected parts raise the patch count from %u to %u", s->name, count - want + 1,
                want, count);
    if (nearest_centres(s, &g, centres, count, near))
        goto fail;
    LC_DEBUG("scene", "%s: %u patches: %s sampling %.0f ms, nearest centres %.0f ms", s->name, count,
             sampling == LC_PATCH_SAMPLING_GRID ? "grid" : "farthest-point", (t1 - t0) * 1e3, (lc_now() - t1) * 1e3);
    rc = lc_elements_alloc(e, n, count, s->name, err);
    if (rc)
        goto out;
    for (uint32_t v = 0; v < n; v++) {
        nearest3 *t = &near[v];
        uint32_t ids[3];
        float w[3];
        if (t->n == 0) { /* not referenced by any triangle: never drawn */
            ids[0] = 0;
            w[0] = 1.0f;
            lc_elements_set_vertex(e, v, 1, ids, w, 0);
            continue;
        }
        /* sort the (at most 3) labels by distance, then id */
        int ord[3] = {0, 1, 2};
        for (int a = 0; a < t->n; a++)
            for (int b = a + 1; b < t->n; b++)
                if (t->d[ord[b]] < t->d[ord[a]] || (t->d[ord[b]] == t->d[ord[a]] && t->c[ord[b]] < t->c[ord[a]])) {
                    int tmp = ord[a];
                    ord[a] = ord[b];
                    ord[b] = tmp;
                }
        for (int k = 0; k < t->n; k++)
            ids[k] = t->c[ord[k]];
        int m = t->n;
        /* Shepard d^-2; on (or numerically at) a centre the weight is all its own */
        if (t->d[ord[0]] <= 1e-30f) {
            w[0] = 1.0f;
            m = 1;
        } else {
            double inv[3], sum = 0;
            for (int k = 0; k < m; k++) {
                double d = t->d[ord[k]];
                inv[k] = 1.0 / (d * d);
                sum += inv[k];
            }
            for (int k = 0; k < m; k++)
                w[k] = (float)(inv[k] / sum);
        }
        lc_elements_set_vertex(e, v, m, ids, w, ids[0]);
    }
    /* patches are adjacent when a mesh edge joins vertices of both */
    size_t npairs = 0, cap = 1024;
    pairs = malloc(cap * sizeof *pairs);
    if (!pairs)
        goto fail;
    for (uint32_t v = 0; v < n; v++) {
        uint32_t pv = e->vertex_elements[4 * (size_t)v + 3];
        for (uint32_t i = g.off[v]; i < g.off[v + 1]; i++) {
            uint32_t w = g.nbr[i];
            uint32_t pw = e->vertex_elements[4 * (size_t)w + 3];
            if (w < v || pv == pw)
                continue; /* each undirected edge once */
            if (npairs + 2 > cap) {
                cap *= 2;
                uint64_t *grown = realloc(pairs, cap * sizeof *grown);
                if (!grown)
                    goto fail;
                pairs = grown;
            }
            pairs[npairs++] = (uint64_t)pv << 32 | pw;
            pairs[npairs++] = (uint64_t)pw << 32 | pv;
        }
    }
    rc = lc_elements_adjacency_from_pairs(e, pairs, npairs, s->name, err);
    pairs = NULL;
    goto out;
fail:
    rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory building surface patches", s->name);
out:
    free(pairs);
    free(centres);
    free(near);
    free(used);
    graph_free(&g);
    return rc;
}

void lc_elements_free(lc_elements *e)
{
    if (!e)
        return;
    free(e->vertex_elements);
    free(e->vertex_weights);
    free(e->adjacency_offsets);
    free(e->adjacency);
    memset(e, 0, sizeof *e);
}

static uint32_t clamp_u64(uint64_t v, uint64_t lo, uint64_t hi) { return (uint32_t)(v < lo ? lo : v > hi ? hi : v); }

uint32_t lc_elements_default_count(const lc_element_geometry *s)
{
    if (s->type == LC_PRIM_POINTS)
        return s->vertex_count;
    if (s->type == LC_PRIM_LINES) {
        uint64_t segments = s->vertex_count > s->line_count ? (uint64_t)s->vertex_count - s->line_count : 0;
        uint64_t by_lines = (uint64_t)s->line_count * MIN_ELEMENTS_PER_LINE,
                 by_segments = segments / SEGMENTS_PER_ELEMENT;
        return clamp_u64(by_lines > by_segments ? by_lines : by_segments, DEFAULT_LINE_BUDGET, MAX_DERIVED_ELEMENTS);
    }
    uint64_t cap = s->vertex_count / VERTICES_PER_PATCH_CAP;
    cap = cap > MAX_DEFAULT_PATCHES ? (cap < MAX_DERIVED_ELEMENTS ? cap : MAX_DERIVED_ELEMENTS) : MAX_DEFAULT_PATCHES;
    return clamp_u64(s->vertex_count / 8, 1, cap);
}

void lc_elements_adjacency_weights(const lc_elements *e, const float *positions, uint32_t vertex_count, float *out)
{
    if (!e->adjacency_count)
        return;
    double *centre = calloc((size_t)e->count * 4, sizeof *centre);
    for (uint32_t v = 0; centre && v < vertex_count; v++) {
        uint32_t id = e->vertex_elements[4 * (size_t)v + 3];
        if (id >= e->count)
            continue;
        double *c = centre + 4 * (size_t)id;
        for (int k = 0; k < 3; k++)
            c[k] += positions[3 * (size_t)v + k];
        c[3] += 1;
    }
    for (uint32_t i = 0; i < e->count; i++) {
        uint32_t begin = e->adjacency_offsets[i], end = e->adjacency_offsets[i + 1];
        double sum = 0;
        int uniform = !centre || centre[4 * (size_t)i + 3] == 0;
        for (uint32_t k = begin; k < end && !uniform; k++) {
            const double *a = centre + 4 * (size_t)i, *b = centre + 4 * (size_t)e->adjacency[k];
            if (e->adjacency[k] >= e->count || b[3] == 0) {
                uniform = 1;
                break;
            }
            double d2 = 0;
            for (int c = 0; c < 3; c++) {
                double d = a[c] / a[3] - b[c] / b[3];
                d2 += d * d;
            }
            if (!(d2 > 0) || !isfinite(1.0 / d2)) {
                uniform = 1;
                break;
            }
            out[k] = (float)(1.0 / d2);
            sum += 1.0 / d2;
        }
        /* In 1/65535 steps: the GPU holds them as 16-bit unorm (gpu_scene.c). */
        for (uint32_t k = begin; k < end; k++)
            out[k] = (float)(lrint((uniform ? 1.0 / (end - begin) : out[k] / sum) * 65535.0) / 65535.0);
    }
    free(centre);
}
