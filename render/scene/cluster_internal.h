/* Private to cluster.c and cluster_cut.c: the dendrogram's layout. Include
 * after cluster.h (not included here, so the two modules form no cycle). */
#ifndef LC_CLUSTER_INTERNAL_H
#define LC_CLUSTER_INTERNAL_H

#include <stdint.h>

#define DIM 5 /* x, y, z, lambda_g g, lambda_c c (DLS Eq. 2) */

typedef struct merge {
    uint32_t a, b; /* node ids: lines 0..m-1, merge i creates node m + i */
    float height;
} merge;

struct lc_dendrogram {
    uint32_t lines;
    int k;          /* samples per line */
    float *samples; /* lines * k * DIM, the lifted resampled lines */
    float *mean_g;  /* per line: mean importance, or length when none was given */
    merge *merges;  /* lines - 1, in the order a cut replays them (non-decreasing height, except with
                     * sampling: the attachments, then the sample's merges) */
    lc_cluster_stats stats;
};

#endif
