/* Movie camera paths (render/math/camera_path.c) against explicit geometry,
 * movie request parsing (protocol/movie.c) with its error fields, and a short
 * H.264 and VP9 file through render/image/video.c (when built with libavcodec). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "camera_path.h"
#include "lc_test.h"
#include "movie.h"
#include "video.h"

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double dist(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(dot(d, d));
}

static void test_turntable(void)
{
    /* Looking from +y down at the origin with z up, tilted: up (0, 0.3, 1) is
     * not orthogonal to the view and must come out orthogonalized. */
    lc_camera start = {.position = {0, -4, 1},
                       .focal_point = {0, 0, 0},
                       .view_up = {0, 0.3, 1},
                       .view_angle = 30,
                       .parallel_scale = 1};
    lc_camera c0, c90, c180;
    lc_camera_turn(&start, 0, &c0);
    lc_camera_turn(&start, 90, &c90);
    lc_camera_turn(&start, 180, &c180);
    double d[3] = {0, 4, -1}, up0 = dot(c0.view_up, d);
    CHECK(fabs(up0) < 1e-12, "the up vector is orthogonalized to the view (%g)", up0);
    CHECK_NEAR(dist(c0.position, start.position), 0, 1e-12, "0 degrees is the start");
    CHECK(dist(c90.view_up, c0.view_up) < 1e-12 && dist(c180.view_up, c0.view_up) < 1e-12,
          "the up vector never changes");
    double h0 = dot(c0.position, c0.view_up), h90 = dot(c90.position, c0.view_up);
    CHECK_NEAR(h0, h90, 1e-12, "the height along the up axis stays (no pole crossing)");
    CHECK_NEAR(dist(c90.position, c90.focal_point), sqrt(17.0), 1e-12, "the distance stays");
    /* Half a turn: the point mirrored through the up axis. */
    double mirror[3];
    for (int i = 0; i < 3; i++)
        mirror[i] = 2 * h0 * c0.view_up[i] - start.position[i];
    CHECK_NEAR(dist(c180.position, mirror), 0, 1e-12, "180 degrees is the opposite side");
    lc_camera t;
    lc_camera_tilt(&start, 30, &t);
    double a = acos(dot(t.position, start.position) / (dist(t.position, t.focal_point) * sqrt(17.0))) * 180 / M_PI;
    CHECK_NEAR(a, 30, 1e-9, "tilt turns the position by 30 degrees");
}

static void test_interpolate(void)
{
    lc_camera a = {
        .position = {0, 0, 8}, .focal_point = {0, 0, 0}, .view_up = {0, 1, 0}, .view_angle = 30, .parallel_scale = 1};
    lc_camera b = {
        .position = {2, 0, 0}, .focal_point = {0, 0, 0}, .view_up = {0, 1, 0}, .view_angle = 50, .parallel_scale = 4};
    lc_camera m, e0, e1;
    lc_camera_interpolate(&a, &b, 0.5, &m);
    lc_camera_interpolate(&a, &b, 0, &e0);
    lc_camera_interpolate(&a, &b, 1, &e1);
    CHECK(dist(e0.position, a.position) < 1e-9 && dist(e1.position, b.position) < 1e-9,
          "t = 0 and 1 are the keyframes");
    CHECK_NEAR(dist(m.position, m.focal_point), 4, 1e-9, "distance: geometric mean of 8 and 2");
    double dir[3] = {m.position[0] / 4, m.position[1] / 4, m.position[2] / 4};
    CHECK_NEAR(dir[0], sqrt(0.5), 1e-9, "slerp: halfway between +z and +x is at 45 degrees (x)");
    CHECK_NEAR(dir[2], sqrt(0.5), 1e-9, "slerp: halfway between +z and +x is at 45 degrees (z)");
    CHECK(fabs(m.view_up[1] - 1) < 1e-9, "the shared up vector is kept");
    CHECK_NEAR(m.view_angle, 40, 1e-9, "view angle linear");
    CHECK_NEAR(m.parallel_scale, 2, 1e-9, "parallel scale log-linear");
    lc_camera keys[3] = {a, b, a}, p;
    lc_camera_path(keys, 3, 2, 5, &p);
    CHECK(dist(p.position, b.position) < 1e-9, "frame 2 of 5 through 3 keyframes is the middle keyframe");
    lc_camera_path(keys, 3, 4, 5, &p);
    CHECK(dist(p.position, a.position) < 1e-9, "the last frame is the last keyframe");
}

static int parse(const char *json, lc_movie_spec *m, lc_proto_error *e)
{
    memset(e, 0, sizeof *e);
    return lc_proto_parse_movie(json, strlen(json), NULL, m, e);
}

static void test_parse(void)
{
    static lc_movie_spec m;
    lc_proto_error e;
    CHECK(parse("{}", &m, &e) == 0 && m.frames == 300 && m.fps == 30 && m.request.render.width == 960 &&
              m.request.render.height == 540 && strcmp(m.codec, "h264") == 0 && m.path == LC_MOVIE_TURNTABLE,
          "defaults: 10 s turntable, 30 fps, 960x540, h264");
    CHECK(
        parse("{\"duration\":2.5,\"fps\":24,\"codec\":\"vp9\",\"request\":{\"dataset\":\"demo:abc\",\"params\":{\"q\":"
              "80}}}",
              &m, &e) == 0 &&
            m.frames == 60 && strcmp(m.request.dataset, "demo:abc") == 0 && m.request.render.foo.q == 80,
        "duration x fps frames, the nested render request: %s", e.message);
    CHECK(parse("{\"keyframes\":[{\"position\":[0,0,5]},\"#position=1,0,5&focalPoint=0,0,0&viewUp=0,1,0&q=80\"],"
                "\"frames\":10}",
                &m, &e) == 0 &&
              m.path == LC_MOVIE_KEYFRAMES && m.keyframe_count == 2 && m.keyframes[1].position[0] == 1 &&
              m.keyframes[0].view_angle == 30,
          "keyframes as a camera object and a page link: %s", e.message);
    static const struct {
        const char *json, *field;
    } bad[] = {{"{\"frames\":0}", "frames"},
               {"{\"duration\":0}", "duration"},
               {"{\"duration\":0.001}", "duration"},
               {"{\"width\":16384,\"height\":8640}", "width"},
               {"{\"width\":4096,\"height\":4096,\"fps\":1}", "width"}, /* over a movie frame's 4K cap */
               {"{\"width\":3840,\"height\":2160,\"fps\":1}", ""},
               {"{\"width\":3840,\"height\":2160,\"frames\":1801}", "frames"},
               {"{\"height\":541}", "height"},
               {"{\"codec\":\"av1\"}", "codec"},
               {"{\"keyframes\":[{\"position\":[0,0,5]}]}", "keyframes"},
               {"{\"keyframes\":[{\"position\":[0,0,5]},{\"position\":[0,0,0]}]}", "keyframes[1].camera.focalPoint"},
               {"{\"keyframes\":[{\"position\":[0,0,5]},\"#bandz=3\"]}", "keyframes[1].bandz"},
               {"{\"keyframes\":[{\"position\":[0,0,5]},\"#q=3\"]}", "keyframes[1]"},
               {"{\"path\":\"spiral\"}", "path"},
               {"{\"path\":\"turntable\",\"keyframes\":[]}", "keyframes"},
               {"{\"request\":{\"width\":100}}", "request.width"},
               {"{\"request\":{\"params\":{\"bands\":9}}}", "request.params.bands"},
               {"{\"frames\":10,\"duration\":1}", "frames"},
               {"{\"loop\":true}", "loop"},
               {"[1]", ""}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        int rc = parse(bad[i].json, &m, &e);
        bool ok = rc != 0 && strcmp(e.field, bad[i].field) == 0 &&
                  (!bad[i].field[0] || strncmp(e.message, bad[i].field, strlen(bad[i].field)) == 0);
        if (strcmp(bad[i].json, "{\"width\":3840,\"height\":2160,\"fps\":1}") == 0)
            ok = rc == 0; /* 4K, 10 frames: within both caps */
        CHECK(ok, "%s -> rc %d field \"%s\": %s", bad[i].json, rc, e.field, e.message);
    }
}

static void test_video(void)
{
    for (int codec = 0; codec < 2; codec++) {
        if (!lc_video_available(codec)) {
            printf("note: no %s encoder in this build\n", lc_video_codec_name(codec));
            continue;
        }
        char path[64];
        snprintf(path, sizeof path, "/tmp/lucent-test-video-%d.%s", (int)getpid(), lc_video_extension(codec));
        lc_video *v = NULL;
        lc_error err = {0};
        int rc = lc_video_open(path, codec, 64, 48, 10, &v, &err);
        CHECK(rc == 0, "open %s: %s", path, err.msg);
        static unsigned char rgba[64 * 48 * 4];
        for (int f = 0; rc == 0 && f < 5; f++) {
            for (int i = 0; i < 64 * 48; i++)
                rgba[4 * i] = (unsigned char)(i * 3 + f * 40), rgba[4 * i + 1] = 128, rgba[4 * i + 2] = 20,
                         rgba[4 * i + 3] = 255;
            rc = lc_video_write(v, rgba, &err);
        }
        CHECK(rc == 0, "write 5 frames: %s", err.msg);
        if (v)
            rc = lc_video_close(v, &err);
        CHECK(rc == 0, "close: %s", err.msg);
        FILE *f = fopen(path, "rb");
        long size = 0;
        if (f) {
            fseek(f, 0, SEEK_END);
            size = ftell(f);
            fclose(f);
        }
        CHECK(size > 100, "%s has %ld bytes", path, size);
        unlink(path);
        lc_video *odd = NULL;
        CHECK(lc_video_open(path, codec, 65, 48, 10, &odd, &err) != 0 && strcmp(err.field, "width") == 0 &&
                  access(path, F_OK) != 0,
              "odd width refused before a file exists: %s", err.msg);
    }
}

int main(void)
{
    test_turntable();
    test_interpolate();
    test_parse();
    test_video();
    return lc_test_finish();
}
