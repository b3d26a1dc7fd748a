/* Parts of a scene read by several processes (docs/MPI.md "Loading"): each
 * process holds only its share of the vertices, read from the file, and
 * finalizes it together with the others through a few collective operations,
 * so that bounds, attribute ranges and percentiles, derived attributes and
 * the element numbering come out exactly as lc_scene_finalize gives them for
 * the whole scene followed by lc_scene_shard.
 * The scene layer knows nothing of MPI: the caller supplies the collectives
 * (server/mpi implements them with MPI). Every process must call
 * lc_scene_finalize_part with parts of the same file, in the same order as
 * its other collectives. Points and lines only; surfaces are split after
 * loading (lc_scene_shard), since their patches are built over the whole mesh. */
#ifndef LC_SCENE_PART_H
#define LC_SCENE_PART_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Collective operations over all processes (each returns 0 or an error with
 * err set; a failure need not return at all: the implementation may end the
 * job). */
typedef struct lc_scene_collective {
    void *ctx;
    int rank, size;
    /* Every process passes its status; returns 0 when all are 0, else the
     * lowest failing process's status with err naming it, on every process. */
    int (*agree)(void *ctx, int rc, lc_error *err);
    /* Element-wise sum or minimum of v[0..n) over all processes, in place
     * (a maximum is the minimum of the negated values). */
    int (*sum_u64)(void *ctx, uint64_t *v, size_t n, lc_error *err);
    int (*min_f64)(void *ctx, double *v, size_t n, lc_error *err);
    /* Every process's `bytes` bytes at mine, concatenated in process order into
     * *all, and process r's count in (*bytes_of)[r] (both malloc'd; the caller
     * frees them; an implementation that cannot allocate them ends the job). */
    int (*gather)(void *ctx, const void *mine, size_t bytes, void **all, uint64_t **bytes_of, lc_error *err);
} lc_scene_collective;

/* Finalizes the part s (un-finalized, as a reader left it: this process's
 * whole lines or contiguous points) as its share of the whole scene: global
 * bounds, attribute min/max, percentiles and auto range, derived line
 * attributes, default mappings, and the elements of the whole scene's
 * numbering with desc's budget (0 = derived from the whole), their adjacency
 * complete on every process. A part may be empty. Collective: every process
 * calls it, and returns the same status (err names the failing process). */
int lc_scene_finalize_part(lc_scene *s, const lc_elements_desc *desc, const lc_scene_collective *c, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
