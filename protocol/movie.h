/* The movie request (POST /api/v1/movies, `lucent movie`): a render request,
 * a camera path (turntable, orbit, or keyframes given as cameras or as the web
 * page's URL state), duration/fps or a frame count, size and codec. Parsed and
 * validated here; the path's cameras are computed where the dataset is known
 * (render/math/camera_path.h). */
#ifndef LC_PROTO_MOVIE_H
#define LC_PROTO_MOVIE_H

#include "request.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_MOVIE_MAX_KEYFRAMES 64
#define LC_MOVIE_MAX_FRAMES 18000 /* 10 minutes at 30 fps */
#define LC_MOVIE_MAX_DURATION 600.0
/* A video frame at most 4K UHD: the encoders' memory grows with it (an
 * 8192 x 4608 H.264 job held 2.7 GB, VP9 4.2 GB). */
#define LC_MOVIE_MAX_PIXELS (3840LL * 2160LL)
/* Frames x pixels at most a minute of 4K at 30 fps (10 minutes at 960 x 540;
 * 4 minutes at 1920 x 1080): a job holds one worker for its whole length. */
#define LC_MOVIE_MAX_PIXEL_FRAMES (3840LL * 2160LL * 1800LL)

typedef enum { LC_MOVIE_TURNTABLE = 0, LC_MOVIE_ORBIT = 1, LC_MOVIE_KEYFRAMES = 2 } lc_movie_path;

typedef struct lc_movie_spec {
    lc_request request; /* width/height = the movie's; camera (if set) = where presets start */
    lc_movie_path path;
    double degrees;   /* turntable/orbit: the whole turn (default 360) */
    double elevation; /* orbit: tilt about the view's right axis before turning (default 20) */
    int keyframe_count;
    lc_camera keyframes[LC_MOVIE_MAX_KEYFRAMES];
    int fps;         /* 1..120, default 30 */
    int frames;      /* round(duration * fps), or "frames" as given */
    double duration; /* frames / fps */
    char codec[8];   /* "h264" or "vp9" */
} lc_movie_spec;

/* Parses a movie request (JSON text). Returns 0, or LC_ERR_INVALID / LC_ERR_LIMIT
 * with err naming the field ("keyframes", "fps", "width", "request.params.q",
 * "keyframes[1].position"). Sizes obey lim (side and pixel caps) and must be even.
 * On success m->request holds its layers: lc_request_release it when done. */
int lc_proto_parse_movie(const char *json, size_t len, const lc_proto_limits *lim, lc_movie_spec *m,
                         lc_proto_error *err);

#ifdef __cplusplus
}
#endif
#endif
