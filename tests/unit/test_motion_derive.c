/* Derived motion attributes of timed line files (render/scene/scene_motion.c,
 * docs/ALGORITHM.md §16) on one tiny track in every format that carries a
 * time or frame per vertex (tests/data/loaders/motion/): VTK, CSV track
 * tables, OBJ with "# vt: time", LAMMPS dumps. The track runs
 * (0,0,0) -> (3,4,5) -> (3,4,15) -> (6,8,15) at t = 0, 2, 4, 5 with q = 1, 3,
 * 4, 10, so its speeds, turning and ascent angles and q's changes and rates
 * are known by hand. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "lc_test.h"
#include "loaders.h"
#include "scene.h"

#define DATA LUCENT_TEST_DATA "/loaders/motion/"

static const float *attr(const lc_scene *s, const char *name, const char *what)
{
    int i = lc_scene_find_attribute(s, name);
    CHECK(i >= 0, "%s: attribute %s derived", what, name);
    return i >= 0 ? s->attributes[i].values : NULL;
}

static void check4(const float *got, uint32_t first, const double want[4], double tol, const char *what,
                   const char *name)
{
    if (!got)
        return;
    for (int i = 0; i < 4; i++)
        CHECK(fabs(got[first + i] - want[i]) <= tol, "%s: %s[%d] = %g, want %g", what, name, i, got[first + i],
              want[i]);
}

/* The hand-computed values of the track (segments (3,4,5) over 2, (0,0,10)
 * over 2, (3,4,0) over 1). */
static const double SPEED[4] = {3.5355339, (3.5355339 + 5.0) / 2, 5.0, 5.0};
static const double TURN[4] = {0, 45, 90, 0};
static const double ASCENT[4] = {45, 90, 0, 0};
static const double Q_DELTA[4] = {2, 1, 6, 6};
static const double Q_RATE[4] = {1, 0.5, 6, 6};

static lc_scene *load(const char *file)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    char path[512];
    snprintf(path, sizeof path, DATA "%s", file);
    CHECK(lc_scene_load_file(path, &s, &err) == 0, "%s: %s", file, err.msg);
    if (s)
        CHECK(s->type == LC_PRIM_LINES && s->line_count >= 1 && s->line_offsets[1] == 4, "%s: a line of 4 vertices",
              file);
    return s && s->type == LC_PRIM_LINES && s->line_offsets[1] == 4 ? s : NULL;
}

static void test_format(const char *file, int has_q, int own_speed)
{
    lc_scene *s = load(file);
    if (!s)
        return;
    if (!own_speed)
        check4(attr(s, "speed", file), 0, SPEED, 1e-5, file, "speed");
    check4(attr(s, "turning_angle", file), 0, TURN, 1e-4, file, "turning_angle");
    check4(attr(s, "ascent_angle", file), 0, ASCENT, 1e-4, file, "ascent_angle");
    if (has_q) {
        check4(attr(s, "q_delta", file), 0, Q_DELTA, 1e-6, file, "q_delta");
        check4(attr(s, "q_rate", file), 0, Q_RATE, 1e-6, file, "q_rate");
    }
    int ti = lc_scene_time_attribute(s, "");
    CHECK(ti >= 0, "%s: a time attribute", file);
    if (ti >= 0) {
        char name[LC_NAME_LEN + 8];
        snprintf(name, sizeof name, "%s_rate", s->attributes[ti].name);
        CHECK(lc_scene_find_attribute(s, name) < 0, "%s: no rate of the time itself", file);
    }
    /* a second finalize (a new element budget) derives the same values, not rates of rates */
    int count = s->attribute_count;
    lc_error err = {0};
    CHECK(lc_scene_finalize(s, NULL, &err) == 0 && s->attribute_count == count, "%s: refinalize keeps %d attributes",
          file, count);
    CHECK(lc_scene_find_attribute(s, "q_delta_delta") < 0, "%s: no change of a change", file);
    if (!own_speed)
        check4(attr(s, "speed", file), 0, SPEED, 1e-5, file, "speed after refinalize");
    lc_scene_destroy(s);
}

static void test_csv_tracks(void)
{
    lc_scene *s = load("track.csv");
    if (!s)
        return;
    /* tracks by value (7, then 8), rows by time; the one-row track 9 dropped */
    CHECK(s->line_count == 2 && s->vertex_count == 6, "%u lines, %u vertices", s->line_count, s->vertex_count);
    const float *t = attr(s, "time", "csv"), *speed = attr(s, "speed", "csv");
    if (t && speed && s->vertex_count == 6) {
        CHECK(t[0] == 0 && t[1] == 2 && t[2] == 4 && t[3] == 5 && t[4] == 0 && t[5] == 1, "rows in time order");
        CHECK(fabs(speed[4] - 1) < 1e-6 && fabs(speed[5] - 1) < 1e-6, "track 8 moves 1 per unit time");
    }
    CHECK(strcmp(s->default_importance, "speed") == 0, "a track table's default importance is %s",
          s->default_importance);
    lc_scene_destroy(s);
}

/* Lines without a time attribute get nothing (the OBJ sample of the loader cases). */
static void test_untimed(void)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    CHECK(lc_scene_load_file(LUCENT_TEST_DATA "/loaders/valid/lines.obj", &s, &err) == 0, "lines.obj: %s", err.msg);
    if (s)
        CHECK(lc_scene_find_attribute(s, "turning_angle") < 0 && lc_scene_find_attribute(s, "vt_rate") < 0,
              "untimed lines get no motion attributes");
    lc_scene_destroy(s);
}

int main(void)
{
    test_format("track.vtk", 1, 0);
    test_format("track.csv", 1, 0);
    test_format("track.obj", 0, 0);
    /* a dump keeps its own speed (distance per frame); its time is the TIMESTEP */
    test_format("track.dump", 1, 1);
    lc_scene *d = load("track.dump");
    if (d) {
        const float *sp = attr(d, "speed", "dump");
        CHECK(sp && fabs(sp[1] - sqrt(50)) < 1e-4 && fabs(sp[2] - 10) < 1e-4 && fabs(sp[3] - 5) < 1e-4,
              "dump speed per frame: %g %g %g", sp ? sp[1] : 0, sp ? sp[2] : 0, sp ? sp[3] : 0);
        lc_scene_destroy(d);
    }
    test_csv_tracks();
    test_untimed();
    return lc_test_finish();
}
