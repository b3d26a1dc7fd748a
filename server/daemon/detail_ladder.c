/* The interactive detail ladder (detail_ladder.h). */
#include "detail_ladder.h"

#include <math.h>

/* One rung down roughly halves the geometry a frame draws. Lines coarsen
 * their level of detail first; the line stride (whole lines, the important
 * ones kept) serves data the levels cannot thin, such as noise-like MD
 * trajectories, and the renderer keeps a segment per LC_LINE_SUBSET_PIXELS
 * pixels, so sparse lines keep every line. Lines that it thins lower the
 * resolution later (thinned_scale): a thinned frame at a larger size looks more
 * like the still than a small one stretched (docs/EVALUATION.md, "Interactive frames"); sparse
 * lines, which it does not thin, shrink as before. Point clouds take the
 * thinned scales too, and a steeper stride at the coarse end: on llvmpipe a
 * splat costs about the same at any size of frame (it shades a block of
 * pixels however small it is), so only fewer splats make a frame cheaper,
 * and the renderer keeps a point per LC_POINT_SUBSET_PIXELS pixels
 * (docs/EVALUATION.md, "The geometry path"). */
static const lc_detail_rung rungs[LC_DETAIL_RUNGS] = {
    {0.5, 1, 1, 1.0, 1.0}, {1, 2, 2, 1.0, 1.0}, {2, 4, 4, 0.85, 1.0}, {4, 16, 8, 0.7, 0.85}, {8, 64, 16, 0.5, 0.7}};

static int clamp_rung(int i) { return i < 0 ? 0 : i >= LC_DETAIL_RUNGS ? LC_DETAIL_RUNGS - 1 : i; }

const lc_detail_rung *lc_detail_rung_at(int i) { return &rungs[clamp_rung(i)]; }

int lc_detail_rung_next(int step, double wall_ms, double budget_ms)
{
    int next = step;
    if (budget_ms > 0 && wall_ms > budget_ms) { /* an overrun by a hair is still one rung */
        int k = (int)ceil(log2(wall_ms / budget_ms) - 1e-9);
        next = step + (k > 1 ? k : 1);
    } else if (budget_ms > 0 && wall_ms < 0.45 * budget_ms) { /* the gap keeps the controller from oscillating */
        next = step - 1;
    }
    return clamp_rung(next);
}
