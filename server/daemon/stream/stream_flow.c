/* The stream's flow-control window from the round trip and the render rate (stream_flow.h). */
#include "stream_flow.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

static void update_window(lc_stream_flow *f)
{
    if (f->rtt <= 0 || f->frame_s <= 0) {
        f->window = f->ceiling < LC_PROTO_DEFAULT_WINDOW ? f->ceiling : LC_PROTO_DEFAULT_WINDOW;
        return;
    }
    bool link_bound = f->link_s > f->frame_s && f->last_ack - f->link_at < LC_FLOW_RTT_HORIZON;
    double frames = link_bound ? ceil(f->rtt / f->link_s - 1e-9) : ceil(f->rtt / f->frame_s - 1e-9) + 2;
    int floor = f->ceiling < LC_PROTO_DEFAULT_WINDOW ? f->ceiling : LC_PROTO_DEFAULT_WINDOW;
    f->window = frames < floor ? floor : frames > f->ceiling ? f->ceiling : (int)frames;
}

void lc_stream_flow_init(lc_stream_flow *f, int ceiling)
{
    memset(f, 0, sizeof *f);
    f->ceiling = ceiling < 1 ? 1 : ceiling > LC_PROTO_MAX_WINDOW ? LC_PROTO_MAX_WINDOW : ceiling;
    update_window(f);
}

void lc_stream_flow_sent(lc_stream_flow *f, uint64_t id, bool moving, double bytes, double now)
{
    if (f->nsent == LC_PROTO_MAX_WINDOW) { /* cannot happen under the window; keep the newest */
        memmove(f->sent_id, f->sent_id + 1, (LC_PROTO_MAX_WINDOW - 1) * sizeof f->sent_id[0]);
        memmove(f->sent_at, f->sent_at + 1, (LC_PROTO_MAX_WINDOW - 1) * sizeof f->sent_at[0]);
        memmove(f->sent_moving, f->sent_moving + 1, (LC_PROTO_MAX_WINDOW - 1) * sizeof f->sent_moving[0]);
        memmove(f->sent_alone, f->sent_alone + 1, (LC_PROTO_MAX_WINDOW - 1) * sizeof f->sent_alone[0]);
        memmove(f->sent_bytes, f->sent_bytes + 1, (LC_PROTO_MAX_WINDOW - 1) * sizeof f->sent_bytes[0]);
        f->nsent--;
    }
    f->sent_id[f->nsent] = id;
    f->sent_moving[f->nsent] = moving;
    f->sent_alone[f->nsent] = f->nsent == 0;
    f->sent_bytes[f->nsent] = bytes > 0 ? bytes : 0;
    f->sent_at[f->nsent++] = now;
}

void lc_stream_flow_acked(lc_stream_flow *f, uint64_t id, double now)
{
    bool found = false, moving = false, alone = false;
    double sent = 0, bytes = 0, newest = 0;
    int k = 0;
    for (int i = 0; i < f->nsent; i++) {
        if (f->sent_id[i] <= id) { /* oldest first: the last of these is the newest acked */
            found = true;
            bytes += f->sent_moving[i] ? f->sent_bytes[i] : 0;
            newest = f->sent_bytes[i];
            sent = f->sent_at[i];
            moving = f->sent_moving[i];
            alone = f->sent_alone[i];
            continue;
        }
        f->sent_id[k] = f->sent_id[i];
        f->sent_moving[k] = f->sent_moving[i];
        f->sent_alone[k] = f->sent_alone[i];
        f->sent_bytes[k] = f->sent_bytes[i];
        f->sent_at[k++] = f->sent_at[i];
    }
    f->nsent = k;
    if (!found || now < 0)
        return;
    /* Any frame, a still too: its bytes crossed the link before its ack left,
     * so bytes / send-to-ack is at most the link's rate; a large frame's is
     * close to it. The highest within the horizon. */
    double bound = now > sent ? newest / (now - sent) : 0;
    if (bound >= f->bound || now - f->bound_at > LC_FLOW_RTT_HORIZON) {
        f->bound = bound;
        f->bound_at = now;
        f->bound_bytes = newest;
        f->bound_s = now - sent;
    }
    if (!moving)
        return;
    /* The least-waiting moving frame: the small end of the rate from sizes. */
    if (f->small_at <= 0 || now - sent <= f->small_s || now - f->small_at > LC_FLOW_RTT_HORIZON) {
        f->small_bytes = newest;
        f->small_s = now - sent > 0 ? now - sent : 0;
        f->small_at = now;
    }
    /* The spacing of acks within a gesture: what the link delivers. */
    double gap = now - f->last_ack, sample = now - sent;
    if (f->last_ack > 0 && gap >= 0 && gap < LC_FLOW_ACK_GAP_MAX) {
        /* This frame waited on the link: the gap is its transfer. A frame
         * taken at once has sample = base + transfer with gap >= transfer,
         * one that waited sample = wait + base + transfer with gap =
         * transfer, so sample - gap exceeds rtt (base + one frame's
         * transfer) only where it waited longer than a frame's transfer, and
         * a late ack of this frame (jitter) moves both alike. Acks that
         * come slower than frames are rendered are no such test: where the
         * window holds the renderer back they do too, and a rate read from
         * them shrinks the frames that set it. Smoothed bytes over smoothed
         * gaps, so acks that bunch do not count as rate. */
        if (f->rtt > 0 && sample - gap > f->rtt) {
            bool fresh = f->wait_at > 0 && f->last_ack - f->wait_at < LC_FLOW_RTT_HORIZON;
            f->waits = fresh ? f->waits + 1 : 1;
            f->wait_s = fresh ? f->wait_s + LC_FLOW_FRAME_GAIN * (gap - f->wait_s) : gap;
            f->wait_bytes = fresh ? f->wait_bytes + LC_FLOW_FRAME_GAIN * (bytes - f->wait_bytes) : bytes;
            f->wait_at = now;
        }
        f->ack_bytes = f->ack_s > 0 ? f->ack_bytes + LC_FLOW_FRAME_GAIN * (bytes - f->ack_bytes) : bytes;
        f->ack_s = f->ack_s > 0 ? f->ack_s + LC_FLOW_FRAME_GAIN * (gap - f->ack_s) : gap;
        /* Frames wait on the link: the acks' spacing is its time per frame. */
        if (f->srtt > f->rtt + 0.5 * f->ack_s) {
            f->link_s = f->link_s > 0 ? f->link_s + LC_FLOW_FRAME_GAIN * (gap - f->link_s) : gap;
            f->link_at = now;
        }
    }
    f->last_ack = now;
    if (sample < 0)
        sample = 0;
    f->nsamples++;
    f->srtt = f->srtt > 0 ? f->srtt + LC_FLOW_FRAME_GAIN * (sample - f->srtt) : sample;
    if (alone && (f->rtt <= 0 || sample <= f->rtt || now - f->rtt_at > LC_FLOW_RTT_HORIZON)) {
        f->rtt = sample > 0 ? sample : 1e-6;
        f->rtt_at = now;
    }
    update_window(f);
}

void lc_stream_flow_forget(lc_stream_flow *f, uint64_t id)
{
    int k = 0;
    for (int i = 0; i < f->nsent; i++)
        if (f->sent_id[i] != id) {
            f->sent_id[k] = f->sent_id[i];
            f->sent_moving[k] = f->sent_moving[i];
            f->sent_alone[k] = f->sent_alone[i];
            f->sent_bytes[k] = f->sent_bytes[i];
            f->sent_at[k++] = f->sent_at[i];
        }
    f->nsent = k;
}

void lc_stream_flow_rendered(lc_stream_flow *f, double seconds)
{
    if (seconds <= 0)
        return;
    f->frame_s = f->frame_s > 0 ? f->frame_s + LC_FLOW_FRAME_GAIN * (seconds - f->frame_s) : seconds;
    update_window(f);
}

/* The rate from a larger frame's longer transfer (stream_flow.h "from
 * sizes"), 0 where the two frames tell none: no pair within the horizon of
 * each other, sizes too alike, or times the noise could order either way. */
static double size_rate(const lc_stream_flow *f)
{
    if (f->small_at <= 0 || f->bound_at <= 0 || fabs(f->small_at - f->bound_at) > LC_FLOW_RTT_HORIZON)
        return 0;
    if (f->bound_bytes < LC_FLOW_SIZE_RATIO * f->small_bytes || f->bound_s <= f->small_s)
        return 0;
    return (f->bound_bytes - f->small_bytes) / (f->bound_s - f->small_s);
}

double lc_stream_flow_link_rate(const lc_stream_flow *f, bool *measured)
{
    *measured = f->waits >= LC_FLOW_WAITS && f->wait_s > 0 && f->last_ack - f->wait_at < LC_FLOW_RTT_HORIZON;
    if (*measured)
        return f->wait_bytes / f->wait_s;
    double carried = f->ack_s > 0 ? f->ack_bytes / f->ack_s : 0;
    carried = carried > f->bound ? carried : f->bound;
    double sizes = size_rate(f);
    *measured = sizes > 0;
    return sizes > carried ? sizes : carried;
}
