/* Sampled clustering's attachment step (cluster_sample.c), private to
 * render/scene/cluster*.c. */
#ifndef LC_CLUSTER_SAMPLE_H
#define LC_CLUSTER_SAMPLE_H

#include <stdint.h>

/* For every line i of `lines` (soa: the lines by coordinate, k samples), the
 * sampled line (index into pick[0..samples)) nearest by rMCPD among the 64
 * whose centroids are nearest (of rings of grid cells holding at least 32), into
 * nearest[i] and its distance into dist[i]; a sampled line answers itself at
 * 0. *pairs: rMCPDs measured. Returns 0 or -1 (out of memory). */
int lc_cluster_attach(const float *soa, uint32_t lines, int k, const uint32_t *pick, uint32_t samples, uint32_t threads,
                      uint32_t *nearest, float *dist, uint64_t *pairs);

#endif
