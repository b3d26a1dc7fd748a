/* Scale-out over MPI (docs/MPI.md): start-up checks that every rank agrees,
 * the split of each dataset into per-rank shards, the renderer's reduction
 * hook (lc_reducer) over MPI collectives, and the per-frame broadcast with
 * which rank 0 of `lucent serve --mpi` leads the other ranks.
 * Built with MPI only when LUCENT_MPI is on; otherwise every call fails with a
 * message saying so (lc_mpi_none.c), and the rest of the binary is the same.
 * Threading: MPI is started with MPI_THREAD_MULTIPLE, but the collectives of
 * one lc_mpi must come from one thread at a time, in the same order on every
 * rank (the render thread during frames, the main thread before and after). */
#ifndef LC_MPI_H
#define LC_MPI_H

#include <stdio.h>

#include "lc_base.h"
#include "renderer.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_mpi lc_mpi;

/* 1 when this binary was built with MPI. */
int lc_mpi_available(void);
/* Starts MPI. A collective that waits longer than LUCENT_MPI_TIMEOUT seconds
 * (default 60) for the other ranks aborts the job with a message naming it. */
int lc_mpi_init(lc_mpi **out, lc_error *err);
/* Ends MPI (MPI_Finalize) and frees m. Collective. */
void lc_mpi_finalize(lc_mpi *m);
/* Logs msg on this rank and ends every rank of the job (MPI_Abort), after
 * the hook of lc_mpi_on_abort (if any) has run and had half a second. */
void lc_mpi_abort(lc_mpi *m, int code, const char *msg);
/* Runs hook(ctx, msg) once on this rank before lc_mpi_abort ends the job: the
 * daemon answers the requests in hand with msg instead of a closed connection.
 * NULL clears it. The hook runs on whichever thread aborts (a watchdog, the
 * exit guard, a reduction) and must not wait for the renderer. */
void lc_mpi_on_abort(lc_mpi *m, void (*hook)(void *ctx, const char *msg), void *ctx);
/* Milliseconds this rank spent in reductions since the last call: waiting for
 * the slowest rank (measured only with LUCENT_MPI_PROFILE=1, else 0 and
 * counted as transfer) and transferring/combining; resets both. */
void lc_mpi_profile(lc_mpi *m, double *wait_ms, double *transfer_ms);
int lc_mpi_rank(const lc_mpi *m);
int lc_mpi_size(const lc_mpi *m);
/* The reduction hook for lc_renderer_set_reducer; valid until finalize. */
const lc_reducer *lc_mpi_reducer(lc_mpi *m);

/* Collective: every rank passes its own status (0 = ok) and error. Returns 0
 * when all succeeded; otherwise the status of the lowest failing rank, with
 * err = "rank R: its message" on every rank. */
int lc_mpi_agree(lc_mpi *m, int rc, lc_error *err);
/* 1 once an lc_mpi_agree has returned a failure: every rank learnt it at the
 * same collective, so each may end without another agreement (a rank that
 * failed on its own still needs one to tell the others). */
int lc_mpi_agreed_failure(const lc_mpi *m);
/* Collective: LC_ERR_INVALID unless every rank passes the same text (e.g. its
 * dataset list); err then names a differing rank and both texts (cut). */
int lc_mpi_check_same(lc_mpi *m, const char *what, const char *text, lc_error *err);
/* Collective: replaces *scene (finalized, the whole dataset) with this rank's
 * shard (lc_scene_shard) and reports each rank's scene memory on rank 0: to
 * report (one line per rank) or, when NULL, in the log. A failure on any rank
 * fails every rank (lc_mpi_agree). */
int lc_mpi_shard(lc_mpi *m, lc_scene **scene, FILE *report, lc_error *err);
/* Collective: finishes this rank's part of a line file or point cloud, read with
 * lc_scene_read_file_part(path, rank, size) (read_rc its status; on failure
 * *scene is destroyed if set), together with the other ranks
 * (lc_scene_finalize_part) with `elements` line elements (0 = derived from
 * the whole). The result is what lc_mpi_shard gives from the whole file,
 * without any rank holding the whole; the part keeps this lc_mpi's
 * collectives for later element rebuilds. Reports as lc_mpi_shard does. */
int lc_mpi_finalize_part(lc_mpi *m, int read_rc, lc_scene **scene, uint32_t elements, FILE *report, lc_error *err);

/* ---- Serve: rank 0 leads, the others follow. */
/* Rank 0: announces the next frame to the other ranks (dataset indices in the
 * registry, parameters, the viewer's fading history) before its own
 * lc_render_frame of datasets[0] (layer_count 0) or lc_render_layers of the
 * layer_count layers over datasets[0..layer_count) with the same arguments.
 * element_count: the state's size (the layers' sum). */
int lc_mpi_frame_announce(lc_mpi *m, const int *datasets, const lc_layer_params *layers, int layer_count,
                          uint32_t element_count, const lc_render_params *p, const lc_frame_state *state, double dt,
                          lc_error *err);
/* Rank 0: tells the followers to leave lc_mpi_follow (once, at shutdown). */
int lc_mpi_stop_followers(lc_mpi *m, lc_error *err);
/* Ranks > 0: renders every announced frame with r (its reducer set) on
 * scenes[dataset] (or the layers over theirs) until rank 0 stops; the image
 * stays on rank 0. element_counts[i]: the elements of scenes[i]. What arrives
 * is checked (layer count, dataset indices, roles, the state's size against
 * the datasets' elements). Returns 0 after the stop, or the error that ended
 * the loop. */
int lc_mpi_follow(lc_mpi *m, lc_renderer *r, const lc_gpu_scene *const *scenes, const uint32_t *element_counts,
                  int count, lc_error *err);
/* After a shutdown signal: ends the job with a message if this process has
 * not exited `seconds` from now (a rank that died leaves a collective waiting). */
void lc_mpi_exit_guard(lc_mpi *m, double seconds);

#ifdef __cplusplus
}
#endif
#endif
