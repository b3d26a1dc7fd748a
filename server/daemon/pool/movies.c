/* Movie jobs: queue, one runner thread, frames through the render workers,
 * encoding into a temporary file, status, download and cancel (movies.h). */
#include "movies.h"

#include <errno.h>
#include <fcntl.h>
#include <microhttpd.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include "admit.h"
#include "camera.h"
#include "camera_path.h"
#include "cost.h"
#include "datasets.h"
#include "image.h"
#include "metrics.h"
#include "movie.h"
#include "session.h"
#include "traced.h"
#include "video.h"
#include "workers.h"

#define MOD "movies"

typedef enum { QUEUED, RUNNING, DONE, FAILED, CANCELLED } job_state;
static const char *const STATE_NAMES[] = {"queued", "running", "done", "failed", "cancelled"};

typedef struct movie_job {
    char id[LC_SESSION_ID_LEN];
    lc_movie_spec spec;
    const lc_dataset *ds; /* the request's dataset, or its first layer's */
    const lc_dataset
        *layers[LC_MAX_LAYERS]; /* request.layers' datasets (lc_request_layer_count(&spec.request) of them) */
    lc_traced *traced;          /* a vector field's streamline set that ds points into, owned; NULL otherwise */
    lc_video_codec codec;
    uint64_t owner; /* the client that made it (lc_movies_route) */
    double cost;
    job_state state;
    bool cancel;
    bool over_disk; /* its file outgrew --movie-disk (check_disk) */
    int frames_done;
    double created, started, finished;
    char path[600];
    long long bytes;
    lc_proto_error error;
} movie_job;

struct lc_movies {
    lc_server *srv;
    pthread_mutex_t lock;
    pthread_cond_t cond;             /* a job queued, a frame finished, or stopping */
    movie_job *jobs[LC_MOVIES_KEPT]; /* oldest first */
    int count;
    bool stopping;
    bool frame_finished;
    pthread_t thread;
    bool thread_started;
    char dir[512]; /* the files' private folder, made by the first job: a killed daemon leaves none */
    bool dir_made;
};

/* ---------------------------------------------------------------- replies */

static void reply_json(lc_movies *m, lc_movie_reply *out, unsigned status, json_t *o)
{
    (void)m;
    out->status = status;
    out->body = o ? lc_proto_dump(o) : NULL;
    out->type = "application/json";
    json_decref(o);
}

static void reply_error(lc_movies *m, lc_movie_reply *out, unsigned status, const char *code, const char *field,
                        const char *fmt, ...) __attribute__((format(printf, 6, 7)));
static void reply_error(lc_movies *m, lc_movie_reply *out, unsigned status, const char *code, const char *field,
                        const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    lc_metrics_error(m->srv->metrics, code);
    out->status = status;
    out->body = lc_proto_error_json(code, msg, field && field[0] ? field : NULL);
    out->type = "application/json";
}

/* Status of a job; m->lock held. */
static json_t *job_json(const movie_job *j)
{
    const lc_movie_spec *s = &j->spec;
    json_t *o = json_object();
    json_object_set_new(o, "id", json_string(j->id));
    json_object_set_new(o, "state", json_string(STATE_NAMES[j->state]));
    json_object_set_new(o, "progress", json_real(s->frames ? (double)j->frames_done / s->frames : 0));
    json_object_set_new(o, "framesDone", json_integer(j->frames_done));
    json_object_set_new(o, "frames", json_integer(s->frames));
    json_object_set_new(o, "fps", json_integer(s->fps));
    json_object_set_new(o, "duration", json_real(s->duration));
    json_object_set_new(o, "width", json_integer(s->request.render.width));
    json_object_set_new(o, "height", json_integer(s->request.render.height));
    json_object_set_new(o, "codec", json_string(s->codec));
    json_object_set_new(o, "dataset", json_string(j->ds->name));
    if (lc_request_layer_count(&s->request) > 0) { /* a movie of layers: every frame draws them all */
        json_t *names = json_array();
        for (int i = 0; i < lc_request_layer_count(&s->request); i++)
            json_array_append_new(names, json_string(j->layers[i]->name));
        json_object_set_new(o, "layers", names);
    }
    double end = j->finished > 0 ? j->finished : lc_now();
    json_object_set_new(o, "seconds", json_real(j->started > 0 ? end - j->started : 0));
    if (j->state == DONE) {
        char url[96];
        snprintf(url, sizeof url, "/api/v1/movies/%s/file", j->id);
        json_object_set_new(o, "file", json_string(url));
        json_object_set_new(o, "bytes", json_integer(j->bytes));
    }
    if (j->state == FAILED) {
        json_t *e = json_pack("{ss ss}", "code", j->error.code, "message", j->error.message);
        if (j->error.field[0])
            json_object_set_new(e, "field", json_string(j->error.field));
        json_object_set_new(o, "error", e);
    }
    return o;
}

/* ---------------------------------------------------------------- the runner */

static void frame_done(lc_render_job *rj)
{
    lc_movies *m = rj->user;
    pthread_mutex_lock(&rj->session->lock);
    rj->session->http_busy = false;
    pthread_mutex_unlock(&rj->session->lock);
    pthread_mutex_lock(&m->lock);
    m->frame_finished = true;
    pthread_cond_broadcast(&m->cond);
    pthread_mutex_unlock(&m->lock);
}

static bool should_stop(lc_movies *m, movie_job *j)
{
    pthread_mutex_lock(&m->lock);
    bool stop = j->cancel || m->stopping;
    pthread_mutex_unlock(&m->lock);
    return stop;
}

/* The camera of frame i: the path's start is the request's camera, else the
 * one a request without camera gets (the dataset's suggested view, fitted to
 * it, or to the union of the layers' bounds). */
static void frame_camera(const movie_job *j, int i, lc_camera *out)
{
    const lc_movie_spec *s = &j->spec;
    lc_camera start = s->request.render.camera;
    if (!s->request.render.has_camera && j->ds->traced && !j->ds->gpu) { /* a traced set, not uploaded yet */
        start.view_angle = start.view_angle > 0 ? start.view_angle : 30; /* as lc_render_fit_camera fits */
        lc_camera_fit(&start, j->ds->scene->bounds, NULL, NULL);
    } else if (!s->request.render.has_camera) {
        int n = lc_request_layer_count(&s->request);
        const lc_gpu_scene *scenes[LC_MAX_LAYERS] = {j->ds->gpu};
        for (int k = 0; k < n; k++)
            scenes[k] = j->layers[k]->gpu;
        lc_render_fit_camera(scenes, n ? n : 1, &start);
    }
    lc_camera_path_desc d = {.kind = (int)s->path,
                             .degrees = s->degrees,
                             .elevation = s->elevation,
                             .keys = s->keyframes,
                             .key_count = s->keyframe_count,
                             .frames = s->frames};
    lc_camera_path_frame(&d, &start, i, out);
}

/* Renders frame i through the worker pool into rgba (w*h*4). */
static int render_frame(lc_movies *m, movie_job *j, lc_session *s, int i, lc_image *img, lc_error *err)
{
    lc_render_job *rj = calloc(1, sizeof *rj);
    if (!rj)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    lc_request_copy(&rj->req, &j->spec.request); /* the layers by reference */
    rj->req.format = LC_FORMAT_PNG;
    rj->req.has_dt = false;
    rj->req.render.has_camera = true;
    frame_camera(j, i, &rj->req.render.camera);
    rj->dataset = j->ds;
    memcpy(rj->layers, j->layers, sizeof rj->layers); /* a layered frame when the request has layers */
    rj->session = s;
    lc_session_ref(s);
    /* The first frame shows its targets, as an HTTP render of its camera
     * would; then the opacities fade with the movie's clock. */
    rj->dt = i == 0 ? 1e6 : 1.0 / j->spec.fps;
    rj->cost = j->cost;
    rj->done = frame_done;
    rj->user = m;
    int rc;
    for (;;) {
        rj->rc = 0;
        rj->refused = NULL;
        pthread_mutex_lock(&s->lock);
        s->http_busy = true;
        s->last_used = lc_now();
        pthread_mutex_unlock(&s->lock);
        pthread_mutex_lock(&m->lock);
        m->frame_finished = false;
        pthread_mutex_unlock(&m->lock);
        lc_error serr = {0};
        rc = lc_workers_submit(m->srv->workers, rj, &serr);
        if (rc != 0) {
            pthread_mutex_lock(&s->lock);
            s->http_busy = false;
            pthread_mutex_unlock(&s->lock);
            if (rc != LC_ERR_LIMIT || should_stop(m, j)) {
                *err = serr;
                lc_session_unref(s);
                lc_request_release(&rj->req);
                free(rj);
                return rc;
            }
            usleep(100 * 1000); /* the queue is full of other clients' work: theirs first */
            continue;
        }
        pthread_mutex_lock(&m->lock);
        while (!m->frame_finished)
            pthread_cond_wait(&m->cond, &m->lock);
        pthread_mutex_unlock(&m->lock);
        /* A frame that waited past the render deadline (other clients kept
         * the workers busy) goes back in line: a movie is not in a hurry. */
        if (!(rj->rc == LC_ERR_LIMIT && rj->refused && strcmp(rj->refused, "deadline") == 0) || should_stop(m, j))
            break;
    }
    rc = rj->rc;
    if (rc == LC_ERR_LIMIT && rj->refused && strcmp(rj->refused, "deadline") == 0)
        rc = lc_err(err, LC_ERR_LIMIT, "a frame waited past the render deadline");
    else if (rc != 0)
        *err = rj->err;
    else
        rc = lc_image_decode(rj->image, rj->image_size, img, err);
    free(rj->image);
    lc_session_unref(s);
    lc_request_release(&rj->req);
    free(rj);
    return rc;
}

static void forget(lc_movies *m, int i);

/* Holds the folder to --movie-disk while job j's file grows to bytes: finished
 * movies are deleted oldest first to make room; false when j alone outgrows
 * it. m->lock held. */
static bool fits_disk(lc_movies *m, const movie_job *j, long long bytes)
{
    unsigned long long budget = m->srv->cfg.movie_disk, used = (unsigned long long)bytes;
    for (int i = 0; i < m->count; i++)
        if (m->jobs[i] != j && m->jobs[i]->state == DONE)
            used += (unsigned long long)m->jobs[i]->bytes;
    for (int i = 0; i < m->count && used > budget; i++)
        if (m->jobs[i] != j && m->jobs[i]->state == DONE) {
            LC_INFO(MOD, "movie %s deleted to keep the folder under --movie-disk", m->jobs[i]->id);
            used -= (unsigned long long)m->jobs[i]->bytes;
            forget(m, i--);
        }
    return used <= budget;
}

/* The size of the file being written, checked against the folder's budget. */
static int check_disk(lc_movies *m, movie_job *j, lc_error *err)
{
    struct stat st;
    long long bytes = stat(j->path, &st) == 0 ? (long long)st.st_size : 0;
    pthread_mutex_lock(&m->lock);
    bool fits = fits_disk(m, j, bytes);
    pthread_mutex_unlock(&m->lock);
    if (!fits) {
        j->over_disk = true;
        return lc_err(err, LC_ERR_LIMIT, "the movie outgrew the movie folder's budget (--movie-disk %llu bytes)",
                      m->srv->cfg.movie_disk);
    }
    return 0;
}

static void set_failed(movie_job *j, int rc, const lc_error *err)
{
    if (j->over_disk) {
        lc_proto_set_error(&j->error, LC_PROTO_TOO_LARGE, NULL, "%s", err->msg);
        return;
    }
    const char *code = rc == LC_ERR_INVALID || rc == LC_ERR_NOT_FOUND ? LC_PROTO_BAD_FIELD
                       : rc == LC_ERR_BUDGET                          ? "too_expensive" /* cost.h work budgets */
                                                                      : "render_failed";
    lc_proto_set_error(&j->error, code, err->field, "%s", err->msg);
    if (err->field[0]) /* lc_proto_set_error prefixed the field; the renderer's message already starts with it */
        snprintf(j->error.message, sizeof j->error.message, "%s", err->msg);
}

static void run_job(lc_movies *m, movie_job *j)
{
    lc_error err = {0};
    lc_session *s = NULL;
    lc_video *v = NULL;
    int rc = lc_session_create(m->srv->sessions, LC_SESSION_HTTP, j->owner, j->ds, &j->spec.request, &s, &err);
    if (rc == 0)
        rc = lc_video_open(j->path, j->codec, j->spec.request.render.width, j->spec.request.render.height, j->spec.fps,
                           &v, &err);
    LC_INFO(MOD, "movie %s: %d frames of %dx%d at %d fps, %s, %s", j->id, j->spec.frames, j->spec.request.render.width,
            j->spec.request.render.height, j->spec.fps, j->spec.codec, j->ds->name);
    bool stopped = false;
    for (int i = 0; rc == 0 && i < j->spec.frames; i++) {
        if (should_stop(m, j)) {
            stopped = true;
            break;
        }
        lc_image img = {0};
        rc = render_frame(m, j, s, i, &img, &err);
        if (rc == 0 && (img.width != j->spec.request.render.width || img.height != j->spec.request.render.height))
            rc = lc_err(&err, LC_ERR_INTERNAL, "frame %d came back %dx%d", i, img.width, img.height);
        if (rc == 0)
            rc = lc_video_write(v, img.rgba, &err);
        if (rc == 0)
            rc = check_disk(m, j, &err);
        lc_image_free(&img);
        pthread_mutex_lock(&m->lock);
        if (rc == 0)
            j->frames_done = i + 1;
        pthread_mutex_unlock(&m->lock);
    }
    if (rc == 0 && !stopped && v) {
        rc = lc_video_close(v, &err);
        v = NULL;
        if (rc == 0)
            rc = check_disk(m, j, &err); /* the container's trailer */
    }
    if (v)
        lc_video_abort(v); /* deletes the partial file */
    if (s) {
        lc_session_close(m->srv->sessions, s);
        lc_session_unref(s);
    }
    struct stat st;
    pthread_mutex_lock(&m->lock);
    j->finished = lc_now();
    if (stopped) {
        j->state = CANCELLED;
    } else if (rc != 0) {
        j->state = FAILED;
        set_failed(j, rc, &err);
        unlink(j->path);
    } else {
        j->state = DONE;
        j->bytes = stat(j->path, &st) == 0 ? (long long)st.st_size : 0;
    }
    pthread_mutex_unlock(&m->lock);
    LC_INFO(MOD, "movie %s: %s after %.1f s (%d frames)%s%s", j->id, STATE_NAMES[j->state], j->finished - j->started,
            j->frames_done, rc ? ": " : "", rc ? err.msg : "");
}

static void *runner(void *arg)
{
    lc_movies *m = arg;
    pthread_mutex_lock(&m->lock);
    for (;;) {
        movie_job *next = NULL;
        for (int i = 0; i < m->count && !next; i++)
            if (m->jobs[i]->state == QUEUED)
                next = m->jobs[i];
        if (m->stopping)
            break;
        if (!next) {
            pthread_cond_wait(&m->cond, &m->lock);
            continue;
        }
        next->state = RUNNING;
        next->started = lc_now();
        pthread_mutex_unlock(&m->lock);
        run_job(m, next);
        pthread_mutex_lock(&m->lock);
    }
    pthread_mutex_unlock(&m->lock);
    return NULL;
}

/* ---------------------------------------------------------------- life cycle */

int lc_movies_create(lc_server *srv, lc_movies **out, lc_error *err)
{
    *out = NULL;
    lc_movies *m = calloc(1, sizeof *m);
    if (!m)
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    m->srv = srv;
    pthread_mutex_init(&m->lock, NULL);
    pthread_cond_init(&m->cond, NULL);
    if (pthread_create(&m->thread, NULL, runner, m) != 0) {
        free(m);
        return lc_err(err, LC_ERR_INTERNAL, "movies: cannot start a thread");
    }
    m->thread_started = true;
    *out = m;
    return 0;
}

void lc_movies_stop(lc_movies *m)
{
    if (!m)
        return;
    pthread_mutex_lock(&m->lock);
    m->stopping = true;
    pthread_cond_broadcast(&m->cond);
    pthread_mutex_unlock(&m->lock);
    if (m->thread_started)
        pthread_join(m->thread, NULL);
    m->thread_started = false;
}

void lc_movies_destroy(lc_movies *m)
{
    if (!m)
        return;
    lc_movies_stop(m);
    for (int i = 0; i < m->count; i++) {
        unlink(m->jobs[i]->path);
        lc_traced_free(m->jobs[i]->traced);
        lc_request_release(&m->jobs[i]->spec.request);
        free(m->jobs[i]);
    }
    rmdir(m->dir); /* ("" or the template where none was made: nothing to remove) */
    pthread_cond_destroy(&m->cond);
    pthread_mutex_destroy(&m->lock);
    free(m);
}

/* ---------------------------------------------------------------- routes */

static void random_id(char out[LC_SESSION_ID_LEN])
{
    unsigned char b[16] = {0};
    if (getrandom(b, sizeof b, 0) != (ssize_t)sizeof b) {
        static atomic_uint counter;
        unsigned c = atomic_fetch_add(&counter, 1);
        memcpy(b, &c, sizeof c);
    }
    for (int i = 0; i < 16; i++)
        snprintf(out + 2 * i, 3, "%02x", b[i]);
}

/* Index of owner's job id, or -1 (another client's job too); m->lock held. */
static int find(lc_movies *m, uint64_t owner, const char *id, size_t len)
{
    for (int i = 0; i < m->count; i++)
        if (m->jobs[i]->owner == owner && strlen(m->jobs[i]->id) == len && strncmp(m->jobs[i]->id, id, len) == 0)
            return i;
    return -1;
}

/* Frees j, the streamline set it traced and its request's layers. */
static void drop(movie_job *j)
{
    lc_traced_free(j->traced);
    lc_request_release(&j->spec.request);
    free(j);
}

static void forget(lc_movies *m, int i)
{
    unlink(m->jobs[i]->path);
    drop(m->jobs[i]);
    memmove(&m->jobs[i], &m->jobs[i + 1], (size_t)(m->count - i - 1) * sizeof m->jobs[0]);
    m->count--;
}

static void create(lc_movies *m, uint64_t owner, const char *body, size_t len, lc_movie_reply *out)
{
    lc_server *srv = m->srv;
    movie_job *j = calloc(1, sizeof *j);
    if (!j) {
        reply_error(m, out, 503, "overloaded", NULL, "out of memory");
        return;
    }
    lc_proto_error pe;
    if (lc_proto_parse_movie(body ? body : "", len, &srv->cfg.limits, &j->spec, &pe) != 0) {
        reply_error(m, out, strcmp(pe.code, LC_PROTO_TOO_LARGE) == 0 ? 413 : 400, pe.code, pe.field, "%s", pe.message);
        free(j);
        return;
    }
    lc_request *req = &j->spec.request;
    if (req->render.method == LC_METHOD_SURFACE_LAYERS) { /* its frames draw a field's surface, not a dataset */
        reply_error(m, out, 400, LC_PROTO_BAD_FIELD, "request.method",
                    "request.method: a movie draws a dataset; surface-layers is served by renders and sessions");
        free(j);
        return;
    }
    /* layers[] (docs/ALGORITHM.md §24): their datasets resolved as a session's; the first is the movie's dataset. */
    if (lc_admit_resolve_layers(srv, req, j->layers, &pe) != 0) {
        char field[sizeof pe.field + 8];
        snprintf(field, sizeof field, "request.%s", pe.field);
        reply_error(m, out, strcmp(pe.code, "not_found") == 0 ? 404 : 400, pe.code, field, "request.%s", pe.message);
        drop(j);
        return;
    }
    /* a loaded dataset, or a vector field's streamline set traced for the movie (traced.h) */
    j->ds = lc_request_layer_count(req) > 0 ? j->layers[0] : lc_traced_resolve(srv, req, &j->traced, &pe);
    if (!j->ds) {
        char field[sizeof pe.field + 8];
        snprintf(field, sizeof field, "request.%s", pe.field);
        reply_error(m, out, strcmp(pe.code, "not_found") == 0 ? 404 : 400, pe.code, field, "request.%s", pe.message);
        drop(j);
        return;
    }
    snprintf(req->dataset, sizeof req->dataset, "%s", j->ds->name);
    j->codec = (lc_video_codec)lc_video_codec_from_name(j->spec.codec);
    if (!lc_video_available(j->codec)) {
        reply_error(m, out, 400, LC_PROTO_BAD_FIELD, "codec", "codec: this server cannot encode %s (%s)", j->spec.codec,
                    "no libavcodec encoder for it");
        drop(j);
        return;
    }
    /* Every frame has this request's fields and size (the cameras differ): admitted once; a
     * frame of a moving camera is never a still to build up in batches. */
    if (req->render.foo.progressive > 1)
        lc_proto_set_error(&pe, LC_PROTO_BAD_FIELD, "params.progressive",
                           "a movie's frames are drawn whole; leave it 1");
    if (req->render.foo.progressive > 1 || lc_request_admit(srv, NULL, req, j->ds, j->layers, &j->cost, &pe) != 0) {
        reply_error(m, out, 400, pe.code, pe.field, "%s", pe.message);
        drop(j);
        return;
    }
    random_id(j->id);
    j->owner = owner;
    j->created = lc_now();
    pthread_mutex_lock(&m->lock);
    if (!m->dir_made && !m->stopping) {
        const char *tmp = getenv("TMPDIR");
        snprintf(m->dir, sizeof m->dir, "%s/lucent-movies-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!(m->dir_made = mkdtemp(m->dir) != NULL)) {
            int e = errno;
            pthread_mutex_unlock(&m->lock);
            LC_WARN(MOD, "cannot create %s: %s", m->dir, strerror(e));
            reply_error(m, out, 500, "internal", NULL, "this server cannot store movie files: %s", strerror(e));
            drop(j);
            return;
        }
    }
    snprintf(j->path, sizeof j->path, "%s/%s.%s", m->dir, j->id, lc_video_extension(j->codec));
    int active = 0;
    for (int i = 0; i < m->count; i++)
        active += m->jobs[i]->state == QUEUED || m->jobs[i]->state == RUNNING;
    if (active >= LC_MOVIES_ACTIVE || m->stopping) {
        pthread_mutex_unlock(&m->lock);
        reply_error(m, out, m->stopping ? 503 : 429, "overloaded", NULL,
                    m->stopping ? "the server is shutting down"
                                : "%d movie jobs are queued or running (the limit); retry when one is done",
                    active);
        drop(j);
        return;
    }
    for (int i = 0; i < m->count && m->count >= LC_MOVIES_KEPT; i++)
        if (m->jobs[i]->state != QUEUED && m->jobs[i]->state != RUNNING)
            forget(m, i--); /* the oldest finished job and its file make room */
    m->jobs[m->count++] = j;
    json_t *o = job_json(j);
    json_object_set_new(o, "position", json_integer(active));
    pthread_cond_broadcast(&m->cond);
    pthread_mutex_unlock(&m->lock);
    LC_INFO(MOD, "movie %s queued (%d ahead)", j->id, active);
    reply_json(m, out, 202, o);
}

void lc_movies_route(lc_movies *m, uint64_t owner, const char *method, const char *rest, const char *body, size_t len,
                     lc_movie_reply *out)
{
    memset(out, 0, sizeof *out);
    out->fd = -1;
    bool get = strcmp(method, "GET") == 0 || strcmp(method, "HEAD") == 0;
    if (rest[0] == 0) {
        if (strcmp(method, "POST") == 0) {
            create(m, owner, body, len, out);
        } else if (get) {
            json_t *list = json_array();
            pthread_mutex_lock(&m->lock);
            for (int i = 0; i < m->count; i++)
                if (m->jobs[i]->owner == owner)
                    json_array_append_new(list, job_json(m->jobs[i]));
            pthread_mutex_unlock(&m->lock);
            reply_json(m, out, 200, json_pack("{so si}", "movies", list, "limit", LC_MOVIES_ACTIVE));
        } else {
            reply_error(m, out, 405, "method_not_allowed", NULL, "method %.16s not allowed here (allowed: GET, POST)",
                        method);
            out->allow = "GET, POST";
        }
        return;
    }
    const char *id = rest + 1;
    const char *slash = strchr(id, '/');
    size_t idlen = slash ? (size_t)(slash - id) : strlen(id);
    bool file = slash && strcmp(slash, "/file") == 0;
    pthread_mutex_lock(&m->lock);
    int i = rest[0] == '/' && (!slash || file) ? find(m, owner, id, idlen) : -1;
    if (i < 0) {
        pthread_mutex_unlock(&m->lock);
        reply_error(m, out, 404, "not_found", NULL, "no such movie: %.100s", rest);
        return;
    }
    movie_job *j = m->jobs[i];
    if (file) {
        if (!get) {
            pthread_mutex_unlock(&m->lock);
            reply_error(m, out, 405, "method_not_allowed", NULL, "method %.16s not allowed here (allowed: GET)",
                        method);
            out->allow = "GET";
            return;
        }
        if (j->state != DONE) {
            const char *state = STATE_NAMES[j->state];
            pthread_mutex_unlock(&m->lock);
            reply_error(m, out, 409, "not_ready", NULL, "movie %s is %s; its file comes when it is done", j->id, state);
            return;
        }
        int fd = open(j->path, O_RDONLY | O_CLOEXEC);
        struct stat st;
        if (fd < 0 || fstat(fd, &st) != 0) {
            if (fd >= 0)
                close(fd);
            pthread_mutex_unlock(&m->lock);
            reply_error(m, out, 500, "internal", NULL, "movie %s: its file is gone", j->id);
            return;
        }
        out->status = 200;
        out->fd = fd;
        out->size = (size_t)st.st_size;
        out->type = lc_video_mime(j->codec);
        pthread_mutex_unlock(&m->lock);
        return;
    }
    if (get) {
        json_t *o = job_json(j);
        pthread_mutex_unlock(&m->lock);
        reply_json(m, out, 200, o);
    } else if (strcmp(method, "DELETE") == 0) {
        /* An active job is cancelled (the runner drops its session and partial
         * file after the frame in hand); a finished one is forgotten with its file. */
        json_t *o;
        if (j->state == QUEUED || j->state == RUNNING) {
            j->cancel = true;
            if (j->state == QUEUED) {
                j->state = CANCELLED;
                j->finished = lc_now();
            }
            o = job_json(j);
            if (j->state == RUNNING)
                json_object_set_new(o, "state", json_string("cancelling"));
        } else {
            o = json_pack("{ss ss}", "id", j->id, "state", "deleted");
            forget(m, i);
        }
        pthread_cond_broadcast(&m->cond);
        pthread_mutex_unlock(&m->lock);
        reply_json(m, out, 200, o);
    } else {
        pthread_mutex_unlock(&m->lock);
        reply_error(m, out, 405, "method_not_allowed", NULL, "method %.16s not allowed here (allowed: GET, DELETE)",
                    method);
        out->allow = "GET, DELETE";
    }
}

int lc_movies_answer(lc_movies *m, struct MHD_Connection *c, uint64_t owner, const char *method, const char *rest,
                     const char *body, size_t len)
{
    lc_movie_reply rep;
    lc_movies_route(m, owner, method, rest, body, len, &rep);
    struct MHD_Response *r = rep.fd >= 0 ? MHD_create_response_from_fd(rep.size, rep.fd)
                             : rep.body
                                 ? MHD_create_response_from_buffer(strlen(rep.body), rep.body, MHD_RESPMEM_MUST_FREE)
                                 : NULL;
    if (!r) {
        if (rep.fd >= 0)
            close(rep.fd);
        free(rep.body);
        return MHD_NO;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, rep.type);
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    if (rep.allow)
        MHD_add_response_header(r, MHD_HTTP_HEADER_ALLOW, rep.allow);
    if (rep.status == 429)
        MHD_add_response_header(r, MHD_HTTP_HEADER_RETRY_AFTER, "5");
    enum MHD_Result ret = MHD_queue_response(c, rep.status, r);
    MHD_destroy_response(r);
    lc_metrics_http_request(m->srv->metrics, (int)rep.status);
    return ret;
}
