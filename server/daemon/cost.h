/* Render cost control: an estimate of what a request costs before it is
 * queued, in "fragment units" (about one fragment written by one pass), so
 * that one cheap-looking request (a 256-pixel point splat over 200,000 points)
 * cannot hold the renderer for minutes.
 *
 * The estimate (all in output pixels):
 *   area per primitive  points: pi * max(pointSize/2, 0.75)^2; lines: ribbon
 *                       length x max(minLinePixels, lineWidth x px per unit);
 *                       triangles: area x (px per unit)^2; each capped at W*H
 *   px per world unit   from the camera's distance to the data centre and its
 *                       view angle (parallel: parallelScale); without a
 *                       camera, the fitted view (about H / bounds diagonal)
 *   passes              by method, bands m (ceil((2m+1)/4) targets in P1/P4),
 *                       resolutionScale s (P1/P2 at s^2), subset, depthRange
 *   plus W*H per target for clears and resolve, elements x smoothing for P3
 *   and (vertices + 100 x primitives) per traversal of the geometry for vertex
 *   and primitive set-up: one per pass and resolution it runs at whatever
 *   targets it writes, P2 once per clarity try, none for P1 and P2 where they
 *   run over recorded fragments (software rasterizers, no stride); a stride n
 *   sets up 1/n of a strided pass, 3/n for lines (drawn segment by segment).
 * Measured against it on llvmpipe: 2e7..5e7 units per second (a 4096^2
 * tornado, 3.9e8 units: 19 s; the 64^2 points with 256-pixel splats of the
 * issue, 4.1e9 units: 80-90 s).
 * The default budget (1e9) is therefore 20-50 s on the 2-core llvmpipe
 * development machine and well under a second on a GPU.
 *
 * A frame is priced at the level of detail it will draw (params.lod at the
 * data's nearest depth; the levels are measured at upload).
 *
 * Threading: pure functions; a dataset's lc_scene_measures (render/scene
 * scene_measure.h) are taken once, at load. */
#ifndef LC_SERVER_COST_H
#define LC_SERVER_COST_H

#include <stdbool.h>
#include <stdint.h>

#include "lc_params.h"
#include "lc_work.h"
#include "scene_measure.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_COST_DEFAULT_BUDGET 1e9

/* Calibration factors (tests/bench/cost_bench.py; docs/ALGORITHM.md "Work
 * budgets"): what a feature's work costs on llvmpipe against the plain
 * frames' rate, where the terms below under-priced it by more than 2x. A halo
 * fragment is a widened ribbon's, blended with a depth test against the line
 * (8-12x); the shadow map's pass and blur (6x) and equalization's extra geometry
 * pass and histogram read-back (6x) stall on their read-backs; antialias
 * samples each resolve and blend again (2.5x). Tiled stills were priced as
 * one tile (6x under) until the estimate counted the pool's tiles (cost.c frame_tiles). */
#define LC_COST_HALO_FACTOR 12.0
#define LC_COST_SHADOW_FACTOR 6.0
#define LC_COST_EQUALIZE_FACTOR 6.0
#define LC_COST_ANTIALIAS_FACTOR 2.5
/* Building a line-cluster tree (lines.clusters with a new linkage or lift):
 * about 4e4 units a line on llvmpipe's host (0.42 s for 500 tornado lines,
 * 1.4 s for 2000). Charged on every clustered frame: the estimate cannot know
 * whether the tree is cached. */
#define LC_COST_CLUSTER_BUILD_UNITS_PER_LINE 4e4
/* Surface-layers' screen passes (clears, merge, composite over K layers, the
 * read-back) per pixel and layer: 8x the one unit first assumed (about 0.45 s
 * fixed at 512^2, K = 8). */
#define LC_COST_SURFACE_SCREEN_UNITS 8.0

/* The estimate for one frame of p on a dataset with stats st. */
double lc_cost_estimate(const lc_scene_measures *st, const lc_render_params *p);

/* When cost > budget: the request field that lowering helps most (a style
 * size, the method or a parameter when the defaults would fit, else "width"),
 * for the 4xx that names it. */
const char *lc_cost_field(const lc_scene_measures *st, const lc_render_params *p, double budget);
/* The smallest params.subset (a power of two up to 64) at which a frame of p
 * fits budget, for the methods that weight a stride; 0 when none does. */
int lc_cost_subset_for(const lc_scene_measures *st, const lc_render_params *p, double budget);

/* The check of a request against a budget (<= 0: none): 0 with *cost set, or
 * -1 with *field (lc_cost_field) and a message for the client in msg. */
int lc_cost_check(const lc_scene_measures *st, const lc_render_params *p, double budget, double *cost,
                  const char **field, char *msg, size_t n);

/* layers[] (docs/ALGORITHM.md "Layers"): the sum of each layer's frame on its
 * dataset (st[i]) with the layer's style; the screen passes are counted per
 * layer, which overestimates a frame of n layers by n - 1 of them. Over the
 * budget, *field is "layers". */
int lc_cost_check_layers(const lc_scene_measures *const *st, const lc_layer_params *const *layers, int n,
                         const lc_render_params *p, double budget, double *cost, const char **field, char *msg,
                         size_t size);

/* Method surface-layers (render/gl/surface_render.h): particles curves of
 * about `steps` RK4 steps each (lc_cost_surface_steps), each step traced (30
 * units, LC_TRACE_STEP_UNITS: RK4 with its ghost particle) and drawn as a
 * segment of about H / 400 pixels under the fitted camera, every fragment
 * written and merged (20 units a pixel); plus 8 W*H*(K + 3) for the clears,
 * the merge and composite passes over the K layers and the read-back.
 * Calibrated by tests/bench/cost_bench.py (at 512^2, 400 and 1600 curves of
 * the ABC flow: 0.09 and 0.41 s of tracing, 0.58 and 0.81 s of drawing);
 * over the budget, *field is "surface.particles". */
double lc_cost_surface(const lc_render_params *p, int particles, double steps, int k);
/* Steps of one curve: length (0 = 2 diagonals) over step (0 = diagonal / (200
 * max |v|)) times the largest speed, in 1 .. 1e5. */
double lc_cost_surface_steps(double diagonal, double max_speed, double step, double length);
/* A streamline set a request traces (docs/ALGORITHM.md §22): about
 * `vertices` RK4 steps (lc_streamlines_estimate, within 4% of the vertices
 * traced on demo:abc-flow), 100 units each: measured 4.2 µs a vertex with
 * its ghost, curl and scene set-up on the loaded 2-core llvmpipe machine
 * (density seeding, which is sequential), against the renderer's 2e7..5e7
 * units a second, i.e. 80..210 units a vertex. Paid once per set: a session
 * re-traces only when its seeding changes. Over --max-cost (the default 1e9:
 * 1e7 vertices) the set is refused naming "streamlines.count". */
double lc_cost_trace(double vertices);
int lc_cost_check_surface(const lc_render_params *p, int particles, double steps, int k, double budget, double *cost,
                          const char **field, char *msg, size_t n);

/* Work budgets (render/base lc_work.h; docs/ALGORITHM.md "Work budgets"):
 * what a request admitted at estimate `cost` may spend while it runs.
 * Counted work (RK4 steps) may reach LC_COST_GRANT_FACTOR times the
 * estimate; measured time, converted by the pool's learned rate (units per
 * second), LC_COST_TIME_FACTOR times, since the rate itself moves with the
 * host's load; counted work at least LC_COST_GRANT_FLOOR units, so that a
 * cheap request's fixed costs never trip it. */
#define LC_COST_GRANT_FACTOR 4.0
#define LC_COST_TIME_FACTOR 16.0
#define LC_COST_GRANT_FLOOR 2.5e7
#define LC_COST_TIME_FLOOR_S 30.0
double lc_cost_grant(double cost);
/* A surface-layers frame's budget: RK4 steps counted at the model's price
 * (lc_cost_surface_step_units), limit lc_cost_grant(cost), naming
 * surface.particles. max_cost <= 0 (no --max-cost): b counts but never stops. */
void lc_cost_surface_budget(lc_work_budget *b, double cost, double max_cost);
/* The units of one traced RK4 step (with its ghost) and its drawn segment. */
double lc_cost_surface_step_units(const lc_render_params *p);
/* A frame's budget against measured time: limit LC_COST_TIME_FACTOR x cost
 * (at least LC_COST_TIME_FLOOR_S seconds' worth: a busy host's stall is no
 * reason to stop a frame), elapsed seconds charged at `rate` units
 * per second, naming field. rate <= 0 (nothing learned yet) or max_cost <= 0:
 * b counts nothing and never stops. */
void lc_cost_frame_budget(lc_work_budget *b, double cost, double rate, double max_cost, const char *field);

#ifdef __cplusplus
}
#endif
#endif
