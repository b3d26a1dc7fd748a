/* Vector fields: analytic demo flows and gridded fields (uniform or
 * rectilinear), sampled trilinearly, with their description (grid, bounds,
 * magnitude range). The seed of integral surfaces (docs/ALGORITHM.md §21).
 * Threading: a field is built on one thread and read-only afterwards;
 * lc_field_sample may be called from any number of threads at once. */
#ifndef LC_FIELD_H
#define LC_FIELD_H

#include <stdint.h>

#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { LC_FIELD_ANALYTIC = 0, LC_FIELD_UNIFORM, LC_FIELD_RECTILINEAR } lc_field_kind;

/* An analytic flow: the velocity at p and time t. */
typedef void (*lc_field_fn)(const double p[3], double t, double v[3]);

/* Largest grid a field may hold (nodes): 2^28 nodes are 3 GiB of float vectors. */
#define LC_FIELD_MAX_NODES (1ull << 28)

typedef struct lc_field {
    char name[128];        /* "demo:NAME" or the file stem */
    char vectors_name[64]; /* the VTK array's name; "" for analytic fields */
    lc_field_kind kind;
    double bounds[6];        /* min x, y, z, max x, y, z: the domain; outside it the flow is 0 */
    int time_dependent;      /* 1: the velocity depends on t (path surfaces) */
    double t0, t1;           /* the time span a tracer should cover (t1 > t0 for unsteady fields) */
    double mag_min, mag_max; /* |v| over the grid nodes (analytic: a 33^3 lattice at t0) */
    /* Analytic */
    lc_field_fn fn;
    /* Gridded: dims nodes per axis (each >= 2), x fastest. */
    uint32_t dims[3];
    double *coords[3]; /* node coordinates per axis, strictly increasing (uniform: origin + i * spacing) */
    float *vectors;    /* 3 * dims[0] * dims[1] * dims[2] */
} lc_field;

/* NULL-terminated names of the analytic fields, without the "demo:" prefix:
 * "tornado-flow", "abc-flow", "shear-flow", "double-gyre-flow". */
const char *const *lc_field_demo_names(void);
/* One-line description of a demo field, or NULL if unknown. */
const char *lc_field_demo_description(const char *name);
/* 1 when name (with or without "demo:") is a demo field. */
int lc_field_is_demo(const char *name);
/* The analytic field `name` (without "demo:"), named "demo:NAME". On error
 * *out is NULL and err names the field (LC_ERR_NOT_FOUND for an unknown name). */
int lc_field_demo_create(const char *name, lc_field **out, lc_error *err);

/* A field from a function over a box (tests, demos). Copies nothing but the
 * values; name may be NULL. */
int lc_field_create_analytic(const char *name, lc_field_fn fn, const double bounds[6], int time_dependent, double t0,
                             double t1, lc_field **out, lc_error *err);

/* A gridded field. coords[a] holds dims[a] strictly increasing finite values;
 * vectors holds 3 floats per node, x fastest. Takes ownership of coords[] and
 * vectors (malloc'd) also on error. kind is LC_FIELD_UNIFORM when the
 * coordinates are evenly spaced (set by the caller), else LC_FIELD_RECTILINEAR.
 * Non-finite vectors become 0 (a hole in the data stops the tracer there). */
int lc_field_create_grid(const char *name, lc_field_kind kind, const uint32_t dims[3], double *coords[3],
                         float *vectors, lc_field **out, lc_error *err);

/* The velocity at p and time t (t ignored by steady fields). Returns 1 inside
 * the domain, 0 outside (v set to 0). Gridded fields interpolate trilinearly
 * between the 8 nodes of the cell around p. */
int lc_field_sample(const lc_field *f, const double p[3], double t, double v[3]);

/* The curl of the velocity at p and time t (vorticity ω = ∇ × v) by central
 * differences: over h = 1/1000 of the domain's diagonal for analytic fields,
 * half the cell around p per axis for gridded ones; one-sided at the domain's
 * faces. Returns 1 inside the domain, 0 outside (w set to 0). */
int lc_field_curl(const lc_field *f, const double p[3], double t, double w[3]);

/* 1 when p lies within the field's bounds. */
int lc_field_contains(const lc_field *f, const double p[3]);

/* Number of grid nodes (0 for analytic fields). */
uint64_t lc_field_node_count(const lc_field *f);
/* "analytic", "uniform" or "rectilinear". */
const char *lc_field_kind_name(lc_field_kind kind);
/* Bytes the field holds (grid coordinates and vectors). */
uint64_t lc_field_bytes(const lc_field *f);

void lc_field_destroy(lc_field *f);

#ifdef __cplusplus
}
#endif
#endif
