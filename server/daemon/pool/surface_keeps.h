/* The pool's kept surface layers (progressive insertion across a session's
 * frames, render/gl/surface_render.h lc_surface_keep): a few slots shared by
 * the render workers, whose GL contexts share objects, so that a surface
 * session's next frame continues its layers on whichever worker renders it
 * and draws only its new curves. A slot serves one frame at a time; one idle
 * for LC_SURFACE_KEEP_IDLE seconds gives its memory back.
 * Locking: its own lock. GL work (trim, destroy) runs on a thread with a
 * context of the workers' share group current. */
#ifndef LC_SERVER_SURFACE_KEEPS_H
#define LC_SERVER_SURFACE_KEEPS_H

#include <stdint.h>

#include "surface_render.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_SURFACE_KEEP_IDLE 10.0 /* seconds a slot keeps layers no frame continued */

typedef struct lc_surface_keeps lc_surface_keeps;

/* slots: at most one frame per worker uses one, so the worker count. */
lc_surface_keeps *lc_surface_keeps_create(int slots);
/* The slot for a frame of the curves named curves_id (lc_surface_draw): the
 * one holding them, else an empty one, else the one unused the longest; NULL
 * when every slot is in use (the frame then draws all its curves). */
lc_surface_keep *lc_surface_keeps_take(lc_surface_keeps *ks, uint64_t curves_id);
/* The frame that took k ended at `now`. */
void lc_surface_keeps_give(lc_surface_keeps *ks, lc_surface_keep *k, double now);
/* When the next slot falls idle (0 = none holds layers). */
double lc_surface_keeps_due(lc_surface_keeps *ks);
/* Frees the layers of the slots idle since LC_SURFACE_KEEP_IDLE before now. */
void lc_surface_keeps_trim(lc_surface_keeps *ks, double now);
void lc_surface_keeps_destroy(lc_surface_keeps *ks);

#ifdef __cplusplus
}
#endif
#endif
