/* Line clustering: rMCPD by hand, jittered bundles, the Borromean rings of DLS
 * Fig. 2, the pruned stage against linking every pair, representatives. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cluster.h"
#include "demo.h"
#include "lc_test.h"

/* Brute-force rMCPD straight from DLS Eq. 3-4 (double precision). */
static double rmcpd_reference(const float *a, const float *b, int k)
{
    double d[2] = {0, 0};
    for (int dir = 0; dir < 2; dir++) {
        const float *p = dir ? b : a, *q = dir ? a : b;
        for (int i = 0; i < k; i++) {
            double best = INFINITY;
            for (int j = 0; j < k; j++) {
                double s = 0;
                for (int c = 0; c < 5; c++)
                    s += ((double)p[5 * i + c] - q[5 * j + c]) * ((double)p[5 * i + c] - q[5 * j + c]);
                best = fmin(best, sqrt(s));
            }
            d[dir] += best / k;
        }
    }
    return fmin(d[0], d[1]);
}

static uint64_t state = 12345;
static double uniform(void)
{
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(state >> 11) * 0x1.0p-53;
}

static void test_rmcpd(void)
{
    /* a: (0,0)-(1,0); b: (0,1)-(3,1). d'(a,b) = (1 + sqrt2)/2, d'(b,a) = (1 + sqrt5)/2. */
    const float a[10] = {0, 0, 0, 0, 0, 1, 0, 0, 0, 0}, b[10] = {0, 1, 0, 0, 0, 3, 1, 0, 0, 0};
    CHECK_NEAR(lc_cluster_rmcpd(a, b, 2), (1 + sqrt(2.0)) / 2, 1e-6, "rMCPD by hand");
    CHECK_NEAR(lc_cluster_rmcpd(b, a, 2), (1 + sqrt(2.0)) / 2, 1e-6, "rMCPD symmetric (by hand)");
    CHECK(lc_cluster_rmcpd(a, a, 2) == 0.0f, "rMCPD of a line with itself");
    /* The lift coordinates count: b lifted by 2 in g. d'(a,b): sqrt(1+4), sqrt(2+4); d'(b,a): sqrt5, sqrt(5+4). */
    const float c[10] = {0, 1, 0, 2, 0, 3, 1, 0, 2, 0};
    CHECK_NEAR(lc_cluster_rmcpd(a, c, 2), (sqrt(5.0) + sqrt(6.0)) / 2, 1e-6, "rMCPD with the lift by hand");
    float p[5 * 16], q[5 * 16];
    for (int t = 0; t < 20; t++) {
        for (int i = 0; i < 5 * 16; i++) {
            p[i] = (float)uniform();
            q[i] = (float)(uniform() * 2 - 0.5);
        }
        double ref = rmcpd_reference(p, q, 16);
        CHECK_NEAR(lc_cluster_rmcpd(p, q, 16), ref, 1e-5, "rMCPD against the brute force");
        CHECK(lc_cluster_rmcpd(p, q, 16) == lc_cluster_rmcpd(q, p, 16), "rMCPD symmetric");
        CHECK(lc_cluster_rmcpd(q, q, 16) == 0.0f, "rMCPD zero for identical lines");
    }
}

/* Three bundles of `per` jittered lines (a helix, a straight line, an arc)
 * with 20 vertices each; truth[i] = bundle of line i. */
#define VERTS 20
static void bundles(uint32_t per, float **pos, uint32_t **off, uint32_t *truth)
{
    uint32_t n = 3 * per;
    *pos = malloc((size_t)n * VERTS * 3 * sizeof **pos);
    *off = malloc(((size_t)n + 1) * sizeof **off);
    for (uint32_t i = 0; i <= n; i++)
        (*off)[i] = i * VERTS;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t b = i % 3; /* interleaved, so the labels are not sorted */
        truth[i] = b;
        double jx = 0.05 * (uniform() - 0.5), jy = 0.05 * (uniform() - 0.5), jz = 0.05 * (uniform() - 0.5);
        for (int v = 0; v < VERTS; v++) {
            double t = (double)v / (VERTS - 1), x, y, z;
            if (b == 0) {
                x = 0.3 * cos(6 * t);
                y = 0.3 * sin(6 * t);
                z = t;
            } else if (b == 1) {
                x = 1.5 + 0.2 * t;
                y = t;
                z = 0.5;
            } else {
                x = 0.5 + 0.8 * cos(3 * t);
                y = -1.0 + 0.8 * sin(3 * t);
                z = 0.2;
            }
            float *o = *pos + ((size_t)i * VERTS + (size_t)v) * 3;
            o[0] = (float)(x + jx);
            o[1] = (float)(y + jy);
            o[2] = (float)(z + jz);
        }
    }
}

static void test_bundles(void)
{
    enum { PER = 40, N = 3 * PER };
    uint32_t truth[N], labels[N], rep[3];
    float *pos;
    uint32_t *off;
    bundles(PER, &pos, &off, truth);
    const lc_linkage linkages[] = {LC_LINKAGE_COMPLETE, LC_LINKAGE_SINGLE, LC_LINKAGE_AVERAGE};
    for (int li = 0; li < 3; li++)
        for (int pruned = 0; pruned < 2; pruned++) {
            /* pruned: about 8 candidates per line, so the dense top stage runs too */
            lc_cluster_desc desc = {.linkage = linkages[li], .neighbours = pruned ? 8 : 0, .top_clusters = 100};
            lc_dendrogram *d = NULL;
            lc_error err = {0};
            CHECK(lc_dendrogram_build(pos, off, N, &desc, &d, &err) == 0, "build: %s", err.msg);
            if (!d)
                continue;
            lc_cluster_stats st;
            lc_dendrogram_stats(d, &st);
            if (pruned)
                CHECK(isfinite(st.prune_radius) && st.top_clusters > 1 && st.pairs_tested < (uint64_t)N * (N - 1) / 2,
                      "%s: pruning left %u clusters for the top after %llu pairs", lc_linkage_name(linkages[li]),
                      st.top_clusters, (unsigned long long)st.pairs_tested);
            CHECK(lc_dendrogram_cut(d, 3, LC_REPRESENTATIVE_MEAN, NULL, labels, rep, &err) == 3, "cut: %s", err.msg);
            double ari = lc_cluster_adjusted_rand(labels, truth, N);
            CHECK(ari == 1.0, "%s%s: adjusted Rand index %.4f", lc_linkage_name(linkages[li]),
                  pruned ? " (pruned)" : "", ari);
            for (int c = 0; c < 3; c++)
                CHECK(rep[c] < N && labels[rep[c]] == (uint32_t)c, "representative of cluster %d is a member", c);
            lc_dendrogram_destroy(d);
        }
    /* A mutation check of the index itself: a wrong partition scores below 1. */
    uint32_t wrong[N];
    memcpy(wrong, truth, sizeof wrong);
    wrong[0] = (wrong[0] + 1) % 3;
    CHECK(lc_cluster_adjusted_rand(wrong, truth, N) < 1.0, "adjusted Rand index of a wrong partition");
    free(pos);
    free(off);
}

/* Sampled clustering (lc_cluster_desc.sample_lines): the sample's cut with
 * every other line in its nearest sampled line's cluster. */
static void test_sampled(void)
{
    enum { PER = 400, N = 3 * PER, S = 150 };
    uint32_t *truth = malloc(N * sizeof *truth), *labels = malloc(N * sizeof *labels), rep[S];
    float *pos;
    uint32_t *off;
    bundles(PER, &pos, &off, truth);
    lc_cluster_desc desc = {.sample_lines = S};
    lc_dendrogram *d = NULL;
    lc_error err = {0};
    CHECK(lc_dendrogram_build(pos, off, N, &desc, &d, &err) == 0, "sampled build: %s", err.msg);
    if (d) {
        lc_cluster_stats st;
        lc_dendrogram_stats(d, &st);
        CHECK(st.sampled_lines == S, "%u lines sampled", st.sampled_lines);
        CHECK(lc_dendrogram_cut(d, 3, LC_REPRESENTATIVE_MEAN, NULL, labels, rep, &err) == 3, "cut 3: %s", err.msg);
        double ari = lc_cluster_adjusted_rand(labels, truth, N);
        CHECK(ari == 1.0, "sampled: adjusted Rand index %.4f", ari);
        /* Cut into S: one sampled line per cluster; a line's cluster is its nearest sampled line's (brute force). */
        CHECK(lc_dendrogram_cut(d, S, LC_REPRESENTATIVE_MEAN, NULL, labels, rep, &err) == S, "cut S: %s", err.msg);
        uint32_t cluster_of_sample[S], agree = 0, others = 0;
        int one_each = 1;
        uint8_t seen[S] = {0};
        for (uint32_t s = 0; s < S; s++) {
            cluster_of_sample[s] = labels[(uint64_t)s * N / S];
            one_each &= !seen[cluster_of_sample[s]]++;
        }
        CHECK(one_each, "every cluster of the cut into S holds one sampled line");
        lc_line_samples *ls = NULL;
        CHECK(lc_line_samples_create(pos, off, N, 0, NULL, 0, &ls, &err) == 0, "samples");
        uint8_t *picked = calloc(N, 1);
        for (uint32_t s = 0; s < S; s++)
            picked[(uint64_t)s * N / S] = 1;
        for (uint32_t i = 0; ls && i < N; i += 7) {
            if (picked[i])
                continue;
            others++;
            float best = INFINITY;
            uint32_t best_s = 0;
            float a[16 * 5], b[16 * 5];
            for (uint32_t s = 0; s < S; s++) {
                uint32_t l = (uint32_t)((uint64_t)s * N / S);
                for (int q = 0; q < 16; q++)
                    for (int j = 0; j < 5; j++) {
                        a[q * 5 + j] = j < 3 ? ls->xyz[((size_t)i * 16 + q) * 3 + j] : 0;
                        b[q * 5 + j] = j < 3 ? ls->xyz[((size_t)l * 16 + q) * 3 + j] : 0;
                    }
                float dd = lc_cluster_rmcpd(a, b, 16);
                if (dd < best)
                    best = dd, best_s = s;
            }
            agree += labels[i] == cluster_of_sample[best_s];
        }
        printf("sampled clustering of %d lines from %d: ARI %.3f; %u of %u checked lines in their nearest sampled "
               "line's cluster\n",
               N, S, ari, agree, others);
        CHECK(others > 100 && agree >= 0.95 * others, "attached to the nearest sampled line: %u of %u", agree, others);
        free(picked);
        lc_line_samples_destroy(ls);
        lc_dendrogram_destroy(d);
    }
    free(truth);
    free(labels);
    free(pos);
    free(off);
}

/* Representatives: the most important line, and least total distance by brute force. */
static void test_representatives(void)
{
    enum { PER = 30, N = 3 * PER };
    uint32_t truth[N], labels[N], rep[3];
    float *pos, importance[N];
    uint32_t *off;
    bundles(PER, &pos, &off, truth);
    for (uint32_t i = 0; i < N; i++)
        importance[i] = (float)uniform();
    lc_dendrogram *d = NULL;
    lc_error err = {0};
    CHECK(lc_dendrogram_build(pos, off, N, NULL, &d, &err) == 0, "build: %s", err.msg);
    if (!d)
        return;
    CHECK(lc_dendrogram_cut(d, 3, LC_REPRESENTATIVE_IMPORTANT, importance, labels, rep, &err) == 3, "cut");
    for (int c = 0; c < 3; c++) {
        float best = -1;
        uint32_t arg = 0;
        for (uint32_t i = 0; i < N; i++)
            if (labels[i] == (uint32_t)c && importance[i] > best) {
                best = importance[i];
                arg = i;
            }
        CHECK(rep[c] == arg, "most important representative of cluster %d: %u, want %u", c, rep[c], arg);
    }
    /* Least distance: recompute each member's total rMCPD from a fresh
     * resampling (a build with the same input keeps the same samples). */
    CHECK(lc_dendrogram_cut(d, 3, LC_REPRESENTATIVE_LEAST_DISTANCE, NULL, labels, rep, &err) == 3, "cut");
    uint32_t keep_labels[N];
    memcpy(keep_labels, labels, sizeof keep_labels);
    uint8_t keep[N];
    CHECK(lc_dendrogram_mask(d, 3, LC_REPRESENTATIVE_LEAST_DISTANCE, NULL, keep, &err) == 3, "mask");
    int kept = 0;
    for (uint32_t i = 0; i < N; i++)
        kept += keep[i];
    CHECK(kept == 3 && keep[rep[0]] && keep[rep[1]] && keep[rep[2]], "mask keeps exactly the representatives");
    /* Cutting into as many clusters as lines keeps every line; more is clamped. */
    uint8_t all[N];
    CHECK(lc_dendrogram_mask(d, 10 * N, LC_REPRESENTATIVE_IMPORTANT, NULL, all, &err) == N, "cut beyond the lines");
    kept = 0;
    for (uint32_t i = 0; i < N; i++)
        kept += all[i];
    CHECK(kept == N, "every line is its own cluster's representative");
    CHECK(lc_dendrogram_cut(d, 0, LC_REPRESENTATIVE_IMPORTANT, NULL, NULL, NULL, &err) == LC_ERR_INVALID,
          "zero clusters rejected");
    lc_dendrogram_destroy(d);
    free(pos);
    free(off);
}

/* The pruned stage is exact for complete linkage below its radius: any cut
 * into at least as many clusters as it left equals the all-pairs result. */
static void test_pruning_exact(void)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    lc_demo_desc dd = {.count = 300};
    CHECK(lc_demo_create("tornado", &dd, &s, &err) == 0, "tornado: %s", err.msg);
    if (!s)
        return;
    lc_dendrogram *dense = NULL, *pruned = NULL;
    lc_cluster_desc a = {0}, b = {.neighbours = 24, .top_clusters = 250};
    CHECK(lc_dendrogram_build(s->positions, s->line_offsets, s->line_count, &a, &dense, &err) == 0, "dense");
    CHECK(lc_dendrogram_build(s->positions, s->line_offsets, s->line_count, &b, &pruned, &err) == 0, "pruned");
    if (dense && pruned) {
        lc_cluster_stats st;
        lc_dendrogram_stats(pruned, &st);
        CHECK(isfinite(st.prune_radius) && st.top_clusters > 1, "pruned build left %u clusters", st.top_clusters);
        uint32_t n = s->line_count, *la = malloc(n * sizeof *la), *lb = malloc(n * sizeof *lb);
        for (uint32_t k = st.top_clusters; k <= n; k += (n - st.top_clusters) / 5 + 1) {
            lc_dendrogram_cut(dense, k, LC_REPRESENTATIVE_IMPORTANT, NULL, la, NULL, &err);
            lc_dendrogram_cut(pruned, k, LC_REPRESENTATIVE_IMPORTANT, NULL, lb, NULL, &err);
            CHECK(lc_cluster_adjusted_rand(la, lb, n) == 1.0, "cut into %u: pruned differs from all pairs", k);
        }
        free(la);
        free(lb);
    }
    lc_dendrogram_destroy(dense);
    lc_dendrogram_destroy(pruned);
    lc_scene_destroy(s);
}

/* DLS Fig. 2: with the importance lifted by λg > 0.5 the ring cores (the
 * important lines) form clusters of their own, each ring at least one, so the
 * representatives trace the rings; without the lift every cluster of a core
 * line also holds lines around it. Returns the clusters mixing core and other
 * lines, and the rings with a cluster of only their own core lines. */
static void borromean_clusters(const lc_scene *s, float lift, int *mixed, int *rings_alone)
{
    int gi = lc_scene_find_attribute(s, "ring_proximity"), ri = lc_scene_find_attribute(s, "ring");
    lc_cluster_desc desc = {.lift_importance = lift, .importance = s->attributes[gi].values};
    lc_dendrogram *d = NULL;
    lc_error err = {0};
    *mixed = *rings_alone = -1;
    CHECK(lc_dendrogram_build(s->positions, s->line_offsets, s->line_count, &desc, &d, &err) == 0, "build");
    if (!d)
        return;
    uint32_t n = s->line_count, *lab = malloc(n * sizeof *lab);
    int k = lc_dendrogram_cut(d, 25, LC_REPRESENTATIVE_LEAST_DISTANCE, NULL, lab, NULL, &err);
    CHECK(k == 25, "25 clusters");
    uint32_t counts[25][4] = {{0}}; /* per cluster: core lines of rings 0..2, other lines */
    for (uint32_t i = 0; i < n && k == 25; i++) {
        uint32_t v = s->line_offsets[i];
        int core = s->attributes[gi].values[v] > 0.5f, ring = (int)s->attributes[ri].values[v];
        counts[lab[i]][core ? ring : 3]++;
    }
    int alone[3] = {0, 0, 0};
    *mixed = 0;
    for (int c = 0; c < 25; c++) {
        int rings = (counts[c][0] > 0) + (counts[c][1] > 0) + (counts[c][2] > 0);
        *mixed += rings > 0 && counts[c][3] > 0;
        for (int q = 0; q < 3; q++)
            alone[q] |= rings == 1 && counts[c][q] > 0 && counts[c][3] == 0;
    }
    *rings_alone = alone[0] + alone[1] + alone[2];
    free(lab);
    lc_dendrogram_destroy(d);
}

static void test_borromean(void)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    CHECK(lc_demo_create("borromean", NULL, &s, &err) == 0, "borromean: %s", err.msg);
    if (!s)
        return;
    CHECK(s->line_count == 600, "600 lines");
    const float lifts[] = {0.6f, 1.0f};
    for (int i = 0; i < 2; i++) {
        int mixed, alone;
        borromean_clusters(s, lifts[i], &mixed, &alone);
        CHECK(mixed == 0 && alone == 3, "λg %.1f: %d clusters mix core and other lines, %d rings stand alone", lifts[i],
              mixed, alone);
    }
    int mixed, alone;
    borromean_clusters(s, 0.0f, &mixed, &alone);
    CHECK(mixed >= 12 && alone == 0, "λg 0: %d clusters mix core and other lines, %d rings stand alone", mixed, alone);
    lc_scene_destroy(s);
}

int main(void)
{
    test_rmcpd();
    test_bundles();
    test_sampled();
    test_representatives();
    test_pruning_exact();
    test_borromean();
    return lc_test_finish();
}
