/* `lucent serve --mpi` (docs/MPI.md): rank 0 runs HTTP, WebSocket and the
 * encoders with one render worker, and announces each frame to the other
 * ranks, which render their shards of it and join the reductions. This room
 * alone speaks MPI (server/mpi); the rest of the daemon sees the frame hook it
 * sets (server.h) and these start-up and shutdown steps. */
#ifndef LC_SERVER_RANKS_H
#define LC_SERVER_RANKS_H

#include "datasets.h"
#include "gl_context.h"
#include "server.h"

/* Starts MPI, sets srv->mpi and the workers' frame hook (srv->frame_hook:
 * the announcement before each frame, the reducer of every renderer). Thread: main. */
int lc_ranks_init(lc_server *srv, lc_error *err);
/* Ends MPI (collective), after everything else; nothing when it never started. */
void lc_ranks_finalize(void);
/* Under --mpi: line files and point clouds are read in shares, one per rank
 * (unless LUCENT_MPI_READ=whole): sets opts->read_part. */
void lc_ranks_datasets_options(lc_server *srv, lc_datasets_options *opts);
/* Start-up, after the datasets loaded (load_rc = that status, err its error):
 * every rank must have loaded, and the same dataset list; then each dataset
 * becomes this rank's shard. Collective; a failure anywhere fails every rank
 * with a message naming the rank. Thread: main. */
int lc_ranks_start(lc_server *srv, int load_rc, lc_error *err);
/* Collective: every rank's status rc (lc_mpi_agree); 0 when all succeeded. */
int lc_ranks_agree(lc_server *srv, int rc, lc_error *err);
/* true on the ranks > 0, which follow rank 0's frames instead of serving. */
bool lc_ranks_follower(const lc_server *srv);
/* Ranks > 0 after the upload: render the announced frames on primary until
 * rank 0 stops. Thread: main, primary current. */
int lc_ranks_follow(lc_server *srv, lc_gl *primary, lc_error *err);
/* Rank 0, serving: a rank that dies makes the pool answer the requests in hand. */
void lc_ranks_serving(lc_server *srv);
/* Rank 0, on a shutdown signal (signame for the log): ends the job if the
 * shutdown hangs on a dead rank, and answers the frames in hand and queued. */
void lc_ranks_signal(lc_server *srv, const char *signame);
/* Rank 0 at shutdown, after the workers stopped: releases the followers. */
void lc_ranks_stop(lc_server *srv);

#endif
