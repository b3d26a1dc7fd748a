/* Movie jobs of the daemon (POST /api/v1/movies): a queue of at most
 * LC_MOVIES_ACTIVE jobs, run one at a time by one thread. Each frame goes
 * through the render workers' queue as an HTTP session's frame (fairness key:
 * the job's session), so movie frames take turns with interactive clients;
 * the session's opacities fade between frames with dt = 1/fps. Frames are
 * encoded into a temporary file (render/image/video.h) that GET
 * /api/v1/movies/ID/file serves; DELETE cancels a job and removes its file. */
#ifndef LC_SERVER_MOVIES_H
#define LC_SERVER_MOVIES_H

#include <stddef.h>
#include <stdint.h>

#include "server.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_MOVIES_ACTIVE 4 /* queued or running jobs; more are refused with 429 */
#define LC_MOVIES_KEPT 16  /* jobs remembered (finished ones are dropped oldest first) */

typedef struct lc_movies lc_movies;

/* A route's answer for http.c: status and a JSON body (malloc'd), or a file. */
typedef struct lc_movie_reply {
    unsigned status;
    char *body;        /* JSON text, or NULL when fd >= 0 */
    int fd;            /* an open file to send (the caller closes it), else -1 */
    size_t size;       /* bytes of fd */
    const char *type;  /* content type */
    const char *allow; /* for 405 */
} lc_movie_reply;

/* Creates the job registry, its temporary folder and its thread. Thread: main. */
int lc_movies_create(lc_server *srv, lc_movies **out, lc_error *err);
/* Cancels every job (a frame in hand finishes first) and joins the thread;
 * call before lc_workers_stop. Thread: main. */
void lc_movies_stop(lc_movies *m);
/* Removes the files and the folder and frees m (after lc_http_stop). */
void lc_movies_destroy(lc_movies *m);

struct MHD_Connection;
/* Queues the answer of lc_movies_route on an MHD connection (JSON or the
 * file); returns MHD_YES or MHD_NO for the access handler. */
int lc_movies_answer(lc_movies *m, struct MHD_Connection *c, uint64_t owner, const char *method, const char *rest,
                     const char *body, size_t len);
/* Answers a request to /api/v1/movies + rest ("" or "/ID" or "/ID/file") with
 * the body given (POST). A job belongs to the client that made it (owner: its
 * key, http/conn_limits.h): the list shows a client its own jobs, and another
 * client's ID answers 404 as an unknown one. Any MHD thread. */
void lc_movies_route(lc_movies *m, uint64_t owner, const char *method, const char *rest, const char *body, size_t len,
                     lc_movie_reply *out);

#ifdef __cplusplus
}
#endif
#endif
