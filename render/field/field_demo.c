/* Analytic demo fields: Crawfis' tornado, the ABC flow, a linear shear (for
 * tests with known stream surfaces) and the time-dependent double gyre. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "field.h"
#include "field_demo.h"

void lc_field_tornado(const double p[3], double t, double v[3])
{
    (void)t; /* the t = 0 frame of Crawfis' animation */
    double x = p[0], y = p[1], z = p[2];
    double xc = 0.5 + 0.1 * sin(10.0 * z);
    double yc = 0.5 + 0.1 * cos(3.0 * z);
    double r = 0.1 + 0.4 * z * z + 0.1 * z * sin(8.0 * z);
    double r2 = 0.2 + 0.1 * z;
    double temp = hypot(x - xc, y - yc);
    double scale = fabs(r - temp);
    scale = scale > r2 ? 0.8 - scale : 1.0;
    double z0 = 0.1 * (0.1 - temp * z);
    if (z0 < 0.0)
        z0 = 0.0;
    temp = sqrt(temp * temp + z0 * z0);
    scale = (r + r2 - temp) * scale / (temp + 1e-11);
    scale = scale / (1.0 + z);
    v[0] = scale * (y - yc) + 0.1 * (x - xc);
    v[1] = -scale * (x - xc) + 0.1 * (y - yc);
    v[2] = scale * z0;
}

void lc_field_abc(const double p[3], double t, double v[3])
{
    (void)t;
    const double A = sqrt(3.0), B = sqrt(2.0), C = 1.0;
    v[0] = A * sin(p[2]) + C * cos(p[1]);
    v[1] = B * sin(p[0]) + A * cos(p[2]);
    v[2] = C * sin(p[1]) + B * cos(p[0]);
}

/* Plane Couette flow: u grows linearly with y, so a seed line across y
 * sweeps a plane while its particles drift apart along x. */
void lc_field_shear(const double p[3], double t, double v[3])
{
    (void)t;
    v[0] = 1.0 + LC_FIELD_SHEAR_RATE * p[1];
    v[1] = 0.0;
    v[2] = 0.0;
}

/* Shadden et al.'s double gyre (A = 0.1, eps = 0.25, omega = 2 pi / 10),
 * extruded along z with no vertical flow. */
void lc_field_double_gyre(const double p[3], double t, double v[3])
{
    const double A = 0.1, eps = 0.25, omega = 2.0 * M_PI / 10.0;
    double a = eps * sin(omega * t), b = 1.0 - 2.0 * eps * sin(omega * t);
    double f = a * p[0] * p[0] + b * p[0], df = 2.0 * a * p[0] + b;
    v[0] = -M_PI * A * sin(M_PI * f) * cos(M_PI * p[1]);
    v[1] = M_PI * A * cos(M_PI * f) * sin(M_PI * p[1]) * df;
    v[2] = 0.0;
}

typedef struct demo_field {
    const char *name, *description;
    lc_field_fn fn;
    double bounds[6];
    int time_dependent;
    double t0, t1;
} demo_field;

static const demo_field demos[] = {
    {"tornado-flow",
     "Crawfis tornado (t = 0) on [0,1]^3: steady, stream surfaces",
     lc_field_tornado,
     {0, 0, 0, 1, 1, 1},
     0,
     0,
     0},
    {"abc-flow",
     "ABC flow (A=sqrt3, B=sqrt2, C=1) on [0,2pi]^3: steady, stream surfaces",
     lc_field_abc,
     {0, 0, 0, 2 * M_PI, 2 * M_PI, 2 * M_PI},
     0,
     0,
     0},
    {"shear-flow",
     "plane Couette shear u = 1 + y/2 on [-1,1]^3: steady, planar stream surfaces (tests)",
     lc_field_shear,
     {-1, -1, -1, 1, 1, 1},
     0,
     0,
     0},
    {"double-gyre-flow",
     "double gyre (A=0.1, eps=0.25, period 10) on [0,2]x[0,1]x[0,1]: time-dependent, path surfaces",
     lc_field_double_gyre,
     {0, 0, 0, 2, 1, 1},
     1,
     0,
     20},
};
#define NDEMOS (sizeof demos / sizeof *demos)

static const char *const demo_names[] = {"tornado-flow", "abc-flow", "shear-flow", "double-gyre-flow", NULL};

const char *const *lc_field_demo_names(void) { return demo_names; }

static const demo_field *find(const char *name)
{
    if (name && strncmp(name, "demo:", 5) == 0)
        name += 5;
    for (size_t i = 0; name && i < NDEMOS; i++)
        if (strcmp(demos[i].name, name) == 0)
            return &demos[i];
    return NULL;
}

const char *lc_field_demo_description(const char *name)
{
    const demo_field *d = find(name);
    return d ? d->description : NULL;
}

int lc_field_is_demo(const char *name) { return find(name) != NULL; }

int lc_field_demo_create(const char *name, lc_field **out, lc_error *err)
{
    *out = NULL;
    const demo_field *d = find(name);
    if (!d)
        return lc_err(err, LC_ERR_NOT_FOUND,
                      "demo:%.64s: unknown demo field (tornado-flow, abc-flow, shear-flow, double-gyre-flow)",
                      name ? name : "");
    char full[128];
    snprintf(full, sizeof full, "demo:%s", d->name);
    return lc_field_create_analytic(full, d->fn, d->bounds, d->time_dependent, d->t0, d->t1, out, err);
}
