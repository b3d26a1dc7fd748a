/* Encoder threads: the render workers hand them RGBA readbacks, so that
 * JPEG/PNG encoding overlaps the next frame's GL work. A finished HTTP job is
 * answered through job->done; a finished stream frame is packed (frame
 * header, websocket.md) and goes to the server's stream sink (server.h). */
#ifndef LC_SERVER_ENCODERS_H
#define LC_SERVER_ENCODERS_H

#include "field.h"
#include "renderer.h"
#include "request.h"
#include "server.h"
#include "session.h"

/* One HTTP render (one-shot, or a frame of an HTTP session). The submitter owns
 * the job; it is lent to the pool from lc_workers_submit() until done() is
 * called, after which the pool never touches it again. */
typedef struct lc_render_job lc_render_job;
struct lc_render_job {
    /* input */
    lc_request req;
    const lc_dataset *dataset;
    const lc_dataset *layers[LC_MAX_LAYERS]; /* the datasets of req.layers (lc_request_layer_count(&req) of them) */
    lc_session *session;                     /* HTTP session (the job holds a reference) or NULL */
    double dt;                               /* fading step for sessions */
    uint64_t client;                         /* fairness key: jobs of one client take turns with other clients' */
    double cost;                             /* estimated cost units (cost.h); 0 = unknown */
    const lc_field *field;    /* method surface-layers: req.surface.field's field (dataset is NULL then) */
    struct lc_traced *traced; /* a one-shot render's own streamline set (traced.h) that dataset points into */
    void (*done)(lc_render_job *job);
    void *user;
    /* output, valid in done() */
    int rc; /* 0, or an LC_ERR_* code with err filled */
    lc_error err;
    unsigned char *image; /* malloc'd encoded image (job owner frees) */
    size_t image_size;
    lc_frame_info info;
    double encode_ms;
    double queue_ms;     /* waiting for a worker */
    const char *refused; /* why submit or the deadline refused it: "queue", "client_queue", "deadline" */
    /* pool internals */
    lc_render_job *next;
    double submitted;
    uint8_t *rgba;
};

typedef struct lc_encoders lc_encoders;

/* Starts n encoder threads (at least one). wake(ctx, s) asks the render pool
 * to consider s again after its frame failed to encode. Thread: main. */
int lc_encoders_create(lc_server *srv, int n, void (*wake)(void *ctx, lc_session *s), void *wake_ctx, lc_encoders **out,
                       lc_error *err);
/* Encodes what was handed over, then joins the threads. Thread: main. */
void lc_encoders_stop(lc_encoders *e);
void lc_encoders_destroy(lc_encoders *e);
/* An HTTP job's image (takes rgba): job->image, or job->rc, then job->done. */
void lc_encoders_job(lc_encoders *e, uint8_t *rgba, lc_render_job *job);
/* A stream frame of s (takes rgba; the item holds a reference to s). */
void lc_encoders_frame(lc_encoders *e, uint8_t *rgba, lc_session *s, const lc_stream_frame *f,
                       const lc_frame_info *info);
/* Images waiting for an encoder. */
int lc_encoders_depth(lc_encoders *e);

/* An error message for s's stream, through the sink, counted in the metrics. */
void lc_stream_error(lc_server *srv, lc_session *s, const char *code, const char *message, const char *field);
/* Fills "timings" style lists: pass names with ms for passes that ran. */
int lc_pass_timings(const lc_frame_info *info, lc_frame_timing *out, int cap);

#endif
