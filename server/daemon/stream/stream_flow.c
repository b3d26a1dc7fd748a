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
    double frames = ceil(f->rtt / f->frame_s - 1e-9) + 1;
    f->window = frames < 1 ? 1 : frames > f->ceiling ? f->ceiling : (int)frames;
}

void lc_stream_flow_init(lc_stream_flow *f, int ceiling)
{
    memset(f, 0, sizeof *f);
    f->ceiling = ceiling < 1 ? 1 : ceiling > LC_PROTO_MAX_WINDOW ? LC_PROTO_MAX_WINDOW : ceiling;
    update_window(f);
}

void lc_stream_flow_sent(lc_stream_flow *f, uint64_t id, double now)
{
    if (f->nsent == LC_PROTO_MAX_WINDOW) { /* cannot happen under the window; keep the newest */
        memmove(f->sent_id, f->sent_id + 1, (LC_PROTO_MAX_WINDOW - 1) * sizeof f->sent_id[0]);
        memmove(f->sent_at, f->sent_at + 1, (LC_PROTO_MAX_WINDOW - 1) * sizeof f->sent_at[0]);
        f->nsent--;
    }
    f->sent_id[f->nsent] = id;
    f->sent_at[f->nsent++] = now;
}

void lc_stream_flow_acked(lc_stream_flow *f, uint64_t id, double now)
{
    bool found = false;
    double sent = 0;
    int k = 0;
    for (int i = 0; i < f->nsent; i++) {
        if (f->sent_id[i] <= id) { /* oldest first: the last of these is the newest acked */
            found = true;
            sent = f->sent_at[i];
            continue;
        }
        f->sent_id[k] = f->sent_id[i];
        f->sent_at[k++] = f->sent_at[i];
    }
    f->nsent = k;
    if (!found || now < 0)
        return;
    double sample = now - sent;
    if (sample < 0)
        sample = 0;
    f->rtt_sample[f->nsamples++ % LC_FLOW_RTT_SAMPLES] = sample;
    int held = f->nsamples < LC_FLOW_RTT_SAMPLES ? f->nsamples : LC_FLOW_RTT_SAMPLES;
    double lo = f->rtt_sample[0];
    for (int i = 1; i < held; i++)
        lo = f->rtt_sample[i] < lo ? f->rtt_sample[i] : lo;
    f->rtt = lo > 0 ? lo : 1e-6;
    update_window(f);
}

void lc_stream_flow_forget(lc_stream_flow *f, uint64_t id)
{
    int k = 0;
    for (int i = 0; i < f->nsent; i++)
        if (f->sent_id[i] != id) {
            f->sent_id[k] = f->sent_id[i];
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
