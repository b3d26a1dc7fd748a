/* Point-table reader (CSV, TSV, XYZ): a header naming the columns, then one
 * point per row; two passes over the mapped file (count rows, then parse into
 * arrays of exactly that size). A process's share (lc_scene_read_file_part)
 * takes a pass more: the rows with finite coordinates are counted first, so
 * that the share is the contiguous range of them lc_scene_shard would give. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "csv.h"
#include "csv_tracks.h"
#include "io_util.h"
#include "scene_shard.h"

#define MAX_COLUMNS 1024

typedef struct csv_load {
    const char *p, *end; /* cursor in the file */
    const char *file;
    lc_error *err;
    size_t line;
    char sep; /* ',', '\t' or ' ' (runs of blanks) */
    int ncol;
    int pos_col[3];           /* columns of x, y, z; -1: z is 0 */
    int attr_of[MAX_COLUMNS]; /* attribute index of a column, or -1 */
    char names[MAX_COLUMNS][LC_NAME_LEN];
    const char *fs[MAX_COLUMNS], *fe[MAX_COLUMNS]; /* fields of the current line */
    lc_io_progress progress;
} csv_load;

static int fail(csv_load *C, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(csv_load *C, int code, const char *fmt, ...)
{
    char reason[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    return lc_err(C->err, code, "%.80s: line %zu: %s", C->file, C->line, reason);
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

/* Next line [*ls, *le) without its end of line; 0 at the end of the file. */
static int next_line(csv_load *C, const char **ls, const char **le)
{
    if (!lc_io_next_line(&C->p, C->end, 0, ls, le))
        return 0;
    C->line++;
    return 1;
}

/* A line that holds no data: empty, blanks only, or a '#' comment. */
static int skip_line(const char *ls, const char *le)
{
    while (ls < le && is_blank(*ls))
        ls++;
    return ls == le || *ls == '#';
}

/* Splits [ls, le) into at most max fields (trimmed, quotes stripped);
 * returns the field count or -1 when there are more than max. */
static int split(const csv_load *C, const char *ls, const char *le, const char **fs, const char **fe, int max)
{
    int n = 0;
    const char *p = ls;
    if (C->sep == ' ') {
        for (;;) {
            while (p < le && is_blank(*p))
                p++;
            if (p == le)
                return n;
            if (n == max)
                return -1;
            fs[n] = p;
            while (p < le && !is_blank(*p))
                p++;
            fe[n++] = p;
        }
    }
    for (;;) {
        if (n == max)
            return -1;
        const char *q = memchr(p, C->sep, (size_t)(le - p));
        const char *e = q ? q : le;
        const char *a = p, *b = e;
        while (a < b && is_blank(*a))
            a++;
        while (b > a && is_blank(b[-1]))
            b--;
        if (b - a >= 2 && *a == '"' && b[-1] == '"')
            a++, b--;
        fs[n] = a;
        fe[n++] = b;
        if (!q)
            return n;
        p = q + 1;
    }
}

/* A whole field as a number; empty is NaN. Returns 0 if it is not a number. */
static int field_number(const char *a, const char *b, double *out)
{
    if (a == b) {
        *out = NAN;
        return 1;
    }
    const char *e = lc_io_parse_double(a, b, out);
    return e == b;
}

static int name_is(const char *name, const char *const *options)
{
    for (; *options; options++)
        if (strcasecmp(name, *options) == 0)
            return 1;
    return 0;
}

/* Chooses the position columns from the names. */
static int pick_positions(csv_load *C)
{
    static const char *const xs[] = {"x", "points:0", "point:0", "px", NULL};
    static const char *const ys[] = {"y", "points:1", "point:1", "py", NULL};
    static const char *const zs[] = {"z", "points:2", "point:2", "pz", NULL};
    static const char *const lons[] = {"lon", "longitude", "lng", NULL};
    static const char *const lats[] = {"lat", "latitude", NULL};
    static const char *const heights[] = {"alt", "altitude", "height", "z", "elevation", NULL};
    const char *const *sets[2][3] = {{xs, ys, zs}, {lons, lats, heights}};
    for (int set = 0; set < 2; set++) {
        int col[3] = {-1, -1, -1};
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < C->ncol && col[k] < 0; c++)
                if (name_is(C->names[c], sets[set][k]))
                    col[k] = c;
        if (col[0] >= 0 && col[1] >= 0 && (col[2] >= 0 || set == 1)) {
            memcpy(C->pos_col, col, sizeof col);
            return 0;
        }
    }
    return fail(C, LC_ERR_INVALID, "no position columns (x, y, z or lon, lat) among the %d columns", C->ncol);
}

/* The position of the current row (fields fs/fe, m of them): 0, or an error
 * for a wrong field count or a position that is not a number. */
static int row_position(csv_load *C, int m, float p[3])
{
    if (m != C->ncol)
        return fail(C, LC_ERR_INVALID, "%d fields, the header has %d", m < 0 ? MAX_COLUMNS + 1 : m, C->ncol);
    p[0] = p[1] = p[2] = 0;
    for (int k = 0; k < 3; k++) {
        double x;
        int c = C->pos_col[k];
        if (c < 0)
            continue;
        if (!field_number(C->fs[c], C->fe[c], &x))
            return fail(C, LC_ERR_INVALID, "column '%s': '%.*s' is not a number", C->names[c],
                        (int)(C->fe[c] - C->fs[c] < 40 ? C->fe[c] - C->fs[c] : 40), C->fs[c]);
        p[k] = (float)x;
    }
    return 0;
}

static int load_csv(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    csv_load *C = calloc(1, sizeof *C); /* the name table is 64 KB: not on the stack */
    if (!C)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    const char **fs = C->fs, **fe = C->fe;
    C->p = data ? data : "";
    C->end = C->p + (data ? size : 0);
    C->file = name;
    C->err = err;
    lc_io_progress_start(&C->progress, name);
    lc_scene *s = NULL;
    int rc = 0;

    /* The first data line: header or first row. */
    const char *ls = NULL, *le = NULL;
    while (next_line(C, &ls, &le) && skip_line(ls, le))
        ;
    if (!ls || skip_line(ls, le)) {
        rc = fail(C, LC_ERR_INVALID, "no header and no rows");
        goto done;
    }
    if (memchr(ls, ',', (size_t)(le - ls)))
        C->sep = ',';
    else
        C->sep = memchr(ls, '\t', (size_t)(le - ls)) ? '\t' : ' ';
    int n = split(C, ls, le, fs, fe, MAX_COLUMNS);
    if (n < 0) {
        rc = fail(C, LC_ERR_LIMIT, "more than %d columns", MAX_COLUMNS);
        goto done;
    }
    C->ncol = n;
    int header = 0;
    for (int c = 0; c < n && !header; c++) {
        double v;
        header = !field_number(fs[c], fe[c], &v) || fs[c] == fe[c];
    }
    size_t header_line = header ? C->line : 0;
    for (int c = 0; c < n; c++) {
        if (header) {
            size_t len = (size_t)(fe[c] - fs[c]);
            snprintf(C->names[c], LC_NAME_LEN, "%.*s", (int)(len < LC_NAME_LEN ? len : LC_NAME_LEN - 1), fs[c]);
            for (char *q = C->names[c]; *q; q++) /* names travel in URLs and PLY headers */
                if (*q == ' ' || (unsigned char)*q < 32)
                    *q = '_';
        } else {
            static const char *const xyz[3] = {"x", "y", "z"};
            if (c < 3)
                snprintf(C->names[c], LC_NAME_LEN, "%s", xyz[c]);
            else
                snprintf(C->names[c], LC_NAME_LEN, "column_%d", c + 1);
        }
    }
    if (!header)
        C->p = ls, C->line--; /* the line is the first row */
    if ((rc = pick_positions(C)))
        goto done;

    /* Pass 1: count the rows; the first row decides which columns hold numbers. */
    const char *body = C->p;
    size_t body_line = C->line, rows = 0;
    int numeric[MAX_COLUMNS];
    int first = 1;
    while (next_line(C, &ls, &le)) {
        if (skip_line(ls, le))
            continue;
        if (++rows > LC_MAX_VERTICES) {
            rc = fail(C, LC_ERR_LIMIT, "more than %u rows", (unsigned)LC_MAX_VERTICES);
            goto done;
        }
        if ((rows & 0xFFFF) == 0)
            lc_io_progress_report(&C->progress, (size_t)(C->p - (const char *)data), 2 * size); /* two passes */
        if (first) {
            int m = split(C, ls, le, fs, fe, MAX_COLUMNS);
            for (int c = 0; c < C->ncol; c++) {
                double v;
                numeric[c] = c < m && field_number(fs[c], fe[c], &v);
            }
            first = 0;
        }
    }
    if (rows == 0) {
        rc = fail(C, LC_ERR_INVALID, "no rows after the header");
        goto done;
    }
    /* The rows this process keeps: with finite coordinates, their index among
     * those in [keep_first, keep_first + keep). The whole file keeps every one
     * and needs no count (the arrays keep room for the dropped rows). */
    uint64_t keep_first = 0, keep = rows;
    if (lc_io_part_active(part)) {
        uint64_t finite = 0;
        C->p = body;
        C->line = body_line;
        while (next_line(C, &ls, &le)) {
            float p[3];
            if (skip_line(ls, le))
                continue;
            if ((rc = row_position(C, split(C, ls, le, fs, fe, MAX_COLUMNS), p)))
                goto done;
            finite += isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
        }
        keep_first = lc_scene_split_points(finite, part->rank, part->size);
        keep = lc_scene_split_points(finite, part->rank + 1, part->size) - keep_first;
    }
    s = lc_scene_create(name, LC_PRIM_POINTS);
    if (!s) {
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
        goto done;
    }
    if ((rc = lc_scene_alloc_vertices(s, (uint32_t)keep, 0, err)))
        goto done;
    float *attr[LC_IO_MAX_FILE_ATTRIBUTES];
    int nattr = 0;
    for (int c = 0; c < C->ncol; c++) {
        C->attr_of[c] = -1;
        if (c == C->pos_col[0] || c == C->pos_col[1] || c == C->pos_col[2])
            continue;
        if (!numeric[c]) {
            LC_WARN(LC_IO_LOG, "%s: line %zu: column '%s' is not numeric, skipped", name, header_line, C->names[c]);
            continue;
        }
        if (nattr == LC_IO_MAX_FILE_ATTRIBUTES) {
            LC_WARN(LC_IO_LOG, "%s: more than %d attribute columns, column '%s' and later skipped", name,
                    LC_IO_MAX_FILE_ATTRIBUTES, C->names[c]);
            break;
        }
        float *values = malloc((keep ? keep : 1) * sizeof *values);
        if (!values) {
            rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for attributes", name);
            goto done;
        }
        char aname[LC_NAME_LEN];
        snprintf(aname, sizeof aname, "%s", C->names[c][0] ? C->names[c] : "column");
        for (int k = 0; lc_scene_find_attribute(s, aname) >= 0 || !strcmp(aname, "rgb"); k++)
            snprintf(aname, sizeof aname, "column_%d_%d", c + 1, k);
        int idx = lc_scene_add_attribute(s, aname, values, err);
        if (idx < 0) {
            rc = idx;
            goto done;
        }
        attr[nattr] = s->attributes[idx].values;
        C->attr_of[c] = nattr++;
    }

    /* Pass 2: parse. */
    C->p = body;
    C->line = body_line;
    uint32_t v = 0;
    uint64_t kept = 0; /* rows with finite coordinates so far */
    size_t dropped = 0, first_dropped = 0;
    while (next_line(C, &ls, &le)) {
        if (skip_line(ls, le))
            continue;
        float p[3];
        if ((rc = row_position(C, split(C, ls, le, fs, fe, MAX_COLUMNS), p)))
            goto done;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            if (!dropped++)
                first_dropped = C->line;
            continue;
        }
        int mine = kept++ - keep_first < keep; /* every row is checked; a share stores its own */
        if ((v & 0xFFFF) == 0)
            lc_io_progress_report(&C->progress, size + (size_t)(C->p - (const char *)data), 2 * size);
        if (mine)
            memcpy(s->positions + 3 * (size_t)v, p, sizeof p);
        for (int c = 0; c < C->ncol; c++) {
            double x;
            if (C->attr_of[c] < 0)
                continue;
            if (!field_number(fs[c], fe[c], &x)) {
                rc = fail(C, LC_ERR_INVALID, "column '%s': '%.*s' is not a number", C->names[c],
                          (int)(fe[c] - fs[c] < 40 ? fe[c] - fs[c] : 40), fs[c]);
                goto done;
            }
            if (mine)
                attr[C->attr_of[c]][v] = (float)x;
        }
        v += mine;
    }
    if (dropped && lc_io_part_speaks(part))
        LC_WARN(LC_IO_LOG, "%s: line %zu: %zu rows with a missing or non-finite coordinate dropped", name,
                first_dropped, dropped);
    if (kept == 0) {
        C->line = first_dropped;
        rc = fail(C, LC_ERR_INVALID, "no row with finite coordinates");
        goto done;
    }
    s->vertex_count = v; /* the arrays keep room for the dropped rows */
    lc_io_set_defaults(s);
    int track = lc_csv_track_column(s);
    if (track >= 0 && lc_io_part_active(part)) /* a track's rows may lie in any share */
        rc = lc_err(err, LC_ERR_UNSUPPORTED, "%s: a track table (column '%s') is read whole, not in shares", name,
                    s->attributes[track].name);
    else if (track >= 0 && (rc = lc_csv_group_tracks(&s, track, err)) == 0 &&
             lc_scene_find_attribute(s, "importance") < 0)
        snprintf(s->default_importance, sizeof s->default_importance, "speed"); /* derived at finalize */
done:
    if (rc) {
        lc_scene_destroy(s);
        s = NULL;
    }
    free(C);
    *out = s;
    return rc;
}

int lc_load_csv_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    return load_csv(data, size, name, NULL, out, err);
}

int lc_load_csv(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_csv_memory, out, err);
}

int lc_load_csv_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return lc_io_load_path_part(path, load_csv, rank, size, out, err);
}
