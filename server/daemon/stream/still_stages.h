/* How a session's still is split into stages (protocol/websocket.md "Staged
 * stills"): the stride of the preview stage, which draws the view at full
 * size with the moving frames' opacities on a thinned subset, so that a
 * full-size image comes about a second after the last input even where the
 * full still takes several. Pure arithmetic on measured render times. */
#ifndef LC_STILL_STAGES_H
#define LC_STILL_STAGES_H

/* Where the first stage of a still should be ready, counted from the last
 * input: about a second, the time a user waits for a picture to settle. */
#define LC_STILL_PREVIEW_TARGET_MS 1000.0
/* A thinned frame at stride n keeps the most important 1/(4n) of the lines or
 * points in full and one in n of the rest (docs/ALGORITHM.md §11) in every
 * pass: about 1.25/n of the primitives, so about that share of a draw-bound
 * frame. */
#define LC_STILL_THINNED_SHARE(n) (1.25 / (double)(n))

/* The stride of a still's preview stage: the smallest power of two n >= 2
 * whose thinned share of full_ms (what the stage costs at full detail,
 * measured or an upper estimate) fits in budget_ms, capped at moving_stride
 * (the stride the moving frames drew at; 1 = they were not thinned, so
 * neither is the still). 1 = no preview: the stage fits at full detail, the
 * data is not thinned while moving, or full_ms is not known (<= 0). */
int lc_still_preview_stride(double full_ms, double budget_ms, int moving_stride);

#endif
