/* serve --mpi: MPI start-up and agreement between ranks, the followers' loop,
 * and the frame hook that announces rank 0's frames. */
#include "ranks.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lc_mpi.h"
#include "loaders.h"
#include "workers.h"

#define MOD "mpi"

static lc_mpi *process_mpi; /* ended after everything else (lc_ranks_finalize) */

/* serve --mpi on rank 0: the frame in hand waits for a rank that died, so the
 * requests waiting for it get an answer that says so, not a closed connection. */
#define MPI_ENDING "the MPI job is ending: a rank has died, hangs or was stopped (the log names it)"

/* A dataset's index in the registry: frames name datasets by index (every
 * rank loaded the same list, lc_ranks_start). */
static int dataset_index(const lc_server *srv, const lc_dataset *ds)
{
    int index = 0;
    while (index < lc_datasets_count(srv->datasets) && lc_datasets_at(srv->datasets, index) != ds)
        index++;
    return index;
}

/* The frame hook: announces the frame (dataset index in the registry,
 * parameters, the viewer's fading history) to the other ranks. */
static int announce(void *ctx, const lc_dataset *ds, const lc_render_params *p, const lc_frame_state *state, double dt,
                    lc_error *err)
{
    lc_server *srv = ctx;
    int index = dataset_index(srv, ds);
    return lc_mpi_frame_announce(srv->mpi, &index, NULL, 0, ds->scene->elements.count, p, state, dt, err);
}

/* The hook of a frame of layers: their datasets' indices and parameters too;
 * the state spans their elements. */
static int announce_layers(void *ctx, const lc_dataset *const *ds, const lc_layer_params *layers, int n,
                           const lc_render_params *p, const lc_frame_state *state, double dt, lc_error *err)
{
    lc_server *srv = ctx;
    int index[LC_MAX_LAYERS];
    uint64_t elements = 0;
    for (int i = 0; i < n && i < LC_MAX_LAYERS; i++) {
        index[i] = dataset_index(srv, ds[i]);
        elements += ds[i]->scene->elements.count;
    }
    return lc_mpi_frame_announce(srv->mpi, index, layers, n, (uint32_t)elements, p, state, dt, err);
}

int lc_ranks_init(lc_server *srv, lc_error *err)
{
    int rc = lc_mpi_init(&process_mpi, err);
    if (rc)
        return rc;
    srv->mpi = process_mpi;
    srv->frame_hook = (lc_frame_hook){
        .ctx = srv, .before = announce, .before_layers = announce_layers, .reducer = lc_mpi_reducer(process_mpi)};
    return 0;
}

void lc_ranks_finalize(void)
{
    lc_mpi_finalize(process_mpi);
    process_mpi = NULL;
}

static int read_part(void *ctx, const char *path, lc_scene **out, lc_error *err)
{
    int rc = lc_scene_read_file_part(path, lc_mpi_rank(ctx), lc_mpi_size(ctx), out, err);
    return lc_mpi_finalize_part(ctx, rc, out, 0, NULL, err); /* --elements and sidecars rebuild collectively */
}

void lc_ranks_datasets_options(lc_server *srv, lc_datasets_options *opts)
{
    const char *mpi_read = getenv("LUCENT_MPI_READ");
    if (srv->mpi &&
        !(mpi_read && strcmp(mpi_read, "whole") == 0)) { /* line files, point clouds: each rank reads its share */
        opts->read_part = read_part;
        opts->read_part_ctx = srv->mpi;
    }
}

static int shard_scene(void *ctx, lc_scene **scene, lc_error *err) { return lc_mpi_shard(ctx, scene, NULL, err); }
int lc_ranks_start(lc_server *srv, int load_rc, lc_error *err)
{
    lc_mpi *m = srv->mpi;
    if (load_rc && lc_mpi_agreed_failure(m))
        return load_rc; /* a file read in parts failed on some rank, and every rank knows it already */
    if (load_rc)
        LC_ERROR(MOD, "rank %d: %s", lc_mpi_rank(m), err->msg);
    int rc = lc_mpi_agree(m, load_rc, err);
    if (rc)
        return rc;
    /* The same names, kinds and sizes in the same order: frames name a dataset by index. */
    char list[1024] = "";
    size_t used = 0;
    for (int i = 0; i < lc_datasets_count(srv->datasets); i++) {
        const lc_dataset *ds = lc_datasets_at(srv->datasets, i);
        const lc_scene *s = ds->scene;
        int n = snprintf(list + used, sizeof list - used, "%s%s (%s, %llu vertices, %u elements)", i ? ", " : "",
                         ds->name, lc_prim_type_name(s->type),
                         (unsigned long long)(s->part_of ? s->whole_vertices : s->vertex_count), s->elements.count);
        if (n < 0 || (size_t)n >= sizeof list - used)
            break;
        used += (size_t)n;
    }
    if ((rc = lc_mpi_check_same(m, "dataset lists", list, err)) != 0)
        return rc;
    rc = lc_datasets_shard(srv->datasets, shard_scene, m, err);
    if (rc == 0)
        LC_INFO(MOD, "rank %d of %d: %d dataset(s) sharded", lc_mpi_rank(m), lc_mpi_size(m),
                lc_datasets_count(srv->datasets));
    return rc;
}

int lc_ranks_follow(lc_server *srv, lc_gl *primary, lc_error *err)
{
    (void)primary;
    lc_renderer *r = NULL;
    int rc = lc_renderer_create(&(lc_renderer_desc){.reducer = lc_mpi_reducer(srv->mpi)}, &r, err);
    int n = lc_datasets_count(srv->datasets);
    const lc_gpu_scene **scenes = calloc((size_t)n + 1, sizeof *scenes);
    uint32_t *elements = calloc((size_t)n + 1, sizeof *elements);
    if ((!scenes || !elements) && rc == 0)
        rc = lc_err(err, LC_ERR_NOMEM, "out of memory");
    for (int i = 0; scenes && elements && i < n; i++) {
        const lc_dataset *ds = lc_datasets_at(srv->datasets, i);
        scenes[i] = ds->gpu, elements[i] = ds->scene->elements.count;
    }
    /* Rank 0 creates its worker's renderer meanwhile; a failure here shows
     * as a frame that never completes (the collective timeout ends the job). */
    if (rc == 0) {
        LC_INFO(MOD, "rank %d (pid %d): following rank 0's frames", lc_mpi_rank(srv->mpi), (int)getpid());
        rc = lc_mpi_follow(srv->mpi, r, scenes, elements, n, err);
    }
    free(scenes);
    free(elements);
    lc_renderer_destroy(r);
    return rc;
}

int lc_ranks_agree(lc_server *srv, int rc, lc_error *err) { return lc_mpi_agree(srv->mpi, rc, err); }

bool lc_ranks_follower(const lc_server *srv) { return lc_mpi_rank(srv->mpi) > 0; }

static void answer_before_abort(void *ctx, const char *msg)
{
    (void)msg;
    lc_workers_abandon(((lc_server *)ctx)->workers, MPI_ENDING);
}

void lc_ranks_serving(lc_server *srv) { lc_mpi_on_abort(srv->mpi, answer_before_abort, srv); }

void lc_ranks_signal(lc_server *srv, const char *signame)
{
    /* Under mpirun a signal also comes when another rank died: mpirun then
     * ends the job and names the rank. A frame waiting for that rank
     * would hold the shutdown, so it has 10 s. */
    LC_WARN("serve", "--mpi: %s received: ending the service on every rank (if a rank died, mpirun names it)", signame);
    lc_mpi_exit_guard(srv->mpi, 10.0);
    /* mpirun follows its signal with SIGKILL about a second later: answer
     * the frames in hand and the queue now rather than let them finish. */
    lc_workers_abandon(srv->workers, MPI_ENDING);
}

void lc_ranks_stop(lc_server *srv)
{
    lc_error err = {0};
    if (lc_mpi_stop_followers(srv->mpi, &err) != 0)
        LC_ERROR(MOD, "%s", err.msg);
    lc_mpi_on_abort(srv->mpi, NULL, NULL); /* the pool and the WebSocket layer go next */
}
