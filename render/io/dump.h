/* LAMMPS dump trajectories (.dump, .lammpstrj, text "atom" or "custom" style):
 * frames of "ITEM:" blocks (TIMESTEP, NUMBER OF ATOMS, BOX BOUNDS, ATOMS with
 * the column names; UNITS and TIME are skipped). Every atom id becomes a
 * polyline through its positions, frame after frame, the lines ordered by id;
 * an atom that is missing from a frame ends its line (and starts a new one
 * when it comes back). Positions: unwrapped (xu yu zu, or scaled xsu ysu zsu)
 * as they are; wrapped (x y z, or scaled xs ys zs, orthogonal or triclinic
 * box) unwrapped with the image flags ix iy iz, or without flags by the
 * minimum image between consecutive frames along the periodic axes. Every
 * other numeric per-atom column (type, q, vx, ...) is an attribute, plus
 * `speed` (distance moved since the previous frame; a line's first point takes
 * its second's) and `displacement` (distance from the line's first point).
 * The default importance is speed. Lines of fewer than two points are
 * dropped with a warning. */
#ifndef LC_IO_DUMP_H
#define LC_IO_DUMP_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers return an un-finalized scene (the caller runs lc_scene_finalize and
 * owns the scene). On error *out is NULL and err names the file, the line and
 * the reason. `name` is used in messages and as the scene name. */
int lc_load_dump_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
int lc_load_dump(const char *path, lc_scene **out, lc_error *err);
/* Only the whole lines of process rank's share of size (lc_scene_read_file_part). */
int lc_load_dump_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
