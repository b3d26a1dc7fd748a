/* `lucent movie`: the daemon's movie jobs offline: a movie request (the body
 * of POST /api/v1/movies, protocol/movie.h) rendered on this machine with
 * fading opacities (dt = 1/fps) and encoded to H.264/MP4 or VP9/WebM. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera_path.h"
#include "cli.h"
#include "lc_options.h"
#include "movie.h"
#include "video.h"

typedef struct movie_args {
    const char *out;
    const char *input;
    int device;
} movie_args;

#define MOVIE(member) LC_OPT_AT(movie_args, member)
static const lc_option movie_options[] = {
    {"--out", "OUT.mp4|OUT.webm", LC_OPT_TEXT, MOVIE(out),
     .help = "the movie file (its extension must match the codec)"},
    {"-o", "OUT", LC_OPT_TEXT, MOVIE(out), .help = NULL}, /* alias of --out */
    {"--input", "FILE|demo:NAME", LC_OPT_TEXT, MOVIE(input), .help = "a dataset file instead of the request's dataset"},
    {"--device", "N", LC_OPT_INT, MOVIE(device), 0, 255,
     .help = "EGL device index (default: LUCENT_EGL_DEVICE or the first GPU)"},
    {NULL}};

static void movie_usage(FILE *f, const lc_opt_set *sets, int nsets)
{
    fprintf(f, "usage: lucent movie MOVIE.json -o OUT.mp4|OUT.webm [--input FILE|demo:NAME] [--device N]\n"
               "Renders a movie request (the JSON of POST /api/v1/movies: request, path turntable|orbit|keyframes,\n"
               "keyframes, degrees, elevation, duration or frames, fps, width, height, codec h264|vp9;\n"
               "protocol/README.md \"Movies\") and encodes it. \"{}\" is a 10 s turntable of demo:tornado at 960x540.\n"
               "A request with layers[] (several datasets in one view) names each dataset as --input does.\n");
    lc_opt_usage(f, sets, nsets);
}

static char *read_text(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 20; /* far beyond any movie request; the parser caps JSON at 64 KiB anyway */
    char *buf = malloc(cap + 1);
    *len = buf ? fread(buf, 1, cap + 1, f) : 0;
    fclose(f);
    return buf; /* a longer file reads as cap + 1 bytes, which the parser refuses as too large */
}

int lc_cli_movie(int argc, char **argv)
{
    movie_args args = {.device = -1};
    lc_opt_set sets[] = {{movie_options, &args}};
    const char *spec_path = NULL;
    int npos = 0;
    int prc = lc_opt_parse("movie", sets, 1, argc, argv, &spec_path, 1, &npos);
    if (prc != 0) {
        if (prc < 0 || !lc_cli_has_flag(argc, argv, "--list-flags"))
            movie_usage(prc > 0 ? stdout : stderr, sets, 1);
        return prc > 0 ? 0 : 2;
    }
    const char *out = args.out;
    lc_cli_common common = {.device = args.device, .input = args.input};
    if (!spec_path || !out) {
        fprintf(stderr, "lucent movie: %s is required (lucent movie --help lists the options)\n",
                spec_path ? "-o OUT.mp4|OUT.webm" : "a MOVIE.json");
        return 2;
    }
    size_t len = 0;
    char *text = read_text(spec_path, &len);
    if (!text) {
        fprintf(stderr, "lucent movie: %s: cannot read\n", spec_path);
        return 1;
    }
    static lc_movie_spec m;
    lc_proto_error pe;
    int rc = lc_proto_parse_movie(text, len, NULL, &m, &pe);
    free(text);
    if (rc != 0) {
        fprintf(stderr, "lucent movie: %s: %s\n", spec_path, pe.message);
        return 2;
    }
    lc_video_codec codec = (lc_video_codec)lc_video_codec_from_name(m.codec);
    const char *ext = strrchr(out, '.');
    if (!ext || strcmp(ext + 1, lc_video_extension(codec)) != 0) {
        fprintf(stderr, "lucent movie: %s: codec %s writes .%s files\n", out, m.codec, lc_video_extension(codec));
        return 2;
    }
    /* One dataset, or the request's layers[]: every frame a layered frame. */
    static lc_cli_scene cs;
    lc_cli_gl g = {0};
    if (lc_cli_scene_open("movie", &m.request, &common, &cs, &g) != 0)
        return 1;
    int status = 1;
    lc_frame_state *state = NULL;
    lc_video *v = NULL;
    lc_error err = {0};
    int w = m.request.render.width, h = m.request.render.height;
    uint8_t *rgba = malloc((size_t)w * h * 4);
    if (!rgba || !(state = lc_cli_frame_state(&common, (uint32_t)lc_cli_scene_elements(&cs)))) {
        fprintf(stderr, "lucent movie: out of memory\n");
        goto done;
    }
    if (lc_video_open(out, codec, w, h, m.fps, &v, &err) != 0) {
        fprintf(stderr, "lucent movie: %s\n", err.msg);
        goto done;
    }
    lc_camera start = m.request.render.camera;
    if (!m.request.render.has_camera) /* as a request without camera: the suggested view, fitted (to every layer) */
        lc_cli_scene_camera(&cs, &start);
    lc_camera_path_desc path = {.kind = (int)m.path,
                                .degrees = m.degrees,
                                .elevation = m.elevation,
                                .keys = m.keyframes,
                                .key_count = m.keyframe_count,
                                .frames = m.frames};
    lc_render_params p = m.request.render;
    p.has_camera = true;
    for (int i = 0; i < m.frames; i++) {
        lc_frame_info info;
        lc_camera_path_frame(&path, &start, i, &p.camera);
        /* Frame 0 shows its targets; then the opacities fade with the movie's clock. */
        if (lc_cli_scene_render(g.renderer, &cs, &p, state, i == 0 ? 1e6 : 1.0 / m.fps, rgba, &info, &err) != 0 ||
            lc_video_write(v, rgba, &err) != 0) {
            fprintf(stderr, "lucent movie: frame %d: %s\n", i, err.msg);
            goto done;
        }
        if (i % m.fps == m.fps - 1 || i == m.frames - 1)
            fprintf(stderr, "\rlucent movie: %d of %d frames", i + 1, m.frames);
    }
    fputc('\n', stderr);
    rc = lc_video_close(v, &err);
    v = NULL;
    if (rc != 0) {
        fprintf(stderr, "lucent movie: %s\n", err.msg);
        goto done;
    }
    char names[1200];
    printf("%s: %d frames of %dx%d at %d fps (%s), %s\n", out, m.frames, w, h, m.fps, m.codec,
           lc_cli_scene_name(&cs, names, sizeof names));
    status = 0;
done:
    lc_video_abort(v);
    free(rgba);
    lc_frame_state_destroy(state);
    lc_cli_scene_close(&cs, &g);
    return status;
}
