/* `lucent serve --mpi` (docs/MPI.md): rank 0 runs HTTP, WebSocket and the
 * encoders with one render worker, and announces each frame to the other
 * ranks, which render their shards of it and join the reductions. */
#ifndef LC_SERVE_MPI_H
#define LC_SERVE_MPI_H

#include "datasets.h"
#include "gl_context.h"
#include "server.h"

/* Start-up, after the datasets loaded (load_rc = that status, err its error):
 * every rank must have loaded, and the same dataset list; then each dataset
 * becomes this rank's shard. Collective; a failure anywhere fails every rank
 * with a message naming the rank. Thread: main. */
int lc_serve_mpi_start(lc_server *srv, int load_rc, lc_error *err);
/* lc_datasets_options.read_part (ctx: the lc_mpi): this rank's share of a
 * line file or point cloud, read (lc_scene_read_file_part) and finalized with
 * the other ranks (lc_mpi_finalize_part). */
int lc_serve_mpi_read_part(void *ctx, const char *path, lc_scene **out, lc_error *err);
/* Ranks > 0 after the upload: render the announced frames on primary until
 * rank 0 stops. Thread: main, primary current. */
int lc_serve_mpi_follow(lc_server *srv, lc_gl *primary, lc_error *err);
/* Rank 0 at shutdown, after the workers stopped: releases the followers. */
void lc_serve_mpi_stop(lc_server *srv);
/* Every frame of a render worker: lc_render_frame, announced first to the
 * other ranks under --mpi. Thread: the render worker. */
int lc_server_render_frame(lc_server *srv, lc_renderer *r, const lc_dataset *ds, const lc_render_params *p,
                           lc_frame_state *state, double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err);

#endif
