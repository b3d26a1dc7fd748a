/* The clustering's distance kernels (cluster_distance.c), private to
 * render/scene/cluster*.c. */
#ifndef LC_CLUSTER_DISTANCE_H
#define LC_CLUSTER_DISTANCE_H

/* The kernels on lines stored by coordinate (SoA,
 * DIM rows of k floats; lc_cluster_transpose from the AoS samples). k is at
 * most KERNEL_MAX_K (LC_CLUSTER_MAX_SAMPLES); KERNEL_FAST_K
 * (LC_CLUSTER_DEFAULT_SAMPLES) gets code specialized for it. */
#define KERNEL_MAX_K 64
#define KERNEL_FAST_K 16
#define KERNEL_DIM 5 /* DIM of cluster_internal.h */
void lc_cluster_transpose(const float *aos, int k, float *soa);
float lc_cluster_rmcpd_soa(const float *a, const float *b, int k);
/* The rMCPD when below r, else INFINITY (early exits). */
float lc_cluster_rmcpd_below(const float *a, const float *b, int k, float r);
/* A lower bound of the rMCPD from each line's samples to the other's 5-D box
 * (lo, hi: DIM floats); may stop early with a smaller value once below r. */
float lc_cluster_lower_bound(const float *a, const float *alo, const float *ahi, const float *b, const float *blo,
                             const float *bhi, int k, float r);

#endif
