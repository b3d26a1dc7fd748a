/* Track tables: a .csv/.tsv/.xyz point table whose columns name a track
 * (track, track_id, trajectory, trajectory_id, particle, particle_id, line,
 * line_id) and a time (time, t, frame, timestep) holds trajectories: its rows
 * become polylines, one per track value, vertices in time order. */
#ifndef LC_IO_CSV_TRACKS_H
#define LC_IO_CSV_TRACKS_H

#include "lc_base.h"
#include "scene.h"

/* The attribute index of s's track column, or -1 when s is no track table
 * (no track column, or no time attribute). */
int lc_csv_track_column(const lc_scene *s);

/* Turns the point scene *s (a reader's, not finalized) into a line scene:
 * rows grouped by track value (tracks in increasing value, rows of a track in
 * increasing time, ties in file order); tracks of one row are dropped with a
 * warning. On error *s is destroyed and NULL; err names the file. */
int lc_csv_group_tracks(lc_scene **s, int track, lc_error *err);

#endif
