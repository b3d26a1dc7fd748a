/* A WebSocket session's frame flow (stream_session.c): which frame is due
 * next at what size, detail and quality, and the bookkeeping of the frames
 * rendered, sent, acked or abandoned. Every function takes s->lock itself.
 * The workers (pool/), the encoders and the I/O thread (ws.c, stream.c) call
 * it; it calls nothing above the session. */
#ifndef LC_SERVER_STREAM_SESSION_H
#define LC_SERVER_STREAM_SESSION_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "session.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Worker side: decides whether s needs a frame now. Returns 1 with *out filled
 * and the frame state reserved (stream.rendering; out->req holds a reference to
 * the session's layers: lc_request_release it), 0 when nothing is due; then
 * *wake_at > 0 asks to be reconsidered at that lc_now() time (the still frame). */
int lc_session_stream_next(lc_session *s, double now, lc_stream_frame *out, double *wake_at);
/* Worker side: the frame reserved by stream_next finished (ok = rendered). */
void lc_session_stream_done(lc_session *s, const lc_stream_frame *f, bool ok, const lc_frame_info *info);
/* Worker side, during a still or refinement (not interactive) frame: whether
 * it should be abandoned for newer input (a camera/params/resize update came
 * since stream_next took it) or because the session closed. */
bool lc_session_stream_preempted(lc_session *s);
/* Worker side: the frame reserved by stream_next was abandoned at a yield
 * point (nothing goes out for it, and its id goes to the next frame); the
 * session stays as it was before that frame, so its still is due again once
 * input is quiet, and the next frame is a moving one. */
void lc_session_stream_yielded(lc_session *s, const lc_stream_frame *f);
/* Worker side: a frame of s begins (its progress starts at "prepare"). */
void lc_session_progress_begin(lc_session *s, uint64_t frame);
/* I/O side: the client acknowledged every frame up to id `frame`. Returns
 * false (and changes nothing) for an id that was never sent: a blind ack must
 * not open the window. */
bool lc_session_stream_ack(lc_session *s, uint64_t frame);
/* I/O side: the client acked frames up to `frame` at now: as lc_session_stream_ack,
 * and the round trip of the newest of them moves the window (stream_flow.h). */
bool lc_session_stream_client_ack(lc_session *s, uint64_t frame, double now);
/* Encoder side: frame `frame` goes to the connection now (acks may cover it),
 * a message of `bytes` (0: none goes out) at JPEG quality and of pixels:
 * a moving frame's are what the next one's fit is predicted from. Returns
 * false, and records nothing, for a frame older than one already handed
 * over: it must not go out (it would show an older camera last). */
bool lc_session_stream_sent(lc_session *s, uint64_t frame, size_t bytes, int quality, long pixels);
/* I/O side: the connection's socket stopped taking data (blocked) or drained.
 * Returns true when it drained and a frame may be due (wake the workers). */
bool lc_session_stream_blocked(lc_session *s, bool blocked);
/* I/O side: records input (camera, params, resize): marks the stream dirty and
 * counts a coalesced update if the previous one was not rendered yet. */
void lc_session_stream_input(lc_session *s, double now);
/* The pixel size of a stream frame for a viewport of css_w x css_h CSS pixels
 * at devicePixelRatio dpr: capped by cfg's --max-stream-pixels and image
 * limits, times scale (interactive frames). Every stream frame's size comes
 * from here: hello and resize check the full-size frame's cost with it, and
 * lc_session_stream_next sizes each frame. */
void lc_stream_frame_size(const lc_serve_config *cfg, int css_w, int css_h, double dpr, double scale, int *w, int *h);

#ifdef __cplusplus
}
#endif
#endif
