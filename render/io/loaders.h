/* Dataset files: the reader chosen by extension, and every format's own API
 * (ply.h, obj.h, vtk.h, trk.h) for callers that name a format.
 * Threading: reentrant; a loaded scene belongs to the caller. */
#ifndef LC_LOADERS_H
#define LC_LOADERS_H

#include "lc_base.h"
#include "obj.h"
#include "ply.h"
#include "scene.h"
#include "trk.h"
#include "vtk.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Picks the reader by extension (.ply, .obj, .vtk, .trk); the scene is named
 * after the file stem. Finalizes the scene with default element options. On
 * error *out is NULL and err names the file and the reason. */
int lc_scene_load_file(const char *path, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
