/* The interactive detail ladder (protocol/websocket.md "Detail while
 * moving"): the rungs a session's moving frames step along, finest first,
 * and how the stream's controller moves between them from measured frame
 * times. Pure data and arithmetic; session.c applies a rung to a request. */
#ifndef LC_DETAIL_LADDER_H
#define LC_DETAIL_LADDER_H

typedef struct {
    double lod_pixels;    /* line error bound, pixels */
    int point_stride;     /* points: the most important 1/(4n) in full, every n-th of the rest */
    int line_stride;      /* lines: the same, by whole lines */
    double scale;         /* factor on the stream's interactiveScale */
    double thinned_scale; /* the same for point clouds, and lines thinned 4-fold or more */
} lc_detail_rung;

#define LC_DETAIL_RUNGS 5
#define LC_DETAIL_START 1 /* a session's first moving frame */

/* Rung i, 0 <= i < LC_DETAIL_RUNGS. */
const lc_detail_rung *lc_detail_rung_at(int i);

/* The rung after a moving frame at rung `step` that took wall_ms against
 * budget_ms: coarser by ceil(log2(wall_ms / budget_ms)) rungs when it
 * overran (a rung about halves the work), one finer when it took under 0.45
 * of the budget, else the same; clamped to the ladder. */
int lc_detail_rung_next(int step, double wall_ms, double budget_ms);

#endif
