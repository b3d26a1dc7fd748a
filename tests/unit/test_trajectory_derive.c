/* Derived trajectory attributes (scene_derive.c, docs/ALGORITHM.md "Derived
 * trajectory attributes"): a synthetic rising trajectory gives the exact
 * pressure change, 48-hour change, ascent angle, speed and turning angle; a
 * straight one turns by 0; the NetCDF sample gets them at load. */
#include <math.h>

#include "lc_test.h"
#include "nc_trajectories.h"
#include "scene.h"

#define DATA LUCENT_TEST_DATA "/loaders/"

static const float *attr(const lc_scene *s, const char *name)
{
    int i = lc_scene_find_attribute(s, name);
    CHECK(i >= 0, "attribute %s derived", name);
    return i >= 0 ? s->attributes[i].values : NULL;
}

/* 13 vertices 6 h apart, northward 0.1 degree per step at lon 0, pressure
 * p_k = 1000 - 50 k hPa (z = 10 ln(1013.25 / p)). */
static lc_scene *rising(double step_hours)
{
    lc_error err = {0};
    enum { N = 13 };
    lc_scene *s = lc_scene_create("rising", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, N, 0, &err) != 0)
        return NULL;
    for (int k = 0; k < N; k++) {
        s->positions[3 * k] = 0;
        s->positions[3 * k + 1] = (float)(0.1 * k);
        s->positions[3 * k + 2] = (float)(10 * log(1013.25 / (1000 - 50.0 * k)));
    }
    s->line_count = 1;
    s->line_offsets = malloc(2 * sizeof(uint32_t));
    s->line_offsets[0] = 0, s->line_offsets[1] = N;
    s->trajectory.geographic = 1;
    s->trajectory.step_hours = step_hours;
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    return s;
}

static void test_rising(void)
{
    lc_scene *s = rising(6);
    if (!s)
        return;
    const float *p = attr(s, "pressure"), *dp = attr(s, "pressure_change"), *dp48 = attr(s, "pressure_change_48h");
    const float *up = attr(s, "ascent_angle"), *speed = attr(s, "speed"), *turn = attr(s, "turning_angle");
    if (!p || !dp || !dp48 || !up || !speed || !turn)
        goto done;
    for (int k = 0; k < 13; k++) {
        CHECK_NEAR(p[k], 1000 - 50.0 * k, 2e-3, "pressure (hPa)");
        CHECK_NEAR(dp[k], -600, 2e-3, "pressure change over the line");
        /* 48 h = 8 steps ahead, or to the line's end */
        double want48 = -50.0 * ((k + 8 < 13 ? k + 8 : 12) - k);
        CHECK_NEAR(dp48[k], want48, 2e-3, "pressure change over 48 h");
        /* ascent: the outgoing segment (the last vertex: the incoming one) */
        int a = k < 12 ? k : 11;
        double up_km = 0.7 * ((double)s->positions[3 * (a + 1) + 2] - s->positions[3 * a + 2]);
        double north = 111.195 * ((double)s->positions[3 * (a + 1) + 1] - s->positions[3 * a + 1]);
        CHECK_NEAR(up[k], atan2(up_km, north) * 180 / M_PI, 1e-4, "ascent angle (degrees)");
        CHECK(up[k] > 0 && up[k] < 90, "a rising parcel ascends: %g", up[k]);
    }
    /* Explicit numbers at vertex 0: 1000 -> 950 hPa is 0.7 * 10 ln(1000/950) km up over 11.1195 km north. */
    CHECK_NEAR(up[0], atan2(7 * log(1000.0 / 950.0), 11.1195) * 180 / M_PI, 1e-4, "ascent angle at the start");
    CHECK_NEAR(speed[0], hypot(7 * log(1000.0 / 950.0), 11.1195) / 6, 1e-4, "speed at the start (km/h)");
    CHECK(turn[0] == 0 && turn[12] == 0, "no turning angle at the ends");
    CHECK(turn[6] > 0 && turn[6] < 5, "a slight bend where the ascent steepens: %g degrees", turn[6]);
done:
    lc_scene_destroy(s);
}

/* Without a time step: segment length instead of speed, no 48 h change. */
static void test_no_time(void)
{
    lc_scene *s = rising(0);
    if (!s)
        return;
    CHECK(lc_scene_find_attribute(s, "segment_length") >= 0 && lc_scene_find_attribute(s, "speed") < 0 &&
              lc_scene_find_attribute(s, "pressure_change_48h") < 0,
          "no time step: segment_length, no speed or 48 h change");
    lc_scene_destroy(s);
}

/* A straight, evenly climbing line turns by 0 everywhere. */
static void test_straight(void)
{
    lc_error err = {0};
    lc_scene *s = lc_scene_create("straight", LC_PRIM_LINES);
    if (!s || lc_scene_alloc_vertices(s, 5, 0, &err) != 0)
        return;
    for (int k = 0; k < 5; k++) {
        s->positions[3 * k] = 0;
        s->positions[3 * k + 1] = (float)(0.5 * k);
        s->positions[3 * k + 2] = (float)(0.25 * k);
    }
    s->line_count = 1;
    s->line_offsets = malloc(2 * sizeof(uint32_t));
    s->line_offsets[0] = 0, s->line_offsets[1] = 5;
    s->trajectory.geographic = 1;
    s->trajectory.step_hours = 1;
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    const float *turn = attr(s, "turning_angle");
    for (int k = 0; turn && k < 5; k++)
        CHECK_NEAR(turn[k], 0, 1e-3, "straight line: turning angle");
    lc_scene_destroy(s);
}

/* The NetCDF sample: lon/lat without units (degrees), time in hours. */
static void test_netcdf(void)
{
    lc_scene *s = NULL;
    lc_error err = {0};
    CHECK(lc_load_netcdf(DATA "nc/valid/trajectories.nc", &s, &err) == 0, "%s", err.msg);
    if (!s)
        return;
    CHECK(s->trajectory.geographic && s->trajectory.step_hours == 1, "trajectory info: %d, %g h",
          s->trajectory.geographic, s->trajectory.step_hours);
    CHECK(lc_scene_finalize(s, NULL, &err) == 0, "finalize: %s", err.msg);
    const float *dp = attr(s, "pressure_change");
    if (dp) {
        CHECK_NEAR(dp[0], -300, 2e-3, "first trajectory: 1000 -> 700 hPa");
        CHECK_NEAR(dp[4], -100, 2e-3, "second trajectory: 500 -> 400 hPa (cut at the missing value)");
    }
    lc_scene_destroy(s);
}

int main(void)
{
    test_rising();
    test_no_time();
    test_straight();
    test_netcdf();
    return lc_test_finish();
}
