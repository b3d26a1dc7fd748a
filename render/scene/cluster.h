/* Line clustering (dense line sets, DLS §3.2): lines resampled and lifted to
 * 5-D, compared by the reduced mean closest point distance, merged bottom-up
 * into a dendrogram once; cutting it into k clusters and choosing one
 * representative line per cluster is cheap and done per request.
 * Threading: a dendrogram is built by one thread; afterwards it is read-only
 * and any number of threads may cut it concurrently.
 * Ownership: lc_dendrogram_build copies what it needs from its inputs; the
 * caller frees the dendrogram with lc_dendrogram_destroy. */
#ifndef LC_CLUSTER_H
#define LC_CLUSTER_H

#include <stddef.h>
#include <stdint.h>

#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_CLUSTER_DEFAULT_SAMPLES 16
#define LC_CLUSTER_MAX_SAMPLES 64
/* Line scenes of more lines are not resampled for clustering at upload (the
 * resampled lines would hold 4 k (3 + attributes) bytes a line). */
#define LC_CLUSTER_MAX_LINES 200000u

typedef enum { LC_LINKAGE_COMPLETE = 0, LC_LINKAGE_SINGLE = 1, LC_LINKAGE_AVERAGE = 2 } lc_linkage;

/* Which line of a cluster stands in for it (DLS §3.2 "Representative
 * Selection"): the most important one (the default), the one closest to the
 * cluster's mean line, the one of least total rMCPD to the other members. */
typedef enum {
    LC_REPRESENTATIVE_IMPORTANT = 0,
    LC_REPRESENTATIVE_MEAN = 1,
    LC_REPRESENTATIVE_LEAST_DISTANCE = 2
} lc_representative;

/* Zero means default for every member. */
typedef struct lc_cluster_desc {
    int samples;        /* K points per resampled line, 2..64; 0 = 16 */
    lc_linkage linkage; /* complete (0) is DLS's recommendation */
    /* Lift weights λg, λc of DLS Eq. 2. Positions are scaled so that the
     * lines' bounding-box diagonal is 1, so a weight compares a scalar's full
     * [0,1] range with that fraction of the data's extent. */
    float lift_importance;
    float lift_color;
    /* In [0,1]: per vertex for lc_dendrogram_build, per sample (lines * k,
     * the layout of lc_line_samples.values) for lc_dendrogram_build_samples;
     * NULL: no such coordinate. */
    const float *importance;
    const float *color;
    /* Candidate pairs per line the spatial pruning aims at (0 = 96), and the
     * most clusters the pruned stage may leave for the dense top stage (0 =
     * 2048). Tests lower them to exercise both stages on small inputs. */
    uint32_t neighbours;
    uint32_t top_clusters;
    /* Above this many lines (0 = 10,000) an evenly spread sample of that many
     * is clustered and every other line attached to its nearest sampled line
     * (docs/ALGORITHM.md §19, "Sampled clustering"). */
    uint32_t sample_lines;
} lc_cluster_desc;

typedef struct lc_dendrogram lc_dendrogram;

/* Lines resampled once, k points equally spaced in arc length, so that a
 * dendrogram can be built after the scene's vertex arrays are released. */
typedef struct lc_line_samples {
    uint32_t lines;
    int k;
    int attributes;
    float *xyz;    /* lines * k * 3, scaled so the lines' bounding-box diagonal is 1 */
    float *values; /* attribute a at sample s of line i: values[(a * lines + i) * k + s] */
    float *length; /* per line, in data units */
} lc_line_samples;

/* Resamples the lines (positions 3 per vertex, line i = vertices
 * [offsets[i], offsets[i+1])) and attribute_count per-vertex attributes.
 * k = 0: 16. Returns 0, LC_ERR_INVALID (no lines, an empty line, bad k),
 * LC_ERR_NOMEM. The caller destroys *out. */
int lc_line_samples_create(const float *positions, const uint32_t *offsets, uint32_t lines, int k,
                           const float *const *attributes, int attribute_count, lc_line_samples **out, lc_error *err);
void lc_line_samples_destroy(lc_line_samples *ls);
size_t lc_line_samples_bytes(const lc_line_samples *ls);
/* What lc_line_samples_bytes will say for these counts (k = 0: 16). */
size_t lc_line_samples_estimate(uint32_t lines, int k, int attributes);

/* Build statistics, for logs and the evaluation. */
typedef struct lc_cluster_stats {
    double prune_radius;   /* r: pairs at rMCPD >= r were not linked (INFINITY: all pairs) */
    uint64_t pairs_tested; /* rMCPD evaluations */
    uint32_t top_clusters; /* clusters left for the dense top stage */
    uint32_t attempts;     /* pruned stages run (the radius grows until few enough clusters are left) */
    double seconds;
    uint32_t sampled_lines; /* 0, or the lines clustered before the others were attached */
} lc_cluster_stats;

/* Clusters resampled lines (desc->samples is ignored: ls has its own k). */
int lc_dendrogram_build_samples(const lc_line_samples *ls, const lc_cluster_desc *desc, lc_dendrogram **out,
                                lc_error *err);
/* Clusters the line_count lines of a polyline set (positions 3 per vertex,
 * line i = vertices [offsets[i], offsets[i+1])). Returns 0 or LC_ERR_INVALID
 * (no lines, bad samples or weights, offsets out of order), LC_ERR_NOMEM. */
int lc_dendrogram_build(const float *positions, const uint32_t *offsets, uint32_t line_count,
                        const lc_cluster_desc *desc, lc_dendrogram **out, lc_error *err);
void lc_dendrogram_destroy(lc_dendrogram *d);
uint32_t lc_dendrogram_lines(const lc_dendrogram *d);
void lc_dendrogram_stats(const lc_dendrogram *d, lc_cluster_stats *out);
size_t lc_dendrogram_bytes(const lc_dendrogram *d);

/* Cuts the dendrogram into min(clusters, lines) clusters (clusters >= 1):
 * labels[i] (may be NULL) gets line i's cluster in 0..k-1, numbered in the
 * order of their lowest line; representative[c] (may be NULL, k entries) the
 * line standing in for cluster c. line_importance (one value per line, may be
 * NULL) ranks lines for LC_REPRESENTATIVE_IMPORTANT; NULL uses each line's
 * mean importance from the build, or its length when the build had none.
 * Returns k, or a negative lc_status. */
int lc_dendrogram_cut(const lc_dendrogram *d, uint32_t clusters, lc_representative rep, const float *line_importance,
                      uint32_t *labels, uint32_t *representative, lc_error *err);

/* A per-line mask for the renderer: keep[i] = 1 for the k representatives,
 * 0 for every other line. Returns k or a negative lc_status. */
int lc_dendrogram_mask(const lc_dendrogram *d, uint32_t clusters, lc_representative rep, const float *line_importance,
                       uint8_t *keep, lc_error *err);

/* The rMCPD of DLS Eq. 3-4 between two lines of k samples, 5 floats each:
 * min(d'(a,b), d'(b,a)), d'(a,b) = mean over a's samples of the distance to
 * the closest sample of b. */
float lc_cluster_rmcpd(const float *a, const float *b, int k);

/* Adjusted Rand index of two labelings of n items (1 = identical partitions
 * up to renaming), for tests and the evaluation. */
double lc_cluster_adjusted_rand(const uint32_t *a, const uint32_t *b, uint32_t n);

const char *lc_linkage_name(lc_linkage l);
const char *lc_representative_name(lc_representative r);

#ifdef __cplusplus
}
#endif
#endif
