/* Built-in demo datasets, deterministic from a seed: tornado and ABC-flow
 * streamlines (RK4), a clustered point cloud, a curvature-rich surface. */
#ifndef LC_DEMO_H
#define LC_DEMO_H

#include <stdint.h>

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lc_demo_desc {
    uint64_t seed;  /* 0 = default seed 1 */
    uint64_t count; /* 0 = default size: lines for streamlines, points for the cloud, grid resolution for the surface */
} lc_demo_desc;

/* NULL-terminated list of names: "tornado", "abc", "points", "surface". */
const char *const *lc_demo_names(void);
/* One-line description of a demo, or NULL if unknown. */
const char *lc_demo_description(const char *name);
/* Generates demo `name` (without the "demo:" prefix) and finalizes it. The
 * scene is named "demo:NAME". */
int lc_demo_create(const char *name, const lc_demo_desc *desc, lc_scene **out, lc_error *err);
/* The same from a spec "NAME[?count=N&seed=S]" (what follows "demo:" in a
 * dataset spec, e.g. "points?count=1000000"); desc's fields are the defaults
 * that the spec's override. */
int lc_demo_create_spec(const char *spec, const lc_demo_desc *defaults, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
