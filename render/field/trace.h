/* Particle tracing for integral surfaces and streamline sets: particles
 * seeded along a seed polyline or at seed points (seeding.h), integrated
 * with RK4 through a field (stream lines of steady fields, path lines of
 * time-dependent ones) forward, backward or both ways, each with a ghost
 * particle beside it whose offset gives the surface normal
 * (docs/ALGORITHM.md §22).
 * Threading: lc_trace_curves runs on the caller's thread and threads - 1 more
 * (lc_parallel_for); it only reads the field and the seed. */
#ifndef LC_FIELD_TRACE_H
#define LC_FIELD_TRACE_H

#include <stdint.h>

#include "field.h"
#include "lc_base.h"
#include "lc_work.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_SEED_MAX_POINTS 256    /* vertices of a seed polyline */
#define LC_TRACE_MAX_STEPS 100000 /* RK4 steps of one curve */
#define LC_TRACE_STEP_UNITS 30.0  /* work units of one RK4 step with its ghost (lc_work.h; measured, cost_bench) */
#define LC_TRACE_CHARGE_STEPS 256 /* steps between two charges to a work budget */

/* A seed polyline: at least 2 points, consecutive points distinct. */
typedef struct lc_seed {
    int count;
    double points[LC_SEED_MAX_POINTS][3];
    double length;                         /* total arc length (set by lc_seed_check) */
    double cumulative[LC_SEED_MAX_POINTS]; /* arc length at each point */
} lc_seed;

/* Which way a particle is integrated from its seed (docs/ALGORITHM.md §22). */
typedef enum {
    LC_TRACE_FORWARD = 0, /* along v: the seed is the curve's first vertex */
    LC_TRACE_BACKWARD,    /* against v (a negative step): the seed is the last vertex */
    LC_TRACE_BOTH         /* the backward half reversed, the seed, then the forward half */
} lc_trace_direction;

/* How curves are traced; zero = defaults. */
typedef struct lc_trace_desc {
    /* RK4 time step; 0 = 1/200 of the field's diagonal over its largest |v|;
     * negative = |step| against the direction (forward <-> backward). */
    double step;
    lc_trace_direction direction;
    double max_length;  /* arc length at which a curve (each half of a two-way one) ends; 0 = 2 field diagonals */
    double max_time;    /* |integration time| at which a curve (half) ends; 0 = none (steady) or t1 - t0 */
    int max_steps;      /* 0 = LC_TRACE_MAX_STEPS */
    double ghost_delta; /* Δ of the ghost particle; 0 = 1e-5 times the field's diagonal */
    double t0;          /* seeding time of path surfaces; NaN/0 = the field's t0 */
    /* Work budget (NULL = none; borrowed for the call): every
     * LC_TRACE_CHARGE_STEPS steps of a curve charge step_units each (0 =
     * LC_TRACE_STEP_UNITS); once the budget is exceeded every thread stops and
     * the call fails with LC_ERR_BUDGET naming the budget's field. */
    lc_work_budget *work;
    double step_units;
} lc_trace_desc;

/* One traced curve: n vertices with position, normal (unit; cross(v, ghost
 * offset)), integration time, speed, and the seed parameter u in [0, 1]. */
typedef struct lc_trace_curve {
    uint32_t n;
    float *xyz;    /* 3n */
    float *normal; /* 3n */
    float *time;   /* n */
    float *speed;  /* n */
    double u;
    int ghost_resets; /* how often the ghost was pulled back to Δ */
} lc_trace_curve;

/* Validates seed (count, finite points, no zero-length segment) and fills
 * its arc lengths. field may be NULL; otherwise the first point must lie in
 * its domain. Errors name "seed.points" and the point. */
int lc_seed_check(lc_seed *seed, const lc_field *field, lc_error *err);

/* Parses "x,y,z;x,y,z[;...]" (command lines) into seed and checks it as
 * lc_seed_check does. Errors name "seed.points" and the point. */
int lc_seed_parse(const char *text, lc_seed *seed, const lc_field *field, lc_error *err);

/* Seed parameter of particle k in the progressive order: the base-2 radical
 * inverse of k+1 (0.5, 0.25, 0.75, 0.125, ...), so that any prefix of the
 * particles samples the seed curve evenly and later ones fill the gaps. */
double lc_seed_param(uint64_t k);
/* The point and unit tangent at arc-length fraction u of the seed. */
void lc_seed_at(const lc_seed *seed, double u, double p[3], double tangent[3]);

/* Fills the defaults of desc for field (a copy in *out). */
void lc_trace_resolve(const lc_field *field, const lc_trace_desc *desc, lc_trace_desc *out);

/* Traces particles first .. first + count - 1 (lc_seed_param order) into
 * curves[0 .. count-1] on threads threads (0 or 1 = the caller only). Curves
 * own malloc'd arrays: free them with lc_trace_curves_free. A particle seeded
 * outside the field gives a curve of 1 vertex. Errors: LC_ERR_NOMEM,
 * LC_ERR_BUDGET (desc->work exceeded; no curves are kept). */
int lc_trace_curves(const lc_field *field, const lc_seed *seed, const lc_trace_desc *desc, uint64_t first,
                    uint32_t count, int threads, lc_trace_curve *curves, lc_error *err);
/* Traces one curve from each of count seed points (3 doubles each) into
 * curves[0 .. count-1], as lc_trace_curves does; curve i has u = i/(count-1)
 * and its ghost starts across the flow. */
int lc_trace_points(const lc_field *field, const double *points, uint32_t count, const lc_trace_desc *desc, int threads,
                    lc_trace_curve *curves, lc_error *err);
void lc_trace_curves_free(lc_trace_curve *curves, uint32_t count);
/* Traces the one particle at seed parameter u in [0, 1] (the meshed
 * reference's particles, stream_mesh.c) into *curve (free with
 * lc_trace_curves_free(curve, 1)). */
int lc_trace_curve_at(const lc_field *field, const lc_seed *seed, const lc_trace_desc *desc, double u,
                      lc_trace_curve *curve, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
