/* lc_mpi.h without MPI (-DLUCENT_MPI=OFF): --mpi fails with a message. */
#include <stdlib.h>

#include "lc_mpi.h"

static int unavailable(lc_error *err)
{
    return lc_err(err, LC_ERR_INVALID,
                  "this lucent was built without MPI (configure with -DLUCENT_MPI=ON and "
                  "install libopenmpi-dev)");
}

int lc_mpi_available(void) { return 0; }
int lc_mpi_init(lc_mpi **out, lc_error *err)
{
    *out = NULL;
    return unavailable(err);
}
void lc_mpi_finalize(lc_mpi *m) { (void)m; }
void lc_mpi_abort(lc_mpi *m, int code, const char *msg)
{
    (void)m, (void)msg;
    exit(code);
}
void lc_mpi_on_abort(lc_mpi *m, void (*hook)(void *ctx, const char *msg), void *ctx) { (void)m, (void)hook, (void)ctx; }
void lc_mpi_profile(lc_mpi *m, double *wait_ms, double *transfer_ms)
{
    (void)m;
    *wait_ms = *transfer_ms = 0;
}
int lc_mpi_rank(const lc_mpi *m) { return (void)m, 0; }
int lc_mpi_size(const lc_mpi *m) { return (void)m, 1; }
const lc_reducer *lc_mpi_reducer(lc_mpi *m) { return (void)m, NULL; }
int lc_mpi_agree(lc_mpi *m, int rc, lc_error *err) { return (void)m, (void)err, rc; }
int lc_mpi_agreed_failure(const lc_mpi *m) { return (void)m, 0; }
int lc_mpi_check_same(lc_mpi *m, const char *what, const char *text, lc_error *err)
{
    return (void)m, (void)what, (void)text, (void)err, 0;
}
int lc_mpi_shard(lc_mpi *m, lc_scene **scene, FILE *report, lc_error *err)
{
    return (void)m, (void)scene, (void)report, unavailable(err);
}
int lc_mpi_finalize_part(lc_mpi *m, int read_rc, lc_scene **scene, uint32_t elements, FILE *report, lc_error *err)
{
    lc_scene_destroy(*scene);
    *scene = NULL;
    return (void)m, (void)read_rc, (void)elements, (void)report, unavailable(err);
}
int lc_mpi_frame_announce(lc_mpi *m, const int *datasets, const lc_layer_params *layers, int layer_count,
                          uint32_t element_count, const lc_render_params *p, const lc_frame_state *state, double dt,
                          lc_error *err)
{
    return (void)m, (void)datasets, (void)layers, (void)layer_count, (void)element_count, (void)p, (void)state,
           (void)dt, unavailable(err);
}
int lc_mpi_stop_followers(lc_mpi *m, lc_error *err) { return (void)m, unavailable(err); }
int lc_mpi_follow(lc_mpi *m, lc_renderer *r, const lc_gpu_scene *const *scenes, const uint32_t *element_counts,
                  int count, lc_error *err)
{
    return (void)m, (void)r, (void)scenes, (void)element_counts, (void)count, unavailable(err);
}
void lc_mpi_exit_guard(lc_mpi *m, double seconds) { (void)m, (void)seconds; }
