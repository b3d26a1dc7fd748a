/* Beyond the sampled-clustering threshold (lc_cluster_desc.sample_lines):
 * each line not in the sample is attached to its nearest sampled line by
 * rMCPD, searched among the sampled lines whose centroids are nearest (a
 * uniform grid of the centroids, rings of cells until enough candidates).
 * Threads take every T-th line. */
#include "cluster_sample.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cluster_distance.h"
#include "lc_parallel.h"

#define CANDIDATES 32 /* sampled lines gathered by centroid before the search stops widening */
#define MEASURED 64   /* of those, the nearest by centroid are measured by rMCPD */

typedef struct cand {
    float d2; /* squared centroid distance */
    uint32_t s;
} cand;

/* Keeps the MEASURED nearest candidates in a max-heap on d2 (ties: larger index on top). */
static int cand_above(const cand *x, const cand *y) { return x->d2 > y->d2 || (x->d2 == y->d2 && x->s > y->s); }

static void cand_offer(cand *h, uint32_t *n, cand c)
{
    uint32_t i;
    if (*n < MEASURED) {
        i = (*n)++;
        while (i > 0 && cand_above(&c, &h[(i - 1) / 2])) {
            h[i] = h[(i - 1) / 2];
            i = (i - 1) / 2;
        }
        h[i] = c;
        return;
    }
    if (!cand_above(&h[0], &c))
        return;
    i = 0;
    for (;;) { /* replace the top and sift down */
        uint32_t l = 2 * i + 1, m = l;
        if (l >= *n)
            break;
        if (l + 1 < *n && cand_above(&h[l + 1], &h[l]))
            m = l + 1;
        if (!cand_above(&h[m], &c))
            break;
        h[i] = h[m];
        i = m;
    }
    h[i] = c;
}

typedef struct grid {
    int g;             /* cells per side */
    float lo[3], cell; /* origin and cell size */
    uint32_t *start;   /* g^3 + 1 offsets into idx */
    uint32_t *idx;     /* sample indices by cell */
} grid;

static void centroid(const float *soa, int k, float *c)
{
    for (int j = 0; j < 3; j++) {
        double s = 0;
        for (int i = 0; i < k; i++)
            s += soa[j * k + i];
        c[j] = (float)(s / k);
    }
}

static int cell_of(const grid *gr, const float *c, int j)
{
    int x = (int)floorf((c[j] - gr->lo[j]) / gr->cell);
    return x < 0 ? 0 : x >= gr->g ? gr->g - 1 : x;
}

typedef struct attach_job {
    const float *soa;
    int k;
    uint32_t lines, first, step;
    const uint32_t *pick, *slot; /* slot[line] = its sample index or UINT32_MAX */
    uint32_t samples;
    const grid *gr;
    const float *cent; /* centroids of the samples */
    uint32_t *nearest;
    float *dist;
    uint64_t pairs;
} attach_job;

static void attach_run(void *arg)
{
    attach_job *w = arg;
    const grid *gr = w->gr;
    size_t stride = (size_t)w->k * KERNEL_DIM;
    uint32_t want = w->samples < CANDIDATES ? w->samples : CANDIDATES;
    for (uint32_t i = w->first; i < w->lines; i += w->step) {
        if (w->slot[i] != UINT32_MAX) {
            w->nearest[i] = w->slot[i];
            w->dist[i] = 0;
            continue;
        }
        const float *a = w->soa + i * stride;
        float c[3];
        centroid(a, w->k, c);
        int cx = cell_of(gr, c, 0), cy = cell_of(gr, c, 1), cz = cell_of(gr, c, 2);
        float best = INFINITY;
        uint32_t best_s = 0, seen = 0, held = 0;
        cand heap[MEASURED];
        /* Rings of cells around the line's: until `want` candidates, then one ring more. */
        int last = -1;
        for (int ring = 0; ring < gr->g && (last < 0 || ring <= last); ring++) {
            for (int z = cz - ring; z <= cz + ring; z++)
                for (int y = cy - ring; y <= cy + ring; y++)
                    for (int x = cx - ring; x <= cx + ring; x++) {
                        if (x < 0 || y < 0 || z < 0 || x >= gr->g || y >= gr->g || z >= gr->g)
                            continue;
                        if (abs(x - cx) != ring && abs(y - cy) != ring && abs(z - cz) != ring)
                            continue; /* inner cells: seen in an earlier ring */
                        size_t cell = ((size_t)z * gr->g + y) * gr->g + x;
                        for (uint32_t q = gr->start[cell]; q < gr->start[cell + 1]; q++) {
                            uint32_t s = gr->idx[q];
                            const float *e = w->cent + 3 * s;
                            float d0 = e[0] - c[0], d1 = e[1] - c[1], d2 = e[2] - c[2];
                            cand_offer(heap, &held, (cand){d0 * d0 + d1 * d1 + d2 * d2, s});
                            seen++;
                        }
                    }
            if (last < 0 && seen >= want)
                last = ring + 1;
        }
        for (uint32_t h = 0; h < held; h++) {
            uint32_t s = heap[h].s;
            float d = lc_cluster_rmcpd_below(a, w->soa + (size_t)w->pick[s] * stride, w->k, best);
            w->pairs++;
            if (d < best || (d == best && s < best_s))
                best = d, best_s = s;
        }
        w->nearest[i] = best_s;
        w->dist[i] = best;
    }
}

int lc_cluster_attach(const float *soa, uint32_t lines, int k, const uint32_t *pick, uint32_t samples, uint32_t threads,
                      uint32_t *nearest, float *dist, uint64_t *pairs)
{
    size_t stride = (size_t)k * KERNEL_DIM;
    grid gr = {0};
    gr.g = (int)ceil(cbrt(samples / 4.0));
    gr.g = gr.g < 1 ? 1 : gr.g > 64 ? 64 : gr.g;
    size_t cells = (size_t)gr.g * gr.g * gr.g;
    float *cent = malloc((size_t)samples * 3 * sizeof *cent);
    uint32_t *slot = malloc((size_t)lines * sizeof *slot), *cell_id = malloc((size_t)samples * sizeof *cell_id);
    gr.start = calloc(cells + 1, sizeof *gr.start);
    gr.idx = malloc((size_t)samples * sizeof *gr.idx);
    int rc = -1;
    if (!cent || !slot || !cell_id || !gr.start || !gr.idx)
        goto out;
    float hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    gr.lo[0] = gr.lo[1] = gr.lo[2] = FLT_MAX;
    for (uint32_t s = 0; s < samples; s++) {
        centroid(soa + (size_t)pick[s] * stride, k, cent + 3 * s);
        for (int j = 0; j < 3; j++) {
            gr.lo[j] = fminf(gr.lo[j], cent[3 * s + j]);
            hi[j] = fmaxf(hi[j], cent[3 * s + j]);
        }
    }
    float ext = fmaxf(fmaxf(hi[0] - gr.lo[0], hi[1] - gr.lo[1]), hi[2] - gr.lo[2]);
    gr.cell = ext > 0 ? ext / gr.g * 1.0001f : 1.0f;
    for (uint32_t s = 0; s < samples; s++) {
        const float *c = cent + 3 * s;
        cell_id[s] = (uint32_t)(((size_t)cell_of(&gr, c, 2) * gr.g + cell_of(&gr, c, 1)) * gr.g + cell_of(&gr, c, 0));
        gr.start[cell_id[s] + 1]++;
    }
    for (size_t c = 0; c < cells; c++)
        gr.start[c + 1] += gr.start[c];
    uint32_t *fill = malloc(cells * sizeof *fill);
    if (!fill)
        goto out;
    memcpy(fill, gr.start, cells * sizeof *fill);
    for (uint32_t s = 0; s < samples; s++)
        gr.idx[fill[cell_id[s]]++] = s;
    free(fill);
    for (uint32_t i = 0; i < lines; i++)
        slot[i] = UINT32_MAX;
    for (uint32_t s = 0; s < samples; s++)
        slot[pick[s]] = s;
    enum { MAX_JOBS = 8 };
    attach_job jobs[MAX_JOBS];
    threads = threads < 1 ? 1 : threads > MAX_JOBS ? MAX_JOBS : threads;
    for (uint32_t t = 0; t < threads; t++)
        jobs[t] = (attach_job){soa, k, lines, t, threads, pick, slot, samples, &gr, cent, nearest, dist, 0};
    lc_parallel_for(threads, attach_run, jobs, sizeof jobs[0]);
    *pairs = 0;
    for (uint32_t t = 0; t < threads; t++)
        *pairs += jobs[t].pairs;
    rc = 0;
out:
    free(cent);
    free(slot);
    free(cell_id);
    free(gr.start);
    free(gr.idx);
    return rc;
}
