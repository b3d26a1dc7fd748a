/* serve --mpi: start-up agreement between ranks, the followers' loop and the
 * per-frame announcement of rank 0's render worker. */
#include "serve_mpi.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lc_mpi.h"
#include "loaders.h"

#define MOD "mpi"

static int shard_scene(void *ctx, lc_scene **scene, lc_error *err) { return lc_mpi_shard(ctx, scene, NULL, err); }

int lc_serve_mpi_read_part(void *ctx, const char *path, lc_scene **out, lc_error *err)
{
    int rc = lc_scene_read_file_part(path, lc_mpi_rank(ctx), lc_mpi_size(ctx), out, err);
    return lc_mpi_finalize_part(ctx, rc, out, 0, NULL, err); /* --elements and sidecars rebuild collectively */
}

int lc_serve_mpi_start(lc_server *srv, int load_rc, lc_error *err)
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

int lc_serve_mpi_follow(lc_server *srv, lc_gl *primary, lc_error *err)
{
    (void)primary;
    lc_renderer *r = NULL;
    int rc = lc_renderer_create(&(lc_renderer_desc){.reducer = lc_mpi_reducer(srv->mpi)}, &r, err);
    int n = lc_datasets_count(srv->datasets);
    const lc_gpu_scene **scenes = calloc((size_t)n + 1, sizeof *scenes);
    if (!scenes && rc == 0)
        rc = lc_err(err, LC_ERR_NOMEM, "out of memory");
    for (int i = 0; scenes && i < n; i++)
        scenes[i] = lc_datasets_at(srv->datasets, i)->gpu;
    /* Rank 0 creates its worker's renderer meanwhile; a failure here shows
     * as a frame that never completes (the collective timeout ends the job). */
    if (rc == 0) {
        LC_INFO(MOD, "rank %d (pid %d): following rank 0's frames", lc_mpi_rank(srv->mpi), (int)getpid());
        rc = lc_mpi_follow(srv->mpi, r, scenes, n, err);
    }
    free(scenes);
    lc_renderer_destroy(r);
    return rc;
}

void lc_serve_mpi_stop(lc_server *srv)
{
    lc_error err = {0};
    if (lc_mpi_stop_followers(srv->mpi, &err) != 0)
        LC_ERROR(MOD, "%s", err.msg);
}

int lc_server_render_frame(lc_server *srv, lc_renderer *r, const lc_dataset *ds, const lc_render_params *p,
                           lc_frame_state *state, double dt, uint8_t *rgba, lc_frame_info *info, lc_error *err)
{
    if (srv->mpi) {
        int index = 0;
        while (index < lc_datasets_count(srv->datasets) && lc_datasets_at(srv->datasets, index) != ds)
            index++;
        int rc = lc_mpi_frame_announce(srv->mpi, index, ds->scene->elements.count, p, state, dt, err);
        if (rc)
            return rc;
    }
    return lc_render_frame(r, ds->gpu, p, state, dt, rgba, info, err);
}
