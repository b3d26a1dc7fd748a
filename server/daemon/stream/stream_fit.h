/* The moving frames' JPEG quality and size from the link's throughput
 * (protocol/websocket.md "Quality that follows the link"): a moving frame's
 * transfer should take no more than a share of the frame budget, so the link
 * carries frames as fast as the renderer makes them. Quality goes first (down
 * to LC_FIT_MIN_QUALITY), size only after; stills are not fitted. Pure
 * arithmetic on explicit figures: session.c feeds it the flow's estimate
 * (stream_flow.h) and the latest moving frame, the unit test explicit ones.
 *
 *     target = rate * budget * LC_FIT_SHARE            the link's rate measured
 *     target = max(ref.bytes * LC_FIT_PROBE * pixels / ref.pixels,
 *                  bound * budget * LC_FIT_SHARE)      not measured
 *     target = bound * budget * LC_FIT_SHARE           ref a still (no moving frame yet)
 *     bytes(q, pixels) = ref.bytes * share(q) / share(ref.quality) * pixels / ref.pixels
 *
 * ref is the latest moving frame sent, or before any the latest still, and
 * bound a lower bound of the rate (stream_flow.h "carried"): frames of that
 * size cross within the budget for certain, so a session's first moving
 * frames start there, not at the ceiling, and probing never goes below it.
 * quality: the highest in
 * [LC_FIT_MIN_QUALITY, ceiling] whose bytes fit the target; where none does,
 * the floor and a side scale of sqrt(target / bytes(floor)), at least
 * LC_FIT_MIN_SCALE. Where the rate is not measured (no frame waited on the
 * link within the horizon) quality climbs, a quarter more bytes a frame, to
 * the ceiling, and size is the detail ladder's: on a wide link the frames
 * reach the ceiling, on a narrow one they grow until frames wait and the rate
 * is measured. */
#ifndef LC_SERVER_STREAM_FIT_H
#define LC_SERVER_STREAM_FIT_H

#include <stdbool.h>

/* Share of the frame budget a moving frame's transfer may take: its transfer
 * adds to every input-to-frame time, and frames made at the budget's pace keep
 * the link at most this busy, so they seldom queue behind each other (at 0.8
 * they did: on 2 Mbit/s a frame waited 60 ms more than its transfer at p95). */
#define LC_FIT_SHARE 0.4
#define LC_FIT_PROBE 1.25     /* growth of a moving frame's bytes per frame while the rate is not measured */
#define LC_FIT_MIN_QUALITY 30 /* quality goes no lower; size goes down after it (the ceiling, where lower) */
#define LC_FIT_MIN_SCALE 0.5  /* side factor the fit goes down to */

/* The latest moving frame sent: what the next one's bytes are predicted from. */
typedef struct lc_fit_ref {
    double bytes;  /* its message's bytes (0: none yet) */
    int quality;   /* its JPEG quality */
    double pixels; /* its width x height */
    bool still;    /* a still: no moving frame was sent yet */
} lc_fit_ref;

typedef struct lc_fit {
    int quality;   /* JPEG quality of the next moving frame */
    double scale;  /* factor on its side, (LC_FIT_MIN_SCALE..1] */
    double target; /* bytes it aims under (0: no reference yet, the ceiling) */
} lc_fit;

/* JPEG bytes at quality q (1..100) over those at quality 70, for one image:
 * a table measured on this encoder (docs/ALGORITHM.md), linear between. */
double lc_fit_jpeg_share(int q);

/* The next moving frame of `pixels` pixels: rate is the link's measured
 * bytes per second (0: not measured), bound a lower bound of it (0: none),
 * budget_s the frame budget, ceiling the session's interactiveQuality. */
void lc_stream_fit(double rate, double bound, double budget_s, const lc_fit_ref *ref, double pixels, int ceiling,
                   lc_fit *out);

#endif
