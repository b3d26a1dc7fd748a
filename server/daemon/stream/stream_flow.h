/* The stream's flow-control window (protocol/websocket.md "Flow control"):
 * how many frames a session may have rendering, in flight and unacknowledged.
 * The window covers the round trip at the rate the renderer sustains,
 *
 *     window = clamp(ceil(rtt / frame_s) + 1, 1, ceiling)
 *
 * rtt: the lowest send-to-ack time of the latest LC_FLOW_RTT_SAMPLES frames
 * (a frame handed to the connection until the client's ack of it: the link's
 * round trip, the frame's transmission and the client's decode); frame_s: the
 * smoothed render time of a frame; ceiling: the hello's window. The lowest
 * sample, not the mean, so that frames queued behind each other on a narrow
 * link do not lengthen the round trip they are measured by and widen the
 * window further (the queue would feed itself). Before any ack the window is
 * LC_PROTO_DEFAULT_WINDOW (or the ceiling when lower).
 *
 * No locking and no clock here: the session calls these under its lock with
 * lc_now(), and the unit test with simulated times. */
#ifndef LC_SERVER_STREAM_FLOW_H
#define LC_SERVER_STREAM_FLOW_H

#include <stdint.h>

#include "messages.h"

#define LC_FLOW_RTT_SAMPLES 16 /* send-to-ack samples the round trip is the lowest of */
#define LC_FLOW_FRAME_GAIN 0.25 /* weight of a new render time in frame_s */

typedef struct lc_stream_flow {
    int ceiling;                             /* the most frames unacknowledged (the hello's window) */
    int window;                              /* frames allowed unacknowledged now, 1..ceiling */
    uint64_t sent_id[LC_PROTO_MAX_WINDOW];   /* frames handed to the connection and not yet acked, oldest first */
    double sent_at[LC_PROTO_MAX_WINDOW];     /* when each was */
    int nsent;
    double rtt_sample[LC_FLOW_RTT_SAMPLES];  /* the latest send-to-ack times, seconds (a ring) */
    int nsamples;                            /* samples taken (the ring holds the latest of them) */
    double rtt;                              /* the lowest of the ring, seconds (0: none yet) */
    double frame_s;                          /* smoothed render time of a frame, seconds (0: none yet) */
} lc_stream_flow;

/* A flow before any frame, under the client's ceiling (1..LC_PROTO_MAX_WINDOW). */
void lc_stream_flow_init(lc_stream_flow *f, int ceiling);
/* Frame id was handed to the connection at now. */
void lc_stream_flow_sent(lc_stream_flow *f, uint64_t id, double now);
/* Frames up to id were acked at now: the newest of them sent gives a
 * round-trip sample and the window follows (now < 0: no sample, an ack the
 * server makes itself for a frame that never went out). */
void lc_stream_flow_acked(lc_stream_flow *f, uint64_t id, double now);
/* Frame id will not be acked (it failed or was abandoned): forget it. */
void lc_stream_flow_forget(lc_stream_flow *f, uint64_t id);
/* A frame took seconds to render: the window follows. */
void lc_stream_flow_rendered(lc_stream_flow *f, double seconds);

#endif
