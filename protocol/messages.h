/* WebSocket session messages (client JSON, server JSON, binary frames) and the
 * HTTP error body. protocol/websocket.md is the spec.
 *
 * Threading: reentrant, no global state. Builders return malloc'd text that the
 * caller free()s; NULL only on allocation failure. */
#ifndef LC_PROTOCOL_MESSAGES_H
#define LC_PROTOCOL_MESSAGES_H

#include <jansson.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "request.h"
#include "request_patch.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_PROTO_DEFAULT_WINDOW 2 /* unacknowledged frames per session */
#define LC_PROTO_MAX_WINDOW 8
#define LC_PROTO_DEFAULT_INTERACTIVE_QUALITY 85
#define LC_PROTO_DEFAULT_INTERACTIVE_SCALE 0.5
#define LC_PROTO_MIN_INTERACTIVE_SCALE 0.25
#define LC_PROTO_MAX_DEVICE_PIXEL_RATIO 8.0
#define LC_PROTO_TOKEN_LEN 256
#define LC_PROTO_MAX_SEQ 9007199254740991ULL /* 2^53 - 1: exact in a JavaScript number */

typedef enum { LC_MSG_HELLO, LC_MSG_CAMERA, LC_MSG_PARAMS, LC_MSG_RESIZE, LC_MSG_ACK } lc_msg_type;

/* One client -> server message. Absent optional fields hold their default and a
 * false has_ flag. */
typedef struct lc_client_msg {
    lc_msg_type type;
    /* hello */
    char dataset[LC_PROTO_DATASET_LEN]; /* "" = server default */
    bool has_dataset;
    char token[LC_PROTO_TOKEN_LEN];
    bool has_token;
    int window; /* 1..8, default 2 */
    bool has_window;
    /* hello (required), resize (required): viewport in CSS pixels, 1..max_size */
    int width, height;
    double device_pixel_ratio; /* (0, 8], default 1; hello and resize */
    bool has_device_pixel_ratio;
    /* camera (required) */
    uint64_t seq;
    /* ack (required) */
    uint64_t frame;
    /* hello, params: stream quality */
    int quality; /* still-frame JPEG quality 1..100, default 90 */
    bool has_quality;
    int interactive_quality; /* JPEG quality while input is active, 1..100, default 70 */
    bool has_interactive_quality;
    double interactive_scale; /* resolution factor while input is active, [0.25, 1], default 0.5 */
    bool has_interactive_scale;
    /* hello, params, camera: an object holding only the render-request fields the
     * message gave (camera, params, importance, color, style, method), and the
     * same parsed once into a typed patch whose field checks have run; merge it
     * into the session's request with lc_proto_patch_apply() (request_patch.h, which runs the
     * cross-field checks). Both NULL when none given. Owned by the message;
     * freed by lc_client_msg_free(). */
    json_t *update;
    lc_request_patch *patch;
} lc_client_msg;

/* Parses and validates one client text message. On success m owns update; on
 * error m is left empty (nothing to free, though lc_client_msg_free() is safe).
 * Returns 0, LC_ERR_INVALID or LC_ERR_LIMIT (too_large/too_deep). */
int lc_proto_parse_client_message(const char *text, size_t len, const lc_proto_limits *lim, lc_client_msg *m,
                                  lc_proto_error *err);
void lc_client_msg_free(lc_client_msg *m);

/* The message as JSON with only the given fields (for C clients, tests and
 * benchmarks); parsing its dump gives an equal message. Caller json_decref()s. */
json_t *lc_proto_client_message_to_json(const lc_client_msg *m);

/* Short name of a message type ("hello", ...). */
const char *lc_proto_msg_type_name(lc_msg_type t);

/* ---- server -> client text messages */

/* Flow-control and quality settings of a stream (hello/params can change them). */
typedef struct lc_stream_settings {
    int window;               /* unacknowledged frames, 1..8 */
    int quality;              /* still-frame JPEG quality */
    int interactive_quality;  /* JPEG quality while input is active */
    double interactive_scale; /* resolution factor while input is active */
} lc_stream_settings;

/* window 2, quality 90, interactiveQuality 70, interactiveScale 0.5. */
void lc_proto_stream_default(lc_stream_settings *s);
/* Copies the stream fields a hello/params message gave into s. */
void lc_proto_stream_apply(lc_stream_settings *s, const lc_client_msg *m);

/* {"type":"ready","session":ID,"dataset":INFO,"defaults":REQUEST,"limits":{...},
 *  "stream":{"window","quality","interactiveQuality","interactiveScale"}}.
 * dataset_info is borrowed (any JSON object the server builds; NULL -> null);
 * defaults is the session's initial request; lim NULL = defaults; stream NULL =
 * lc_proto_stream_default(). */
char *lc_proto_ready_json(const char *session, const json_t *dataset_info, const lc_request *defaults,
                          const lc_proto_limits *lim, const lc_stream_settings *stream);

/* {"type":"error","code":..,"message":..,"field":..?,"fatal":bool}. field NULL
 * or "" is omitted. fatal = the server closes the session after sending it. */
char *lc_proto_error_message_json(const char *code, const char *message, const char *field, bool fatal);

/* {"type":"stats", ...fields}: fields is borrowed, its keys are copied after
 * "type" (a "type" key in it is ignored). websocket.md lists the usual keys. */
char *lc_proto_stats_json(const json_t *fields);

/* {"type":"progress","stage":..,"fraction":f|null,"elapsed":s}: a frame the
 * client waits for is under way. fraction < 0 = not known (null); elapsed is
 * rounded to the millisecond. */
char *lc_proto_progress_json(const char *stage, double fraction, double elapsed);

/* HTTP error body {"error":{"code":..,"message":..,"field":..?}}. */
char *lc_proto_error_json(const char *code, const char *message, const char *field);
/* Same from a filled lc_proto_error. */
char *lc_proto_error_json_from(const lc_proto_error *err);

/* ---- binary frame messages:
 *   uint32 little-endian N | N bytes UTF-8 JSON header | image bytes */

#define LC_PROTO_MAX_TIMINGS 16
#define LC_PROTO_MAX_FRAME_HEADER 4096 /* bytes of header JSON accepted by unpack */

typedef struct lc_frame_timing {
    char pass[32]; /* "importance", "opacity", ... (the renderer's pass names) */
    double ms;
} lc_frame_timing;

typedef struct lc_frame_header {
    uint64_t frame;         /* frame id, what the client acks */
    int width, height;      /* pixels of this image */
    lc_image_format format; /* jpeg for streams, png possible */
    int quality;            /* JPEG quality used (0 for png) */
    uint64_t camera_seq;    /* last camera seq this frame reflects (0 = none yet) */
    bool converged;         /* the session's opacities stopped fading */
    int timing_count;
    lc_frame_timing timings[LC_PROTO_MAX_TIMINGS];
    double encode_ms;
    /* "visibility" (optional): how visible the important and the unimportant
     * elements are in this frame (docs/ALGORITHM.md "Visibility report"). */
    bool has_visibility;
    double top_decile_alpha, bottom_half_alpha, covered_fraction;
    double occluder_alpha;     /* "occluderAlpha"; 0 when a sender omits it */
    double important_occluded; /* "importantOccluded"; 0 when a sender omits it */
    /* "topDecileReach" (optional, >= 0): the top decile's share of the
     * importance shown over its share of the importance drawn. */
    bool has_reach;
    double top_decile_reach;
    /* "visibility.layers" (layered frames): each layer's topDecileAlpha,
     * bottomHalfAlpha and occluderAlpha, in the request's layer order. */
    int layer_count;
    double layer_visibility[LC_MAX_LAYERS][3];
    /* "detail" (optional): what the frame drew (docs/ALGORITHM.md "Level of
     * detail and interactive frames"). */
    bool has_detail;
    bool interactive;    /* rendered while input was active */
    bool reused;         /* P1-P3 skipped: the opacities of an earlier frame */
    int level;           /* level of detail, 0 = every segment */
    double lod_pixels;   /* the pixel bound it was chosen for */
    int point_stride;    /* points: every n-th drawn */
    int line_stride;     /* lines: one in n of the less important lines drawn (0 from a sender without it: 1) */
    uint64_t primitives; /* primitives drawn per geometry pass */
    double render_ms;    /* wall time of the render */
    /* "colorTicks" (optional): with color.equalize, the data values at 0,
     * 1/4, 1/2, 3/4 and 1 of the colormap's bar (docs/ALGORITHM.md §19). */
    bool has_color_ticks;
    double color_ticks[5];
    /* "clarity" (optional, params.clarity on): the factors on λ and on q and r
     * the frame used, and whether it met the goal (false: where it stopped). */
    bool has_clarity, clarity_reached;
    double clarity_lambda, clarity_penalty;
    bool has_clarity_smoothing; /* "clarity.smoothing" (optional): the iterations the loop cut smoothing to */
    int clarity_smoothing;
    /* "surface" (optional; method surface-layers): curves traced so far, the
     * particles asked for, mean layers per covered pixel, fragments dropped
     * beyond k layers, k (docs/ALGORITHM.md §23). */
    bool has_surface;
    uint64_t surface_curves, surface_particles, surface_overflow;
    /* "drawnCurves", "drawnFragments", "kept": this frame's work on the
     * layers (only the new curves when the frame before's layers were kept). */
    uint64_t surface_drawn_curves, surface_drawn_fragments;
    bool surface_kept;
    double surface_layers;
    int surface_k;
    /* "stage", "stages", "final" (optional): a staged still's stage (1..stages);
     * stages 0 = not staged (a still without them is final). */
    int stage, stages;
} lc_frame_header;

/* Packs header + image into one malloc'd binary message (*out, free()).
 * Returns 0 or LC_ERR_NOMEM / LC_ERR_INVALID (bad header values). */
int lc_proto_pack_frame(const lc_frame_header *h, const unsigned char *image, size_t image_len, unsigned char **out,
                        size_t *out_len);

/* Splits a binary frame message: fills h and points *image into msg (no copy).
 * Unknown header keys are ignored (forward compatibility). Returns 0 or
 * LC_ERR_INVALID with err filled. */
int lc_proto_unpack_frame(const unsigned char *msg, size_t len, lc_frame_header *h, const unsigned char **image,
                          size_t *image_len, lc_proto_error *err);

#ifdef __cplusplus
}
#endif
#endif
