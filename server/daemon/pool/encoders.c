/* Encoder threads: JPEG/PNG off the render workers, frames packed for the stream. */
#include "encoders.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image.h"
#include "messages.h"
#include "metrics.h"
#include "stream_session.h"

#define MOD "encoders"

/* An image to encode. */
typedef struct encode_item {
    struct encode_item *next;
    uint8_t *rgba;
    int width, height;
    lc_image_format format;
    int quality;
    lc_render_job *job;    /* HTTP: finish this job */
    lc_session *session;   /* stream: send a frame message (holds a reference) */
    lc_stream_frame frame; /* stream only */
    lc_frame_info info;    /* stream only */
} encode_item;

struct lc_encoders {
    lc_server *srv;
    void (*wake)(void *ctx, lc_session *s);
    void *wake_ctx;
    pthread_t *threads;
    int count, started;
    pthread_mutex_t enc_lock;
    pthread_mutex_t send_lock; /* a session's frame handed over and queued to its connection as one step */
    pthread_cond_t enc_work;
    encode_item *enc_head, *enc_tail;
    int enc_depth;
    bool enc_stopping;
};

static void push(lc_encoders *w, encode_item *e)
{
    pthread_mutex_lock(&w->enc_lock);
    e->next = NULL;
    if (w->enc_tail)
        w->enc_tail->next = e;
    else
        w->enc_head = e;
    w->enc_tail = e;
    w->enc_depth++;
    pthread_cond_signal(&w->enc_work);
    pthread_mutex_unlock(&w->enc_lock);
}

int lc_pass_timings(const lc_frame_info *info, lc_frame_timing *out, int cap)
{
    int n = 0;
    for (int p = 0; p < LC_PASS_COUNT && n < cap; p++) {
        if (info->pass_ms[p] < 0)
            continue;
        snprintf(out[n].pass, sizeof out[n].pass, "%s", lc_pass_name(p));
        out[n].ms = info->pass_ms[p];
        n++;
    }
    return n;
}

static void encode_one(lc_encoders *w, encode_item *e)
{
    lc_server *srv = w->srv;
    unsigned char *img = NULL;
    size_t size = 0;
    lc_error err = {0};
    double t0 = lc_now();
    int rc = e->format == LC_FORMAT_PNG
                 ? lc_image_encode_png(e->rgba, e->width, e->height, &img, &size, &err)
                 : lc_image_encode_jpeg(e->rgba, e->width, e->height, e->quality, &img, &size, &err);
    double ms = (lc_now() - t0) * 1000.0;
    free(e->rgba);
    e->rgba = NULL;
    if ((long long)e->width * e->height > LC_LARGE_FRAME_PIXELS)
        lc_memory_trim(); /* what the large frame's buffers leave in the heap goes back too */
    if (rc == 0)
        lc_metrics_encode(srv->metrics, ms, (long long)e->width * e->height, size);
    if (e->job) {
        lc_render_job *job = e->job;
        job->rc = rc;
        if (rc != 0)
            job->err = err;
        job->image = img;
        job->image_size = size;
        job->encode_ms = ms;
        job->done(job); /* the job belongs to its submitter again from here */
        return;
    }
    lc_session *s = e->session;
    if (rc != 0) {
        LC_WARN(MOD, "session %s: encode failed: %s", s->id, err.msg);
        lc_stream_error(srv, s, "render_failed", err.msg, NULL);
        lc_session_stream_sent(s, e->frame.frame, 0, 0, 0);
        lc_session_stream_ack(s, e->frame.frame); /* nothing to ack for this id */
        w->wake(w->wake_ctx, s);
        return;
    }
    lc_frame_header h;
    memset(&h, 0, sizeof h);
    h.frame = e->frame.frame;
    h.width = e->width;
    h.height = e->height;
    h.format = LC_FORMAT_JPEG;
    h.quality = e->quality;
    h.camera_seq = e->frame.camera_seq;
    h.converged = e->info.converged != 0;
    h.timing_count = lc_pass_timings(&e->info, h.timings, LC_PROTO_MAX_TIMINGS);
    h.encode_ms = ms;
    h.has_detail = true;
    h.interactive = e->frame.interactive;
    h.stage = e->frame.stage, h.stages = e->frame.stages;
    h.reused = e->info.reused_opacities != 0;
    h.level = e->info.lod_level;
    h.lod_pixels = e->frame.req.render.detail.lod_pixels;
    h.point_stride = e->info.point_stride > 0 ? e->info.point_stride : 1;
    h.line_stride = e->info.line_stride > 0 ? e->info.line_stride : 1;
    h.primitives = e->info.primitives_drawn;
    h.render_ms = e->info.wall_ms;
    if (e->info.has_visibility) {
        h.has_visibility = true;
        h.top_decile_alpha = e->info.top_decile_alpha;
        h.bottom_half_alpha = e->info.bottom_half_alpha;
        h.occluder_alpha = e->info.occluder_alpha;
        h.important_occluded = e->info.important_occluded;
        h.has_reach = e->info.has_reach != 0;
        h.top_decile_reach = e->info.top_decile_reach;
        h.covered_fraction = e->info.covered_fraction;
        h.layer_count = e->info.layer_count;
        for (int i = 0; i < e->info.layer_count && i < LC_MAX_LAYERS; i++) {
            h.layer_visibility[i][0] = e->info.layers[i].top_decile_alpha;
            h.layer_visibility[i][1] = e->info.layers[i].bottom_half_alpha;
            h.layer_visibility[i][2] = e->info.layers[i].occluder_alpha;
        }
    }
    if (e->info.clarity_tries > 0 && e->info.clarity_lambda >= 1 && e->info.clarity_penalty >= 1) {
        h.has_clarity = true;
        h.clarity_lambda = e->info.clarity_lambda;
        h.clarity_penalty = e->info.clarity_penalty;
        h.clarity_reached = e->info.clarity_reached != 0;
        h.has_clarity_smoothing = e->info.clarity_smoothing_cut != 0;
        h.clarity_smoothing = e->info.clarity_smoothing;
    }
    if (e->info.has_color_ticks) {
        h.has_color_ticks = true;
        memcpy(h.color_ticks, e->info.color_ticks, sizeof h.color_ticks);
    }
    if (e->info.has_surface) {
        h.has_surface = true;
        h.surface_curves = e->info.surface_curves;
        h.surface_particles = (uint64_t)e->frame.req.surface.particles;
        h.surface_layers = e->info.surface_mean_layers;
        h.surface_overflow = e->info.surface_overflow;
        h.surface_k = e->info.surface_k;
        h.surface_drawn_curves = e->info.surface_drawn_curves;
        h.surface_drawn_fragments = e->info.surface_drawn_fragments;
        h.surface_kept = e->info.surface_kept != 0;
    }
    unsigned char *msg = NULL;
    size_t len = 0;
    rc = lc_proto_pack_frame(&h, img, size, &msg, &len);
    free(img);
    /* Two encoder threads may finish a session's frames out of order (a
     * still behind the moving frame after it): a frame older than one that
     * already went out would show an older camera last, so it is dropped
     * (the newer frame's ack covers its id). */
    if (rc == 0) {
        pthread_mutex_lock(&w->send_lock);
        if (lc_session_stream_sent(s, e->frame.frame, len, e->quality, (long)e->width * e->height))
            srv->sink.send_frame(srv->sink.ctx, s, msg, len, e->info.wall_ms, ms);
        else
            free(msg);
        pthread_mutex_unlock(&w->send_lock);
    }
}

static void *encoder_main(void *arg)
{
    lc_encoders *w = arg;
    pthread_mutex_lock(&w->enc_lock);
    for (;;) {
        while (!w->enc_head && !w->enc_stopping)
            pthread_cond_wait(&w->enc_work, &w->enc_lock);
        encode_item *e = w->enc_head;
        if (!e)
            break; /* stopping and drained */
        w->enc_head = e->next;
        if (!w->enc_head)
            w->enc_tail = NULL;
        w->enc_depth--;
        pthread_mutex_unlock(&w->enc_lock);
        encode_one(w, e);
        if (e->session)
            lc_session_unref(e->session);
        free(e);
        pthread_mutex_lock(&w->enc_lock);
    }
    pthread_mutex_unlock(&w->enc_lock);
    return NULL;
}

int lc_encoders_create(lc_server *srv, int n, void (*wake)(void *ctx, lc_session *s), void *wake_ctx, lc_encoders **out,
                       lc_error *err)
{
    *out = NULL;
    lc_encoders *w = calloc(1, sizeof *w);
    if (w)
        w->threads = calloc((size_t)(n > 0 ? n : 1), sizeof *w->threads);
    if (!w || !w->threads) {
        free(w);
        return lc_err(err, LC_ERR_NOMEM, "out of memory");
    }
    w->srv = srv;
    w->wake = wake;
    w->wake_ctx = wake_ctx;
    w->count = n > 0 ? n : 1;
    pthread_mutex_init(&w->enc_lock, NULL);
    pthread_mutex_init(&w->send_lock, NULL);
    pthread_cond_init(&w->enc_work, NULL);
    for (int i = 0; i < w->count; i++)
        if (pthread_create(&w->threads[i], NULL, encoder_main, w) == 0)
            w->started++;
    *out = w;
    if (w->started == 0)
        return lc_err(err, LC_ERR_INTERNAL, "cannot start encoder threads");
    return 0;
}

void lc_encoders_stop(lc_encoders *w)
{
    if (!w)
        return;
    pthread_mutex_lock(&w->enc_lock);
    w->enc_stopping = true;
    pthread_cond_broadcast(&w->enc_work);
    pthread_mutex_unlock(&w->enc_lock);
    for (int i = 0; i < w->started; i++)
        pthread_join(w->threads[i], NULL);
    w->started = 0;
}

void lc_encoders_destroy(lc_encoders *w)
{
    if (!w)
        return;
    lc_encoders_stop(w);
    pthread_mutex_destroy(&w->enc_lock);
    pthread_mutex_destroy(&w->send_lock);
    pthread_cond_destroy(&w->enc_work);
    free(w->threads);
    free(w);
}

void lc_encoders_job(lc_encoders *w, uint8_t *rgba, lc_render_job *job)
{
    encode_item *e = calloc(1, sizeof *e);
    if (!e) {
        free(rgba);
        job->rc = lc_err(&job->err, LC_ERR_NOMEM, "out of memory");
        job->done(job);
        return;
    }
    e->rgba = rgba;
    e->width = job->req.render.width;
    e->height = job->req.render.height;
    e->format = job->req.format;
    e->quality = job->req.quality;
    e->job = job;
    push(w, e);
}

void lc_encoders_frame(lc_encoders *w, uint8_t *rgba, lc_session *s, const lc_stream_frame *f,
                       const lc_frame_info *info)
{
    encode_item *e = calloc(1, sizeof *e);
    if (!e) {
        free(rgba);
        return;
    }
    e->rgba = rgba;
    e->width = f->req.render.width;
    e->height = f->req.render.height;
    e->format = LC_FORMAT_JPEG;
    e->quality = f->quality;
    e->frame = *f;
    e->frame.req.layers = NULL; /* the frame's numbers are read, not its layers: no reference kept */
    e->info = *info;
    lc_session_ref(s);
    e->session = s;
    push(w, e);
}

int lc_encoders_depth(lc_encoders *w)
{
    pthread_mutex_lock(&w->enc_lock);
    int n = w->enc_depth;
    pthread_mutex_unlock(&w->enc_lock);
    return n;
}

void lc_stream_error(lc_server *srv, lc_session *s, const char *code, const char *message, const char *field)
{
    char *msg = lc_proto_error_message_json(code, message, field, false);
    lc_metrics_error(srv->metrics, code);
    if (msg)
        srv->sink.send(srv->sink.ctx, s, (unsigned char *)msg, strlen(msg), false);
}
