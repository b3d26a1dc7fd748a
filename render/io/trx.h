/* TRX tractograms (.trx): a zip archive (stored or deflated) or a directory
 * holding header.json (NB_VERTICES, NB_STREAMLINES), positions.3.{float16,
 * float32,float64} in RAS+ mm, offsets.{uint32,uint64,int32,int64} (the first
 * vertex of each streamline; a trailing NB_VERTICES is accepted), per-vertex
 * arrays dpv/NAME[.K].DTYPE and per-streamline arrays dps/NAME[.K].DTYPE
 * (little endian; K components become NAME_0..NAME_K-1; per-streamline values
 * are constant along their line). groups/ and dpg/ are ignored. Points with a
 * non-finite coordinate are dropped with a warning, streamlines of fewer than
 * two points too. */
#ifndef LC_IO_TRX_H
#define LC_IO_TRX_H

#include <stddef.h>

#include "lc_base.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A zip archive in memory. Returns an un-finalized scene (the caller runs
 * lc_scene_finalize and owns it); on error *out is NULL and err names the
 * file, the archive entry and the reason. */
int lc_load_trx_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err);
/* A .trx zip file or a .trx directory. */
int lc_load_trx(const char *path, lc_scene **out, lc_error *err);
/* Only the whole streamlines of process rank's share of size
 * (lc_scene_read_file_part). A deflated archive's arrays are still inflated
 * whole; stored archives and directories are read in place. */
int lc_load_trx_part(const char *path, int rank, int size, lc_scene **out, lc_error *err);

#ifdef __cplusplus
}
#endif
#endif
