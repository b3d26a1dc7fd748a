/* lc_mpi.h over Open MPI (or any MPI-3 library): non-blocking collectives
 * waited on with a sleeping poll, so idle ranks leave the CPU to the renderer
 * and a collective that never completes ends the job with a message. */
#include "lc_mpi.h"

#include <mpi.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "scene_part.h"
#include "scene_shard.h"

#define MOD "mpi"
#define TEXT_LEN 1024

struct lc_mpi {
    int rank, size;
    double timeout; /* seconds a collective of a frame may wait */
    lc_reducer reducer;
    /* The watchdog of the blocking reductions: when the current one began
     * (lc_now() in microseconds, 0 = none), checked twice a second. */
    _Atomic long long busy_since_us;
    pthread_t watchdog;
    int watchdog_running;
    _Atomic int quitting;
    /* LUCENT_MPI_PROFILE=1: a barrier before each reduction separates the
     * wait for the slowest rank from the transfer (lc_mpi_profile). */
    int profile;
    double wait_ms, transfer_ms;
    /* LUCENT_MPI_WIRE=half: SUM reductions travel as IEEE half floats (an
     * experiment measured in docs/MPI.md; MIN stays float: its "empty" value
     * 1e30 has no half). */
    int wire_half;
    MPI_Op half_sum;
    _Float16 *half_buf;
    size_t half_cap;
    int agreed_failure; /* an lc_mpi_agree returned a failure (lc_mpi_agreed_failure) */
    /* lc_mpi_finalize_part: the scene layer's collectives, which the parts keep */
    lc_scene_collective collective;
    /* lc_mpi_on_abort */
    void (*_Atomic abort_hook)(void *ctx, const char *msg);
    void *_Atomic abort_ctx;
    _Atomic int aborting;
};

/* What rank 0 broadcasts before each frame of `serve --mpi`. The ranks run
 * the same binary on the same kind of host (docs/MPI.md), so it travels as
 * bytes. A frame of layers is followed by its layer_count lc_layer_params. */
enum { OP_FRAME = 1, OP_STOP = 2 };
typedef struct frame_msg {
    int32_t op, dataset, has_state, fresh;
    uint32_t element_count;
    double dt;
    lc_render_params params;
    int32_t layer_count;                  /* 0: one dataset (dataset) */
    int32_t layer_dataset[LC_MAX_LAYERS]; /* the layers' datasets by index in the registry */
} frame_msg;

int lc_mpi_available(void) { return 1; }

static void sleep_us(long us)
{
    struct timespec ts = {us / 1000000, (us % 1000000) * 1000};
    nanosleep(&ts, NULL);
}

/* Waits for req, polling with a growing sleep (50 us .. 1 ms). timeout <= 0
 * waits for ever (a follower waiting for the next frame). */
static int wait_request(lc_mpi *m, MPI_Request *req, const char *what, double timeout, lc_error *err)
{
    double t0 = lc_now();
    long pause = 50;
    for (;;) {
        int done = 0;
        int rc = MPI_Test(req, &done, MPI_STATUS_IGNORE);
        if (rc != MPI_SUCCESS)
            return lc_err(err, LC_ERR_INTERNAL, "MPI: rank %d: %s failed (MPI error %d)", m->rank, what, rc);
        if (done)
            return 0;
        if (timeout > 0 && lc_now() - t0 > timeout) {
            char msg[256];
            snprintf(msg, sizeof msg,
                     "%s has waited %.0f s for the other ranks: a rank has died or hangs; ending the job", what,
                     timeout);
            lc_mpi_abort(m, 3, msg);
        }
        sleep_us(pause);
        if (pause < 1000)
            pause += pause / 2;
    }
}

static void half_sum(void *in, void *inout, int *len, MPI_Datatype *type)
{
    (void)type;
    const _Float16 *a = in;
    _Float16 *b = inout;
    for (int i = 0; i < *len; i++)
        b[i] = (_Float16)((float)a[i] + (float)b[i]);
}

/* A SUM over the wire in half floats, converted on both ends. */
static int reduce_half(lc_mpi *m, float *values, int count, int root_only)
{
    if ((size_t)count > m->half_cap) {
        _Float16 *b = realloc(m->half_buf, (size_t)count * sizeof *b);
        if (!b)
            return MPI_ERR_NO_MEM;
        m->half_buf = b, m->half_cap = (size_t)count;
    }
    for (int i = 0; i < count; i++)
        m->half_buf[i] = (_Float16)values[i];
    int rc;
    if (!root_only)
        rc = MPI_Allreduce(MPI_IN_PLACE, m->half_buf, count, MPI_SHORT, m->half_sum, MPI_COMM_WORLD);
    else if (m->rank == 0)
        rc = MPI_Reduce(MPI_IN_PLACE, m->half_buf, count, MPI_SHORT, m->half_sum, 0, MPI_COMM_WORLD);
    else
        rc = MPI_Reduce(m->half_buf, NULL, count, MPI_SHORT, m->half_sum, 0, MPI_COMM_WORLD);
    for (int i = 0; i < count && rc == MPI_SUCCESS && (!root_only || m->rank == 0); i++)
        values[i] = (float)m->half_buf[i];
    return rc;
}

/* Blocking collectives: the library's tuned algorithms progress on their own
 * (a non-blocking one progresses only while polled, which with sleeps cost
 * about 50 ms per megabyte); the watchdog thread bounds the wait instead. */
static int reduce(void *ctx, float *values, size_t n, lc_reduce_op op, int root_only, lc_error *err)
{
    lc_mpi *m = ctx;
    MPI_Op mop = op == LC_REDUCE_MIN ? MPI_MIN : MPI_SUM;
    const size_t chunk = (size_t)1 << 28; /* MPI counts are int */
    int rc = MPI_SUCCESS;
    m->busy_since_us = (long long)(lc_now() * 1e6);
    double t0 = lc_now();
    if (m->profile)
        MPI_Barrier(MPI_COMM_WORLD);
    double t1 = lc_now();
    for (size_t off = 0; off < n && rc == MPI_SUCCESS; off += chunk) {
        int count = (int)(n - off < chunk ? n - off : chunk);
        if (m->wire_half && op == LC_REDUCE_SUM)
            rc = reduce_half(m, values + off, count, root_only);
        else if (!root_only)
            rc = MPI_Allreduce(MPI_IN_PLACE, values + off, count, MPI_FLOAT, mop, MPI_COMM_WORLD);
        else if (m->rank == 0)
            rc = MPI_Reduce(MPI_IN_PLACE, values + off, count, MPI_FLOAT, mop, 0, MPI_COMM_WORLD);
        else
            rc = MPI_Reduce(values + off, NULL, count, MPI_FLOAT, mop, 0, MPI_COMM_WORLD);
    }
    m->busy_since_us = 0;
    m->wait_ms += (t1 - t0) * 1e3;
    m->transfer_ms += (lc_now() - t1) * 1e3;
    if (rc != MPI_SUCCESS)
        return lc_err(err, LC_ERR_INTERNAL, "MPI: rank %d: reduction failed (MPI error %d)", m->rank, rc);
    return 0;
}

static void *watchdog_main(void *arg)
{
    lc_mpi *m = arg;
    while (!m->quitting) {
        sleep_us(500000);
        long long since = m->busy_since_us;
        if (since && lc_now() - since * 1e-6 > m->timeout) {
            char msg[256];
            snprintf(msg, sizeof msg,
                     "a reduction has waited %.0f s for the other ranks: a rank has died or hangs "
                     "(LUCENT_MPI_TIMEOUT); ending the job",
                     m->timeout);
            lc_mpi_abort(m, 3, msg);
        }
    }
    return NULL;
}

int lc_mpi_init(lc_mpi **out, lc_error *err)
{
    *out = NULL;
    int provided = 0;
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_MULTIPLE, &provided) != MPI_SUCCESS)
        return lc_err(err, LC_ERR_INTERNAL, "MPI_Init_thread failed (start with mpirun or srun)");
    if (provided < MPI_THREAD_SERIALIZED) {
        MPI_Finalize();
        return lc_err(err, LC_ERR_INTERNAL, "the MPI library offers thread level %d, Lucent needs SERIALIZED",
                      provided);
    }
    lc_mpi *m = calloc(1, sizeof *m);
    if (!m)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    MPI_Comm_rank(MPI_COMM_WORLD, &m->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m->size);
    const char *t = getenv("LUCENT_MPI_TIMEOUT");
    m->timeout = t && atof(t) > 0 ? atof(t) : 60.0;
    const char *prof = getenv("LUCENT_MPI_PROFILE");
    m->profile = prof && atoi(prof) > 0;
    const char *wire = getenv("LUCENT_MPI_WIRE");
    m->wire_half = wire && strcmp(wire, "half") == 0;
    if (m->wire_half)
        MPI_Op_create(half_sum, 1, &m->half_sum);
    m->reducer = (lc_reducer){.ctx = m, .rank = m->rank, .size = m->size, .reduce = reduce};
    m->watchdog_running = pthread_create(&m->watchdog, NULL, watchdog_main, m) == 0;
    *out = m;
    return 0;
}

void lc_mpi_finalize(lc_mpi *m)
{
    if (!m)
        return;
    m->quitting = 1;
    if (m->watchdog_running)
        pthread_join(m->watchdog, NULL);
    if (m->wire_half)
        MPI_Op_free(&m->half_sum);
    free(m->half_buf);
    MPI_Finalize();
    free(m);
}

void lc_mpi_on_abort(lc_mpi *m, void (*hook)(void *ctx, const char *msg), void *ctx)
{
    m->abort_hook = NULL;
    m->abort_ctx = ctx;
    m->abort_hook = hook;
}

void lc_mpi_abort(lc_mpi *m, int code, const char *msg)
{
    LC_ERROR(MOD, "rank %d: %s", m ? m->rank : -1, msg);
    fflush(stderr);
    void (*hook)(void *, const char *) = m ? m->abort_hook : NULL;
    if (hook && atomic_exchange(&m->aborting, 1) == 0) {
        hook(m->abort_ctx, msg);
        sleep_us(500000); /* the HTTP and WebSocket threads send the answers */
    }
    MPI_Abort(MPI_COMM_WORLD, code);
    _exit(code);
}

void lc_mpi_profile(lc_mpi *m, double *wait_ms, double *transfer_ms)
{
    *wait_ms = m->wait_ms, *transfer_ms = m->transfer_ms;
    m->wait_ms = m->transfer_ms = 0;
}

int lc_mpi_rank(const lc_mpi *m) { return m->rank; }
int lc_mpi_size(const lc_mpi *m) { return m->size; }
const lc_reducer *lc_mpi_reducer(lc_mpi *m) { return &m->reducer; }

int lc_mpi_agree(lc_mpi *m, int rc, lc_error *err)
{
    struct {
        int32_t rc;
        char msg[LC_ERROR_MSG_LEN];
    } mine = {.rc = rc}, *all = calloc((size_t)m->size, sizeof mine);
    if (rc && err)
        snprintf(mine.msg, sizeof mine.msg, "%s", err->msg);
    if (!all)
        lc_mpi_abort(m, 1, "out of memory");
    MPI_Request req;
    MPI_Iallgather(&mine, sizeof mine, MPI_BYTE, all, sizeof mine, MPI_BYTE, MPI_COMM_WORLD, &req);
    wait_request(m, &req, "the start-up check", m->timeout, err);
    int out = 0;
    for (int r = 0; r < m->size && !out; r++)
        if (all[r].rc) {
            out = all[r].rc;
            lc_err(err, out, "rank %d: %s", r, all[r].msg);
        }
    free(all);
    m->agreed_failure |= out != 0;
    return out;
}

int lc_mpi_agreed_failure(const lc_mpi *m) { return m->agreed_failure; }

int lc_mpi_check_same(lc_mpi *m, const char *what, const char *text, lc_error *err)
{
    char mine[TEXT_LEN] = {0};
    snprintf(mine, sizeof mine, "%s", text);
    char *all = calloc((size_t)m->size, TEXT_LEN);
    if (!all)
        lc_mpi_abort(m, 1, "out of memory");
    MPI_Request req;
    MPI_Iallgather(mine, TEXT_LEN, MPI_BYTE, all, TEXT_LEN, MPI_BYTE, MPI_COMM_WORLD, &req);
    wait_request(m, &req, "the start-up check", m->timeout, err);
    int rc = 0;
    for (int r = 1; r < m->size && !rc; r++)
        if (memcmp(all, all + (size_t)r * TEXT_LEN, TEXT_LEN) != 0)
            rc = lc_err(err, LC_ERR_INVALID, "ranks see different %s: rank 0 has [%.100s], rank %d has [%.100s]", what,
                        all, r, all + (size_t)r * TEXT_LEN);
    free(all);
    return rc;
}

#define SHARE_FIELDS 5

/* Rank 0 reports each rank's share: vertices, primitives, scene bytes
 * against the whole (whole = 0: the shares' sum, with the element numbering
 * and adjacency, which every rank holds, counted once) and the peak resident
 * size so far, to report (one line per rank) or the log. */
static void report_shares(lc_mpi *m, const lc_scene *shard, size_t whole, const char *how, FILE *report, lc_error *err)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    const lc_elements *e = &shard->elements;
    uint64_t adjacency = e->adjacency_offsets ? ((uint64_t)e->count + 1 + e->adjacency_count) * sizeof(uint32_t) : 0;
    uint64_t mine[SHARE_FIELDS] = {lc_scene_bytes(shard), shard->vertex_count, lc_scene_primitive_count(shard),
                                   (uint64_t)ru.ru_maxrss /* KiB on Linux */, adjacency};
    uint64_t *all = calloc((size_t)m->size * SHARE_FIELDS, sizeof *all);
    if (!all)
        lc_mpi_abort(m, 1, "out of memory");
    MPI_Request req;
    MPI_Igather(mine, SHARE_FIELDS, MPI_UINT64_T, all, SHARE_FIELDS, MPI_UINT64_T, 0, MPI_COMM_WORLD, &req);
    wait_request(m, &req, "the memory report", m->timeout, err);
    if (m->rank == 0 && !whole) {
        whole = all[4];
        for (int r = 0; r < m->size; r++)
            whole += all[SHARE_FIELDS * r] - all[SHARE_FIELDS * r + 4];
    }
    for (int r = 0; m->rank == 0 && r < m->size; r++) {
        const uint64_t *a = all + SHARE_FIELDS * r;
        char line[320];
        snprintf(line, sizeof line,
                 "%s: rank %d of %d: %llu vertices, %llu primitives, %.2f MB of scene arrays (%.0f%% "
                 "of the whole %.2f MB; %s), peak resident %.1f MB",
                 shard->name, r, m->size, (unsigned long long)a[1], (unsigned long long)a[2], a[0] / 1e6,
                 whole ? 100.0 * a[0] / whole : 0.0, whole / 1e6, how, a[3] * 1024 / 1e6);
        if (report)
            fprintf(report, "  %s\n", line);
        else
            LC_INFO(MOD, "%s", line);
    }
    free(all);
}

int lc_mpi_shard(lc_mpi *m, lc_scene **scene, FILE *report, lc_error *err)
{
    lc_scene *shard = NULL;
    size_t whole = lc_scene_bytes(*scene);
    int rc = lc_scene_shard(*scene, m->rank, m->size, &shard, err);
    if ((rc = lc_mpi_agree(m, rc, err)) != 0) {
        lc_scene_destroy(shard);
        return rc;
    }
    lc_scene_destroy(*scene);
    *scene = shard;
    report_shares(m, shard, whole, "read whole, share kept", report, err);
    return 0;
}

/* ---- lc_scene_collective over MPI_COMM_WORLD (parts read by each rank) */

static int coll_agree(void *ctx, int rc, lc_error *err) { return lc_mpi_agree(ctx, rc, err); }

static int coll_allreduce(lc_mpi *m, void *v, size_t n, MPI_Datatype type, MPI_Op op, lc_error *err)
{
    if (n > INT32_MAX)
        return lc_err(err, LC_ERR_LIMIT, "MPI: %zu values in one reduction", n);
    MPI_Request req;
    MPI_Iallreduce(MPI_IN_PLACE, v, (int)n, type, op, MPI_COMM_WORLD, &req);
    return wait_request(m, &req, "a reduction while loading", m->timeout, err);
}

static int coll_sum_u64(void *ctx, uint64_t *v, size_t n, lc_error *err)
{
    return coll_allreduce(ctx, v, n, MPI_UINT64_T, MPI_SUM, err);
}

static int coll_min_f64(void *ctx, double *v, size_t n, lc_error *err)
{
    return coll_allreduce(ctx, v, n, MPI_DOUBLE, MPI_MIN, err);
}

static int coll_gather(void *ctx, const void *mine, size_t bytes, void **all, uint64_t **bytes_of_out, lc_error *err)
{
    lc_mpi *m = ctx;
    *all = NULL;
    uint64_t n = bytes, *bytes_of = *bytes_of_out = calloc((size_t)m->size, sizeof *bytes_of);
    if (!bytes_of)
        lc_mpi_abort(m, 1, "out of memory for the sizes of the parts");
    MPI_Request req;
    MPI_Iallgather(&n, 1, MPI_UINT64_T, bytes_of, 1, MPI_UINT64_T, MPI_COMM_WORLD, &req);
    int rc = wait_request(m, &req, "the sizes of the parts", m->timeout, err);
    uint64_t total = 0;
    int *counts = calloc((size_t)m->size, sizeof *counts), *displs = calloc((size_t)m->size, sizeof *displs);
    for (int r = 0; r < m->size && !rc; r++) {
        if (!counts || !displs || bytes_of[r] > INT32_MAX || total + bytes_of[r] > INT32_MAX)
            lc_mpi_abort(m, 1, "the table of the parts' lines exceeds 2 GB or memory"); /* every rank alike */
        counts[r] = (int)bytes_of[r], displs[r] = (int)total;
        total += bytes_of[r];
    }
    if (!rc && !(*all = malloc(total ? total : 1)))
        lc_mpi_abort(m, 1, "out of memory for the table of the parts' lines");
    if (!rc) {
        MPI_Iallgatherv(mine, (int)bytes, MPI_BYTE, *all, counts, displs, MPI_BYTE, MPI_COMM_WORLD, &req);
        rc = wait_request(m, &req, "the table of the parts' lines", m->timeout, err);
    }
    free(counts);
    free(displs);
    return rc;
}

int lc_mpi_finalize_part(lc_mpi *m, int read_rc, lc_scene **scene, uint32_t elements, FILE *report, lc_error *err)
{
    lc_scene *s = read_rc ? NULL : *scene;
    *scene = NULL;
    int rc;
    if ((rc = lc_mpi_agree(m, read_rc, err)) == 0) {
        m->collective = (lc_scene_collective){.ctx = m,
                                              .rank = m->rank,
                                              .size = m->size,
                                              .agree = coll_agree,
                                              .sum_u64 = coll_sum_u64,
                                              .min_f64 = coll_min_f64,
                                              .gather = coll_gather};
        lc_elements_desc desc = {.line_budget = elements, .patch_count = elements};
        rc = lc_scene_finalize_part(s, &desc, &m->collective, err);
    }
    if (rc) {
        lc_scene_destroy(s);
        return rc;
    }
    report_shares(m, s, 0, "its share read from the file", report, err);
    *scene = s;
    return 0;
}

/* The announcement: msg, then the layers' parameters (layers: room for
 * LC_MAX_LAYERS on a follower), then the fading history when alpha is given
 * (a follower receives it in a second step, once it knows the size). */
static int bcast_frame(lc_mpi *m, frame_msg *msg, lc_layer_params *layers, float *alpha, double timeout, lc_error *err)
{
    MPI_Request req;
    MPI_Ibcast(msg, sizeof *msg, MPI_BYTE, 0, MPI_COMM_WORLD, &req);
    int rc = wait_request(m, &req, "the frame announcement", timeout, err);
    if (rc || msg->op != OP_FRAME)
        return rc;
    if (msg->layer_count < 0 || msg->layer_count > LC_MAX_LAYERS)
        return lc_err(err, LC_ERR_INTERNAL, "rank %d: a frame of %d layers (at most %d)", m->rank, msg->layer_count,
                      LC_MAX_LAYERS);
    if (msg->layer_count > 0) {
        MPI_Ibcast(layers, (int)((size_t)msg->layer_count * sizeof *layers), MPI_BYTE, 0, MPI_COMM_WORLD, &req);
        if ((rc = wait_request(m, &req, "the frame's layers", m->timeout, err)) != 0)
            return rc;
    }
    if (!msg->has_state || msg->fresh || !msg->element_count || !alpha)
        return 0;
    MPI_Ibcast(alpha, (int)msg->element_count, MPI_FLOAT, 0, MPI_COMM_WORLD, &req);
    return wait_request(m, &req, "the fading history", m->timeout, err);
}

int lc_mpi_frame_announce(lc_mpi *m, const int *datasets, const lc_layer_params *layers, int layer_count,
                          uint32_t element_count, const lc_render_params *p, const lc_frame_state *state, double dt,
                          lc_error *err)
{
    if (layer_count < 0 || layer_count > LC_MAX_LAYERS)
        return lc_err_field(err, LC_ERR_INVALID, "layers", "%d layers; 1 to %d are allowed", layer_count,
                            LC_MAX_LAYERS);
    frame_msg msg;
    memset(&msg, 0, sizeof msg);
    msg.op = OP_FRAME, msg.dataset = datasets[0], msg.dt = dt, msg.params = *p;
    msg.has_state = state != NULL;
    msg.fresh = state ? lc_frame_state_is_fresh(state) : 1;
    msg.element_count = element_count;
    msg.layer_count = layer_count;
    for (int i = 0; i < layer_count; i++)
        msg.layer_dataset[i] = datasets[i];
    /* The history P3 fades from; every rank computes the same next one. A
     * compact (16-bit) state travels as floats like the others. */
    float *alpha = NULL;
    if (state && !msg.fresh && element_count) {
        alpha = malloc((size_t)element_count * sizeof *alpha);
        if (!alpha)
            return lc_err(err, LC_ERR_NOMEM, "out of memory for the fading history");
        lc_frame_state_copy(state, alpha);
    }
    int rc = bcast_frame(m, &msg, (lc_layer_params *)layers, alpha, m->timeout, err); /* only read on rank 0 */
    free(alpha);
    return rc;
}

int lc_mpi_stop_followers(lc_mpi *m, lc_error *err)
{
    frame_msg msg;
    memset(&msg, 0, sizeof msg);
    msg.op = OP_STOP;
    return bcast_frame(m, &msg, NULL, NULL, m->timeout, err);
}

/* A follower's check of what arrived: the datasets by index, the layers'
 * roles, and the fading history's size against the datasets' elements (a
 * frame's state spans its layers); the layers' scenes into layer_scenes. */
static int check_frame(lc_mpi *m, frame_msg *msg, lc_layer_params *layers, const lc_gpu_scene *const *scenes,
                       const uint32_t *element_counts, int count, const lc_gpu_scene **layer_scenes, lc_error *err)
{
    int n = msg->layer_count ? msg->layer_count : 1;
    const int32_t *index = msg->layer_count ? msg->layer_dataset : &msg->dataset;
    uint64_t elements = 0;
    for (int i = 0; i < n; i++) {
        if (index[i] < 0 || index[i] >= count)
            return lc_err(err, LC_ERR_INTERNAL, "rank %d: frame for dataset %d of %d", m->rank, index[i], count);
        if (msg->layer_count && layers[i].role != LC_LAYER_TRANSPARENT && layers[i].role != LC_LAYER_CONTEXT)
            return lc_err(err, LC_ERR_INTERNAL, "rank %d: layer %d has role %d", m->rank, i, (int)layers[i].role);
        layer_scenes[i] = scenes[index[i]];
        elements += element_counts[index[i]];
    }
    if (msg->has_state && msg->element_count != elements)
        return lc_err(err, LC_ERR_INTERNAL, "rank %d: a fading history of %u elements for datasets of %llu", m->rank,
                      msg->element_count, (unsigned long long)elements);
    return 0;
}

int lc_mpi_follow(lc_mpi *m, lc_renderer *r, const lc_gpu_scene *const *scenes, const uint32_t *element_counts,
                  int count, lc_error *err)
{
    lc_frame_state *state = NULL;
    uint32_t state_count = 0;
    float *alpha = NULL;
    uint8_t *rgba = NULL;
    size_t rgba_bytes = 0;
    frame_msg msg;
    lc_layer_params *layers = malloc(LC_MAX_LAYERS * sizeof *layers); /* 2 KiB a layer: off the stack */
    const lc_gpu_scene *layer_scenes[LC_MAX_LAYERS];
    int rc = layers ? 0 : lc_err(err, LC_ERR_NOMEM, "rank %d: out of memory", m->rank);
    for (; rc == 0;) {
        memset(&msg, 0, sizeof msg);
        if ((rc = bcast_frame(m, &msg, layers, NULL, 0, err)) != 0 || msg.op != OP_FRAME)
            break;
        if ((rc = check_frame(m, &msg, layers, scenes, element_counts, count, layer_scenes, err)) != 0)
            break;
        if (msg.has_state && (!state || state_count != msg.element_count)) {
            lc_frame_state_destroy(state);
            free(alpha);
            state = lc_frame_state_create(msg.element_count);
            alpha = malloc(((size_t)msg.element_count + 1) * sizeof *alpha);
            state_count = msg.element_count;
            if (!state || !alpha) {
                rc = lc_err(err, LC_ERR_NOMEM, "rank %d: out of memory", m->rank);
                break;
            }
        }
        if (msg.has_state && !msg.fresh && msg.element_count) {
            MPI_Request req;
            MPI_Ibcast(alpha, (int)msg.element_count, MPI_FLOAT, 0, MPI_COMM_WORLD, &req);
            if ((rc = wait_request(m, &req, "the fading history", m->timeout, err)) != 0)
                break;
            lc_frame_state_load(state, alpha);
        } else if (msg.has_state) {
            lc_frame_state_reset(state);
        }
        size_t need = (size_t)msg.params.width * msg.params.height * 4;
        if (need > rgba_bytes) {
            free(rgba);
            rgba = malloc(need);
            rgba_bytes = rgba ? need : 0;
            if (!rgba) {
                rc = lc_err(err, LC_ERR_NOMEM, "rank %d: out of memory for a %dx%d frame", m->rank, msg.params.width,
                            msg.params.height);
                break;
            }
        }
        lc_error ferr = {0};
        /* A failure before the first reduction (a bad parameter) is the same
         * on every rank; rank 0 reports it. */
        lc_frame_state *st = msg.has_state ? state : NULL;
        if ((msg.layer_count
                 ? lc_render_layers(r, layer_scenes, layers, msg.layer_count, &msg.params, st, msg.dt, rgba, NULL,
                                    &ferr)
                 : lc_render_frame(r, scenes[msg.dataset], &msg.params, st, msg.dt, rgba, NULL, &ferr)) != 0)
            LC_DEBUG(MOD, "rank %d: frame failed: %s", m->rank, ferr.msg);
    }
    free(layers);
    lc_frame_state_destroy(state);
    free(alpha);
    free(rgba);
    return rc;
}

static void *exit_guard(void *arg)
{
    lc_mpi *m = ((void **)arg)[0];
    double seconds = *(double *)((void **)arg)[1];
    sleep_us((long)(seconds * 1e6));
    lc_mpi_abort(m, 4,
                 "the shutdown did not finish in time (a rank has died and left a collective waiting); "
                 "ending the job");
    return NULL;
}

void lc_mpi_exit_guard(lc_mpi *m, double seconds)
{
    static void *arg[2];
    static double s;
    s = seconds, arg[0] = m, arg[1] = &s;
    pthread_t t;
    if (pthread_create(&t, NULL, exit_guard, arg) == 0)
        pthread_detach(t);
}
