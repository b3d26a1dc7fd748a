/* Track tables: point rows grouped into polylines by a track column, ordered
 * by time (csv_tracks.h). */
#include "csv_tracks.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_util.h"

int lc_csv_track_column(const lc_scene *s)
{
    static const char *const names[] = {"track",    "track_id",    "trajectory", "trajectory_id",
                                        "particle", "particle_id", "line",       "line_id"};
    if (lc_scene_time_attribute(s, "") < 0)
        return -1;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        int a = lc_scene_find_attribute(s, names[i]);
        if (a >= 0)
            return a;
    }
    return -1;
}

typedef struct row_key {
    float track, time;
    uint32_t row;
} row_key;

static int by_track_time(const void *pa, const void *pb)
{
    const row_key *a = pa, *b = pb;
    if (a->track != b->track)
        return a->track < b->track ? -1 : 1;
    if (a->time != b->time)
        return a->time < b->time ? -1 : 1;
    return a->row < b->row ? -1 : a->row > b->row;
}

/* Gathers src's values at order[0 .. n) into a new array; NULL when out of memory. */
static float *gather(const float *src, int width, const uint32_t *order, uint32_t n)
{
    float *dst = malloc((n ? (size_t)n : 1) * (size_t)width * sizeof *dst);
    for (uint32_t i = 0; dst && i < n; i++)
        memcpy(dst + (size_t)width * i, src + (size_t)width * order[i], (size_t)width * sizeof *dst);
    return dst;
}

int lc_csv_group_tracks(lc_scene **sp, int track, lc_error *err)
{
    lc_scene *s = *sp;
    uint32_t n = s->vertex_count;
    const float *id = s->attributes[track].values, *t = s->attributes[lc_scene_time_attribute(s, "")].values;
    row_key *keys = malloc((n ? (size_t)n : 1) * sizeof *keys);
    uint32_t *order = malloc((n ? (size_t)n : 1) * sizeof *order);
    uint32_t *offsets = malloc(((size_t)n + 1) * sizeof *offsets);
    int rc = 0;
    if (!keys || !order || !offsets) {
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory grouping tracks", s->name);
        goto done;
    }
    uint32_t bad = 0;
    for (uint32_t i = 0; i < n; i++) {
        keys[i] = (row_key){id[i], t[i], i};
        bad += !isfinite(id[i]) || !isfinite(t[i]);
    }
    if (bad) {
        rc = lc_err(err, LC_ERR_INVALID, "%s: %u rows without a finite %s or %s (a track table needs both)", s->name,
                    bad, s->attributes[track].name, s->attributes[lc_scene_time_attribute(s, "")].name);
        goto done;
    }
    qsort(keys, n, sizeof *keys, by_track_time);
    /* tracks of one row make no line: dropped */
    uint32_t v = 0, lines = 0, single = 0;
    for (uint32_t i = 0; i < n;) {
        uint32_t j = i;
        while (j < n && keys[j].track == keys[i].track)
            j++;
        if (j - i >= 2) {
            offsets[lines++] = v;
            for (uint32_t k = i; k < j; k++)
                order[v++] = keys[k].row;
        } else {
            single++;
        }
        i = j;
    }
    offsets[lines] = v;
    if (single)
        LC_WARN(LC_IO_LOG, "%s: %u tracks of a single row dropped", s->name, single);
    if (lines == 0) {
        rc = lc_err(err, LC_ERR_INVALID, "%s: no track has two rows", s->name);
        goto done;
    }
    lc_scene *out = lc_scene_create(s->name, LC_PRIM_LINES);
    float *pos = gather(s->positions, 3, order, v);
    float *rgb = s->rgb ? gather(s->rgb, 3, order, v) : NULL;
    if (!out || !pos || (s->rgb && !rgb)) {
        lc_scene_destroy(out);
        free(pos), free(rgb);
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory grouping tracks", s->name);
        goto done;
    }
    out->positions = pos, out->rgb = rgb, out->vertex_count = v;
    out->line_offsets = offsets, out->line_count = lines;
    offsets = NULL;
    for (int a = 0; a < s->attribute_count && !rc; a++) {
        float *values = gather(s->attributes[a].values, 1, order, v);
        rc = values ? lc_scene_add_attribute(out, s->attributes[a].name, values, err)
                    : lc_err(err, LC_ERR_NOMEM, "%s: out of memory grouping tracks", s->name);
        rc = rc < 0 ? rc : 0;
    }
    snprintf(out->default_importance, sizeof out->default_importance, "%s", s->default_importance);
    snprintf(out->default_color, sizeof out->default_color, "%s", s->default_color);
    if (rc) {
        lc_scene_destroy(out);
        goto done;
    }
    lc_scene_destroy(s);
    *sp = out;
done:
    free(keys), free(order), free(offsets);
    if (rc) {
        lc_scene_destroy(*sp);
        *sp = NULL;
    }
    return rc;
}
