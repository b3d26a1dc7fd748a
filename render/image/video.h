/* Video files from RGBA frames: H.264 in MP4 (libx264) and VP9 in WebM
 * (libvpx) through Debian's libavcodec/libavformat, yuv420p. Knows nothing of
 * rendering: the movie jobs of the daemon and `lucent movie` feed it frames.
 * Built without libavcodec (LUCENT_VIDEO undefined) every call answers
 * LC_ERR_UNSUPPORTED. */
#ifndef LC_IMAGE_VIDEO_H
#define LC_IMAGE_VIDEO_H

#include <stdbool.h>
#include <stdint.h>

#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { LC_VIDEO_H264 = 0, LC_VIDEO_VP9 = 1 } lc_video_codec;

/* "h264" / "vp9" -> codec; -1 when unknown. */
int lc_video_codec_from_name(const char *name);
const char *lc_video_codec_name(lc_video_codec c);
/* File extension and MIME type of the container ("mp4", "video/mp4"). */
const char *lc_video_extension(lc_video_codec c);
const char *lc_video_mime(lc_video_codec c);
/* Whether this build has the codec's encoder (libavcodec found at build time
 * and the encoder present at run time). */
bool lc_video_available(lc_video_codec c);

typedef struct lc_video lc_video;

/* Creates path and opens the encoder. width and height must be even (4:2:0
 * chroma), fps in 1..240. */
int lc_video_open(const char *path, lc_video_codec codec, int width, int height, int fps, lc_video **out,
                  lc_error *err);
/* Appends one frame of width x height RGBA pixels, top row first. */
int lc_video_write(lc_video *v, const uint8_t *rgba, lc_error *err);
/* Flushes the encoder, writes the trailer, closes the file and frees v
 * (also on error). */
int lc_video_close(lc_video *v, lc_error *err);
/* Frees v without finishing the file, and deletes the file. */
void lc_video_abort(lc_video *v);

#ifdef __cplusplus
}
#endif
#endif
