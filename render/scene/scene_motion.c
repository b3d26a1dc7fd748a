/* Derived motion attributes of timed lines: speed, turning and ascent angles,
 * per-segment change and rate of file attributes (scene_motion.h). O(n). */
#include "scene_motion.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Names this module or scene_derive.c writes: never the source of a rate
 * (a second finalize would otherwise derive the change of a change). A
 * reader's own speed is left out too, so that the sources do not depend on
 * whether speed came from the file or from here. */
static int is_derived_name(const char *name)
{
    static const char *const own[] = {"arc_length",    "curvature",    "line_length",
                                      "turning_angle", "ascent_angle", "speed"};
    for (size_t i = 0; i < sizeof own / sizeof own[0]; i++)
        if (strcmp(name, own[i]) == 0)
            return 1;
    size_t n = strlen(name);
    return (n > 6 && strcmp(name + n - 6, "_delta") == 0) || (n > 5 && strcmp(name + n - 5, "_rate") == 0);
}

static void seg(const float *p, uint32_t i, uint32_t j, double d[3])
{
    for (int a = 0; a < 3; a++)
        d[a] = (double)p[3 * (size_t)j + a] - p[3 * (size_t)i + a];
}

static double len3(const double d[3]) { return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]); }

/* One line [a, b) with times t: speed, turning angle, ascent angle. */
static void derive_line(const float *p, const float *t, uint32_t a, uint32_t b, float *speed, float *turn,
                        float *ascent)
{
    for (uint32_t i = a; i < b; i++) {
        int has_in = i > a, has_out = i + 1 < b;
        double in[3] = {0, 0, 0}, on[3] = {0, 0, 0};
        if (has_in)
            seg(p, i - 1, i, in);
        if (has_out)
            seg(p, i, i + 1, on);
        if (speed) { /* the mean of the meeting segments' |Δp| / |Δt|, over those with Δt != 0 */
            double sum = 0;
            int k = 0;
            double dt_in = has_in ? fabs((double)t[i] - t[i - 1]) : 0,
                   dt_on = has_out ? fabs((double)t[i + 1] - t[i]) : 0;
            if (dt_in > 0)
                sum += len3(in) / dt_in, k++;
            if (dt_on > 0)
                sum += len3(on) / dt_on, k++;
            speed[i] = k ? (float)(sum / k) : 0.0f;
        }
        double li = len3(in), lo = len3(on);
        if (has_in && has_out && li > 0 && lo > 0) {
            double c[3] = {in[1] * on[2] - in[2] * on[1], in[2] * on[0] - in[0] * on[2], in[0] * on[1] - in[1] * on[0]};
            double dot = in[0] * on[0] + in[1] * on[1] + in[2] * on[2];
            turn[i] = (float)(atan2(len3(c), dot) * 180.0 / M_PI);
        } else {
            turn[i] = 0.0f;
        }
        const double *d = has_out ? on : in;
        ascent[i] = (float)(atan2(d[2], sqrt(d[0] * d[0] + d[1] * d[1])) * 180.0 / M_PI);
    }
}

/* One line [a, b): the per-segment change of v and its rate. */
static void derive_rate(const float *v, const float *t, uint32_t a, uint32_t b, float *delta, float *rate)
{
    for (uint32_t i = a; i < b; i++) {
        uint32_t from = i + 1 < b ? i : i - 1; /* the outgoing segment; the last vertex: the incoming */
        if (b - a < 2) {
            delta[i] = rate[i] = 0.0f;
            continue;
        }
        double dv = (double)v[from + 1] - v[from], dt = (double)t[from + 1] - t[from];
        delta[i] = (float)dv;
        rate[i] = isfinite(dt) && dt != 0 ? (float)(dv / dt) : 0.0f;
    }
}

static int add(lc_scene *s, const char *name, float *values, lc_error *err)
{
    if (s->attribute_count >= LC_MAX_ATTRIBUTES && lc_scene_find_attribute(s, name) < 0) {
        LC_WARN("scene", "%s: no room for the derived attribute %s", s->name, name);
        free(values);
        return 0;
    }
    int rc = lc_scene_add_attribute(s, name, values, err);
    return rc < 0 ? rc : 0;
}

int lc_scene_derive_motion(lc_scene *s, int *applied, lc_error *err)
{
    *applied = 0;
    int ti = s->type == LC_PRIM_LINES && !s->trajectory.geographic ? lc_scene_time_attribute(s, "") : -1;
    if (ti < 0)
        return 0;
    *applied = 1;
    uint32_t n = s->vertex_count;
    size_t bytes = (n ? n : 1) * sizeof(float);
    /* sources of rates: chosen before anything is added (attribute pointers move) */
    int src[LC_MOTION_MAX_RATES], nsrc = 0;
    for (int i = 0; !s->trajectory.no_rates && i < s->attribute_count && nsrc < LC_MOTION_MAX_RATES; i++) {
        const lc_attribute *at = &s->attributes[i];
        if (i == ti || at->categorical || is_derived_name(at->name) || strlen(at->name) + 7 > LC_NAME_LEN)
            continue;
        src[nsrc++] = i;
    }
    int own_speed = lc_scene_find_attribute(s, "speed") < 0;
    float *speed = own_speed ? malloc(bytes) : NULL, *turn = malloc(bytes), *ascent = malloc(bytes);
    float *delta[LC_MOTION_MAX_RATES] = {0}, *rate[LC_MOTION_MAX_RATES] = {0};
    int ok = (!own_speed || speed) && turn && ascent;
    for (int k = 0; k < nsrc; k++) {
        delta[k] = malloc(bytes), rate[k] = malloc(bytes);
        ok = ok && delta[k] && rate[k];
    }
    if (!ok) {
        free(speed), free(turn), free(ascent);
        for (int k = 0; k < nsrc; k++)
            free(delta[k]), free(rate[k]);
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate motion attributes", s->name);
    }
    const float *t = s->attributes[ti].values;
    for (uint32_t l = 0; l < s->line_count; l++) {
        uint32_t a = s->line_offsets[l], b = s->line_offsets[l + 1];
        if (b <= a)
            continue;
        derive_line(s->positions, t, a, b, speed, turn, ascent);
        for (int k = 0; k < nsrc; k++)
            derive_rate(s->attributes[src[k]].values, t, a, b, delta[k], rate[k]);
    }
    char names[2 * LC_MOTION_MAX_RATES][LC_NAME_LEN];
    for (int k = 0; k < nsrc; k++) {
        snprintf(names[2 * k], LC_NAME_LEN, "%s_delta", s->attributes[src[k]].name);
        snprintf(names[2 * k + 1], LC_NAME_LEN, "%s_rate", s->attributes[src[k]].name);
    }
    int rc = speed ? add(s, "speed", speed, err) : 0;
    rc = rc ? (free(turn), rc) : add(s, "turning_angle", turn, err);
    rc = rc ? (free(ascent), rc) : add(s, "ascent_angle", ascent, err);
    for (int k = 0; k < nsrc; k++) {
        rc = rc ? (free(delta[k]), rc) : add(s, names[2 * k], delta[k], err);
        rc = rc ? (free(rate[k]), rc) : add(s, names[2 * k + 1], rate[k], err);
    }
    return rc;
}
