/* Dendrogram cuts: labels, representatives (most important, mean line, least
 * total distance), the renderer's per-line mask, and the adjusted Rand index. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cluster.h"
#include "cluster_internal.h"

/* Least-distance representatives compare each member with at most this many
 * members of its cluster (evenly spread), so a cut stays O(lines). */
#define LEAST_DISTANCE_SAMPLE 64u

/* ---- cuts and representatives */

static uint32_t find_root(uint32_t *p, uint32_t x)
{
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

int lc_dendrogram_cut(const lc_dendrogram *d, uint32_t clusters, lc_representative rep, const float *line_importance,
                      uint32_t *labels, uint32_t *representative, lc_error *err)
{
    if (!d || clusters == 0)
        return lc_err(err, LC_ERR_INVALID, "clusters must be at least 1");
    if (rep != LC_REPRESENTATIVE_IMPORTANT && rep != LC_REPRESENTATIVE_MEAN && rep != LC_REPRESENTATIVE_LEAST_DISTANCE)
        return lc_err(err, LC_ERR_INVALID, "unknown representative %d", (int)rep);
    uint32_t m = d->lines, k = clusters < m ? clusters : m;
    size_t stride = (size_t)d->k * DIM;
    uint32_t *p = malloc((size_t)(2 * m - 1) * sizeof *p), *lab = malloc((size_t)m * sizeof *lab);
    uint32_t *id = malloc((size_t)(2 * m - 1) * sizeof *id), *count = calloc(k, sizeof *count);
    uint32_t *rp = malloc((size_t)k * sizeof *rp);
    float *score = malloc((size_t)k * sizeof *score), *mean = NULL;
    int rc = -1;
    if (!p || !lab || !id || !count || !rp || !score)
        goto out;
    for (uint32_t i = 0; i < 2 * m - 1; i++) {
        p[i] = i;
        id[i] = UINT32_MAX;
    }
    /* The first m - k merges, in order, leave exactly k clusters. */
    for (uint32_t i = 0; i < m - k; i++) {
        p[d->merges[i].a] = m + i;
        p[d->merges[i].b] = m + i;
    }
    uint32_t next = 0;
    for (uint32_t i = 0; i < m; i++) {
        uint32_t r = find_root(p, i);
        if (id[r] == UINT32_MAX)
            id[r] = next++;
        lab[i] = id[r];
        count[lab[i]]++;
    }
    for (uint32_t c = 0; c < k; c++) {
        score[c] = -FLT_MAX;
        rp[c] = UINT32_MAX;
    }
    if (rep == LC_REPRESENTATIVE_IMPORTANT) {
        const float *g = line_importance ? line_importance : d->mean_g;
        for (uint32_t i = 0; i < m; i++)
            if (rp[lab[i]] == UINT32_MAX || g[i] > score[lab[i]]) {
                score[lab[i]] = g[i];
                rp[lab[i]] = i;
            }
    } else if (rep == LC_REPRESENTATIVE_MEAN) {
        mean = calloc((size_t)k * stride, sizeof *mean);
        if (!mean)
            goto out;
        for (uint32_t i = 0; i < m; i++)
            for (size_t j = 0; j < stride; j++)
                mean[lab[i] * stride + j] += d->samples[i * stride + j] / (float)count[lab[i]];
        for (uint32_t i = 0; i < m; i++) {
            float e = 0;
            for (size_t j = 0; j < stride; j++) {
                float t = d->samples[i * stride + j] - mean[lab[i] * stride + j];
                e += t * t;
            }
            if (rp[lab[i]] == UINT32_MAX || -e > score[lab[i]]) {
                score[lab[i]] = -e;
                rp[lab[i]] = i;
            }
        }
    } else {
        /* Members of each cluster, listed by a counting sort on the labels;
         * each member's total distance to (a spread sample of) the others. */
        uint32_t *start = calloc((size_t)k + 1, sizeof *start), *member = malloc((size_t)m * sizeof *member);
        if (!start || !member) {
            free(start);
            free(member);
            goto out;
        }
        for (uint32_t c = 0; c < k; c++)
            start[c + 1] = start[c] + count[c];
        for (uint32_t c = 0; c < k; c++)
            count[c] = 0;
        for (uint32_t i = 0; i < m; i++)
            member[start[lab[i]] + count[lab[i]]++] = i;
        for (uint32_t c = 0; c < k; c++) {
            uint32_t n = count[c], s = n < LEAST_DISTANCE_SAMPLE ? n : LEAST_DISTANCE_SAMPLE;
            for (uint32_t a = 0; a < n; a++) {
                uint32_t i = member[start[c] + a];
                double total = 0;
                for (uint32_t b = 0; b < s; b++) {
                    uint32_t j = member[start[c] + (uint32_t)((uint64_t)b * n / s)];
                    if (j != i)
                        total += lc_cluster_rmcpd(d->samples + i * stride, d->samples + j * stride, d->k);
                }
                if (rp[c] == UINT32_MAX || -(float)total > score[c]) {
                    score[c] = -(float)total;
                    rp[c] = i;
                }
            }
        }
        free(start);
        free(member);
    }
    if (labels)
        memcpy(labels, lab, (size_t)m * sizeof *lab);
    if (representative)
        memcpy(representative, rp, (size_t)k * sizeof *rp);
    rc = (int)k;
out:
    free(p);
    free(lab);
    free(id);
    free(count);
    free(rp);
    free(score);
    free(mean);
    if (rc < 0)
        return lc_err(err, LC_ERR_NOMEM, "clustering: out of memory cutting %u lines", m);
    return rc;
}

int lc_dendrogram_mask(const lc_dendrogram *d, uint32_t clusters, lc_representative rep, const float *line_importance,
                       uint8_t *keep, lc_error *err)
{
    if (!d)
        return lc_err(err, LC_ERR_INVALID, "no dendrogram");
    uint32_t k = clusters < d->lines ? clusters : d->lines;
    uint32_t *rp = malloc((size_t)(k ? k : 1) * sizeof *rp);
    if (!rp)
        return lc_err(err, LC_ERR_NOMEM, "clustering: out of memory");
    int n = lc_dendrogram_cut(d, clusters, rep, line_importance, NULL, rp, err);
    if (n > 0) {
        memset(keep, 0, d->lines);
        for (int c = 0; c < n; c++)
            keep[rp[c]] = 1;
    }
    free(rp);
    return n;
}

/* ---- adjusted Rand index (Hubert & Arabie 1985) */

double lc_cluster_adjusted_rand(const uint32_t *a, const uint32_t *b, uint32_t n)
{
    uint32_t ka = 0, kb = 0;
    for (uint32_t i = 0; i < n; i++) {
        ka = a[i] + 1 > ka ? a[i] + 1 : ka;
        kb = b[i] + 1 > kb ? b[i] + 1 : kb;
    }
    double *t = calloc((size_t)ka * kb, sizeof *t), *ra = calloc(ka, sizeof *ra), *rb = calloc(kb, sizeof *rb);
    double result = NAN;
    if (t && ra && rb) {
        for (uint32_t i = 0; i < n; i++) {
            t[(size_t)a[i] * kb + b[i]] += 1;
            ra[a[i]] += 1;
            rb[b[i]] += 1;
        }
        double sij = 0, sa = 0, sb = 0;
        for (size_t i = 0; i < (size_t)ka * kb; i++)
            sij += t[i] * (t[i] - 1) / 2;
        for (uint32_t i = 0; i < ka; i++)
            sa += ra[i] * (ra[i] - 1) / 2;
        for (uint32_t i = 0; i < kb; i++)
            sb += rb[i] * (rb[i] - 1) / 2;
        double pairs = (double)n * (n - 1) / 2, expected = pairs > 0 ? sa * sb / pairs : 0;
        double top = (sa + sb) / 2;
        result = top - expected != 0 ? (sij - expected) / (top - expected) : 1.0;
    }
    free(t);
    free(ra);
    free(rb);
    return result;
}

const char *lc_representative_name(lc_representative r)
{
    return r == LC_REPRESENTATIVE_MEAN ? "mean" : r == LC_REPRESENTATIVE_LEAST_DISTANCE ? "leastDistance" : "important";
}
