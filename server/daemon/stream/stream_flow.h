/* The stream's flow-control window (protocol/websocket.md "Flow control"):
 * how many frames a session may have rendering, in flight and unacknowledged.
 * A frame holds its place from its render's start to its ack. Where the
 * renderer sets the pace, frames start a render apart and the window covers
 * the round trip, the frame being rendered and one frame of headroom (rtt is
 * the lowest round trip and frame_s a mean: without it, a quicker frame or a
 * later ack idles the renderer); where the link does (it takes
 * longer per frame than the renderer), the window is what the link carries
 * in a round trip, which includes one frame's transfer:
 *
 *     window = clamp(ceil(rtt / frame_s) + 2, 2, ceiling)   renderer-bound
 *     window = clamp(ceil(rtt / link_s), 2, ceiling)        link-bound
 *
 * Only moving frames count (a still's transfer is no round trip of a drag).
 * - rtt: the lowest send-to-ack time (a frame handed to the connection until
 *   the client's ack of it: the link's round trip, the frame's transmission
 *   and the client's decode) of frames handed over while no other was
 *   unacknowledged, seen within LC_FLOW_RTT_HORIZON seconds; a lower sample
 *   replaces it at once, a higher one once the lowest is that old. Such
 *   frames, and the lowest of them, so that frames queued behind each other
 *   on a narrow link (or behind a still) do not lengthen the round trip they
 *   are measured by and widen the window further (the queue would feed
 *   itself). A gesture's first frame is such a frame.
 * - frame_s: the smoothed render time of a moving frame.
 * - link_s: the link's time per frame, where longer than frame_s: the
 *   smoothed spacing of acks at times when frames wait on the link (the smoothed
 *   send-to-ack time, srtt, exceeds rtt by half the smoothed ack spacing
 *   ack_s or more). It holds for
 *   LC_FLOW_RTT_HORIZON seconds after it was last measured, since a window
 *   that fits the link drains the queue that measured it.
 * - 2 at least (LC_PROTO_DEFAULT_WINDOW, or the ceiling where that is lower):
 *   one frame rendering while one crosses. Before the first ack of a moving
 *   frame the window is that too.
 * - ceiling: the hello's window (LC_PROTO_MAX_WINDOW without one).
 *
 * The link's throughput comes from the same acks (stream_fit.h spends it):
 * - measured: the smoothed bytes per ack over the smoothed ack spacing, of
 *   acks of frames that waited on the link: their send-to-ack time less the
 *   spacing from the ack before exceeds rtt (a frame sent to an idle link
 *   has base + transfer against a spacing of at least its transfer; one that
 *   waited, wait + base + transfer against a spacing of its transfer, as the
 *   link carried the frame before it until its own began; so the test holds
 *   where it waited longer than one frame's transfer, and the spacing is its
 *   transfer).
 *   It counts from the LC_FLOW_WAITS-th such ack (one late ack, a stall of
 *   the client or of a loaded host, is no queue) and holds for
 *   LC_FLOW_RTT_HORIZON seconds after the last; a new measurement after that
 *   starts afresh.
 * - from sizes, where no frame waited: a frame's send-to-ack time is the
 *   round trip plus its bytes over the rate (plus any wait), so two frames of
 *   different sizes give the rate by their difference,
 *       rate = (B - b) / (T - t)
 *   with b, t the moving frame of the lowest send-to-ack time within the
 *   horizon (the least waiting) and B, T the frame of the most bytes per
 *   send-to-ack time within it (a still, or a gesture's first, larger moving
 *   frame: the largest that did not wait), where B is at least
 *   LC_FLOW_SIZE_RATIO times b and T exceeds t. A wait of either frame
 *   lengthens T - t and lowers the figure, never raises it past the rate
 *   (up to the timing noise of t). It is what fits the moving frames on a
 *   link that carries them with room to spare, where none waits.
 * - carried: the same over every ack of a moving frame within a gesture, what
 *   the link was seen to carry, or where higher the most bytes over
 *   send-to-ack time of one frame within the horizon, a still too (its bytes
 *   crossed the link before its ack left): lower bounds of the rate, which is
 *   all that is known where no frame waited and the sizes tell nothing (a
 *   wide link, whose transfers vanish in the timing noise).
 *
 * No locking and no clock here: the session calls these under its lock with
 * lc_now(), and the unit test with simulated times. */
#ifndef LC_SERVER_STREAM_FLOW_H
#define LC_SERVER_STREAM_FLOW_H

#include <stdbool.h>
#include <stdint.h>

#include "messages.h"

#define LC_FLOW_RTT_HORIZON 10.0 /* seconds the lowest send-to-ack time holds against higher ones */
#define LC_FLOW_FRAME_GAIN 0.25  /* weight of a new render time in frame_s, of a new ack gap in ack_s */
#define LC_FLOW_WAITS 3          /* acks of frames that waited before their spacing counts as the link's rate */
#define LC_FLOW_ACK_GAP_MAX 1.0  /* seconds between acks beyond which the next starts a new gesture */
#define LC_FLOW_SIZE_RATIO 2.0   /* bytes of the larger frame over the smaller's for a rate from sizes */

typedef struct lc_stream_flow {
    int ceiling;                            /* the most frames unacknowledged (the hello's window) */
    int window;                             /* frames allowed unacknowledged now, 2..ceiling (the ceiling if lower) */
    uint64_t sent_id[LC_PROTO_MAX_WINDOW];  /* frames handed to the connection and not yet acked, oldest first */
    double sent_at[LC_PROTO_MAX_WINDOW];    /* when each was */
    bool sent_moving[LC_PROTO_MAX_WINDOW];  /* whether it was a moving frame */
    bool sent_alone[LC_PROTO_MAX_WINDOW];   /* whether no other frame was unacknowledged then */
    double sent_bytes[LC_PROTO_MAX_WINDOW]; /* its message's bytes */
    int nsent;
    int nsamples;                          /* send-to-ack samples taken */
    double rtt;                            /* the lowest within the horizon, seconds (0: none yet) */
    double rtt_at;                         /* when it was seen */
    double ack_s;                          /* smoothed seconds between acks of moving frames (0: none yet) */
    double srtt;                           /* smoothed send-to-ack time of moving frames */
    double link_s;                         /* smoothed spacing of acks while frames waited on the link (0: none) */
    double link_at;                        /* when it was last measured */
    double last_ack;                       /* when the latest such ack came */
    double frame_s;                        /* smoothed render time of a moving frame, seconds (0: none yet) */
    double ack_bytes;                      /* smoothed bytes of moving frames an ack covers (with ack_s) */
    double wait_bytes, wait_s;             /* the same and the acks' spacing, of frames that waited on the link */
    double wait_at;                        /* when such an ack last came (0: never) */
    int waits;                             /* such acks since the measurement began */
    double bound, bound_at;                /* the highest bytes / send-to-ack of one frame, and when */
    double bound_bytes, bound_s;           /* that frame's bytes and send-to-ack time */
    double small_bytes, small_s, small_at; /* the moving frame of the lowest send-to-ack: bytes, time, when */
} lc_stream_flow;

/* A flow before any frame, under the client's ceiling (1..LC_PROTO_MAX_WINDOW). */
void lc_stream_flow_init(lc_stream_flow *f, int ceiling);
/* Frame id (moving: a moving frame) of `bytes` was handed to the connection at now. */
void lc_stream_flow_sent(lc_stream_flow *f, uint64_t id, bool moving, double bytes, double now);
/* Frames up to id were acked at now: the newest of them sent gives a
 * round-trip sample and the window follows (now < 0: no sample, an ack the
 * server makes itself for a frame that never went out). */
void lc_stream_flow_acked(lc_stream_flow *f, uint64_t id, double now);
/* Frame id will not be acked (it failed or was abandoned): forget it. */
void lc_stream_flow_forget(lc_stream_flow *f, uint64_t id);
/* A frame took seconds to render: the window follows. */
void lc_stream_flow_rendered(lc_stream_flow *f, double seconds);
/* The link's throughput in bytes per second: *measured true where frames
 * waited on it within the horizon, or a larger frame's transfer told it from
 * a smaller's (its rate), false otherwise (what it carried, a lower bound; 0
 * before an ack). */
double lc_stream_flow_link_rate(const lc_stream_flow *f, bool *measured);

#endif
