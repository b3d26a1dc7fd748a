/* The analytic flows behind the demo fields, for callers that integrate them
 * directly (the streamline demos of render/scene) and for tests. Pure
 * functions of (p, t); any thread. */
#ifndef LC_FIELD_DEMO_H
#define LC_FIELD_DEMO_H

#ifdef __cplusplus
extern "C" {
#endif

/* u = 1 + LC_FIELD_SHEAR_RATE * y of the shear-flow demo. */
#define LC_FIELD_SHEAR_RATE 0.5

void lc_field_tornado(const double p[3], double t, double v[3]);
void lc_field_abc(const double p[3], double t, double v[3]);
void lc_field_shear(const double p[3], double t, double v[3]);
void lc_field_double_gyre(const double p[3], double t, double v[3]);

#ifdef __cplusplus
}
#endif
#endif
