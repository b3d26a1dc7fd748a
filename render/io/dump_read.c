/* LAMMPS dump reader: two walks over the mapped text. The first checks every
 * frame and number, finds the atoms (a hash of ids) and the length of every
 * line (an atom's run of consecutive frames); the second fills arrays of
 * exactly that size, unwrapping positions and deriving speed and
 * displacement, and the frame's TIMESTEP per vertex (a time for time
 * windows; the frame's number when a frame has none). Per atom it keeps only the state of its current run. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "dump.h"
#include "io_util.h"

#define MAX_COLUMNS 256
#define MAX_ATTR (LC_IO_MAX_FILE_ATTRIBUTES - 3) /* speed, displacement and timestep follow */

enum { SRC_X, SRC_XS, SRC_XU, SRC_XSU, SRC_COUNT };

typedef struct dump_atom {
    long long id;
    long long last;    /* frame of the last appearance, -1: none yet */
    uint32_t run;      /* points of the current run */
    uint32_t line;     /* walk 1: kept lines so far; walk 2: index of the current run's line */
    double prev[3];    /* unwrapped position in the previous frame */
    double first[3];   /* the run's first unwrapped position */
    double wrapped[3]; /* position as stored in the previous frame (minimum image) */
} dump_atom;

typedef struct dump_load {
    const char *data, *p, *end;
    const char *file;
    lc_error *err;
    size_t line;
    lc_io_progress progress;
    lc_io_part *part;
    int walk; /* 1 or 2 */

    /* The first frame's choice of columns. */
    int src, images, nattr, have_columns;
    int typed; /* the first row has decided which attribute columns hold numbers */
    char attr_name[MAX_ATTR][LC_NAME_LEN];
    /* The current frame. */
    int ncol, col_id, col_pos[3], col_img[3], col_attr[MAX_ATTR];
    double lo[3], h[6]; /* origin; lx, ly, lz, xy, xz, yz */
    int periodic[3], have_box;
    long long frame;
    double step_now, step_prev; /* TIMESTEP of this frame and of the previous one */
    const char *fs[MAX_COLUMNS], *fe[MAX_COLUMNS];

    dump_atom *atoms;
    uint32_t natoms, atoms_cap;
    uint32_t *hash; /* slot + 1, 0: empty */
    uint32_t hash_cap;
    lc_io_u32vec close_atom, close_len; /* walk 1: kept runs as they end */
    uint32_t *line_len;                 /* points of every line in id order */
    uint64_t lines, points, single;

    /* Walk 2: where values go. */
    lc_scene *s;
    float *attr[MAX_ATTR], *speed, *disp, *timestep;
    float *pending; /* natoms * nattr: a run's first row, written with its second */
} dump_load;

static int fail(dump_load *D, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(dump_load *D, int code, const char *fmt, ...)
{
    char reason[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    return lc_io_fail(D->err, code, D->file, "line", D->line, "%s", reason);
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

/* Next line [*ls, *le) without its end of line or surrounding blanks; 0 at the end of the file. */
static int next_line(dump_load *D, const char **ls, const char **le)
{
    if (!lc_io_next_line(&D->p, D->end, 1, ls, le))
        return 0;
    D->line++;
    return 1;
}

/* Whitespace-separated fields of [ls, le); -1 when more than max. */
static int split(const char *ls, const char *le, const char **fs, const char **fe, int max)
{
    int n = 0;
    for (const char *p = ls;;) {
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

static int field_number(const char *a, const char *b, double *out)
{
    return a < b && lc_io_parse_double(a, b, out) == b;
}

/* "ITEM: WORDS" with the words starting `what`: the rest after them, else NULL. */
static const char *item_is(const char *ls, const char *le, const char *what)
{
    size_t n = strlen(what);
    if ((size_t)(le - ls) < 6 + n || strncmp(ls, "ITEM:", 5) != 0)
        return NULL;
    const char *p = ls + 5;
    while (p < le && is_blank(*p))
        p++;
    if ((size_t)(le - p) < n || strncmp(p, what, n) != 0 || (p + n < le && !is_blank(p[n])))
        return NULL;
    return p + n;
}

static int bad_number(dump_load *D, const char *what, const char *a, const char *b)
{
    return fail(D, LC_ERR_INVALID, "%s: '%.*s' is not a number", what, (int)(b - a < 40 ? b - a : 40), a);
}

/* The one value line after TIMESTEP, NUMBER OF ATOMS, TIME or UNITS. */
static int value_line(dump_load *D, const char *item, double *v)
{
    const char *ls, *le;
    if (!next_line(D, &ls, &le))
        return fail(D, LC_ERR_INVALID, "the file ends after ITEM: %s", item);
    if (v && !field_number(ls, le, v))
        return bad_number(D, item, ls, le);
    return 0;
}

/* BOX BOUNDS [xy xz yz] [bb bb bb] and its three lines "lo hi [tilt]". */
static int read_box(dump_load *D, const char *rest, const char *le)
{
    const char *fs[8], *fe[8];
    int n = split(rest, le, fs, fe, 8), tilted = n >= 3 && fe[0] - fs[0] == 2 && !strncmp(fs[0], "xy", 2);
    int flags = tilted ? 3 : 0;
    for (int k = 0; k < 3; k++) /* old dumps name no boundaries: periodic */
        D->periodic[k] = n < flags + 3 || (fe[flags + k] - fs[flags + k] == 2 && !strncmp(fs[flags + k], "pp", 2));
    double b[3][3] = {{0}};
    size_t at[3];
    for (int k = 0; k < 3; k++) {
        const char *ls, *e;
        if (!next_line(D, &ls, &e))
            return fail(D, LC_ERR_INVALID, "the file ends inside BOX BOUNDS");
        at[k] = D->line;
        const char *vs[4], *ve[4];
        int m = split(ls, e, vs, ve, 4);
        if (m != 2 + tilted)
            return fail(D, LC_ERR_INVALID, "BOX BOUNDS: %d values, expected %d", m < 0 ? 5 : m, 2 + tilted);
        for (int j = 0; j < m; j++)
            if (!field_number(vs[j], ve[j], &b[k][j]) || !isfinite(b[k][j]))
                return bad_number(D, "BOX BOUNDS", vs[j], ve[j]);
    }
    double xy = b[0][2], xz = b[1][2], yz = b[2][2];
    /* A triclinic box's lines hold the bounding box: the tilts move its ends. */
    double xmin = fmin(fmin(0, xy), fmin(xz, xy + xz)), xmax = fmax(fmax(0, xy), fmax(xz, xy + xz));
    double lo[3] = {b[0][0] - xmin, b[1][0] - fmin(0, yz), b[2][0]};
    double hi[3] = {b[0][1] - xmax, b[1][1] - fmax(0, yz), b[2][1]};
    for (int k = 0; k < 3; k++) {
        if (!(hi[k] > lo[k]) && (D->line = at[k]))
            return fail(D, LC_ERR_INVALID, "BOX BOUNDS: axis %c is empty (%g to %g)", "xyz"[k], lo[k], hi[k]);
        D->lo[k] = lo[k];
        D->h[k] = hi[k] - lo[k];
    }
    D->h[3] = xy, D->h[4] = xz, D->h[5] = yz;
    D->have_box = 1;
    return 0;
}

static int column_index(dump_load *D, const char *name)
{
    size_t n = strlen(name);
    for (int c = 0; c < D->ncol; c++)
        if ((size_t)(D->fe[c] - D->fs[c]) == n && strncmp(D->fs[c], name, n) == 0)
            return c;
    return -1;
}

static int is_position_column(const char *a, const char *b)
{
    static const char *const names[] = {"x",  "y",   "z",   "xs",  "ys", "zs", "xu", "yu",
                                        "zu", "xsu", "ysu", "zsu", "ix", "iy", "iz", NULL};
    for (int i = 0; names[i]; i++)
        if ((size_t)(b - a) == strlen(names[i]) && strncmp(a, names[i], (size_t)(b - a)) == 0)
            return 1;
    return 0;
}

/* The ATOMS line's columns: which hold the id, the position (the first
 * frame chooses the kind, every later one must have it) and the attributes. */
static int read_columns(dump_load *D, const char *rest, const char *le)
{
    static const char *const pos[SRC_COUNT][3] = {
        {"x", "y", "z"}, {"xs", "ys", "zs"}, {"xu", "yu", "zu"}, {"xsu", "ysu", "zsu"}};
    static const int priority[SRC_COUNT] = {SRC_XU, SRC_XSU, SRC_X, SRC_XS};
    int n = split(rest, le, D->fs, D->fe, MAX_COLUMNS);
    if (n < 0)
        return fail(D, LC_ERR_LIMIT, "ITEM: ATOMS: more than %d columns", MAX_COLUMNS);
    D->ncol = n;
    if ((D->col_id = column_index(D, "id")) < 0)
        return fail(D, LC_ERR_INVALID, "ITEM: ATOMS has no 'id' column");
    int src = -1;
    for (int i = 0; i < SRC_COUNT && src < 0; i++) {
        int s = priority[i];
        for (int k = 0; k < 3; k++)
            D->col_pos[k] = column_index(D, pos[s][k]);
        if (D->col_pos[0] >= 0 && D->col_pos[1] >= 0 && D->col_pos[2] >= 0)
            src = s;
    }
    if (src < 0)
        return fail(D, LC_ERR_INVALID, "ITEM: ATOMS has no positions (x y z, xs ys zs, xu yu zu or xsu ysu zsu)");
    int images = 1;
    for (int k = 0; k < 3; k++)
        images &= (D->col_img[k] = column_index(D, (const char *[]){"ix", "iy", "iz"}[k])) >= 0;
    if (!D->have_columns) {
        D->src = src, D->images = images, D->nattr = 0;
        for (int c = 0; c < n; c++) {
            if (c == D->col_id || is_position_column(D->fs[c], D->fe[c]))
                continue;
            if (D->nattr == MAX_ATTR) {
                LC_WARN(LC_IO_LOG, "%s: line %zu: more than %d attribute columns, '%.*s' and later skipped", D->file,
                        D->line, MAX_ATTR, (int)(D->fe[c] - D->fs[c]), D->fs[c]);
                break;
            }
            size_t len = (size_t)(D->fe[c] - D->fs[c]);
            snprintf(D->attr_name[D->nattr++], LC_NAME_LEN, "%.*s", (int)(len < LC_NAME_LEN ? len : LC_NAME_LEN - 1),
                     D->fs[c]);
        }
        D->have_columns = 1;
    } else if (src != D->src || images != D->images) {
        return fail(D, LC_ERR_INVALID, "ITEM: ATOMS: the positions are given other than in the first frame");
    }
    for (int a = 0; a < D->nattr; a++)
        if ((D->col_attr[a] = column_index(D, D->attr_name[a])) < 0)
            return fail(D, LC_ERR_INVALID, "ITEM: ATOMS: column '%s' of the first frame is missing", D->attr_name[a]);
    if (src != SRC_XU && !D->have_box) /* scaled, image flags and the minimum image need the box */
        return fail(D, LC_ERR_INVALID, "ITEM: ATOMS before ITEM: BOX BOUNDS");
    return 0;
}

/* ---- atoms by id */

static uint32_t hash_of(long long id, uint32_t cap)
{
    uint64_t x = (uint64_t)id * 0x9E3779B97F4A7C15ull;
    return (uint32_t)(x >> 32) & (cap - 1);
}

static int grow_hash(dump_load *D)
{
    uint32_t cap = D->hash_cap ? 2 * D->hash_cap : 1024;
    uint32_t *h = calloc(cap, sizeof *h);
    if (!h)
        return lc_err(D->err, LC_ERR_NOMEM, "%s: out of memory for %u atoms", D->file, D->natoms);
    for (uint32_t i = 0; i < D->natoms; i++) {
        uint32_t j = hash_of(D->atoms[i].id, cap);
        while (h[j])
            j = (j + 1) & (cap - 1);
        h[j] = i + 1;
    }
    free(D->hash);
    D->hash = h, D->hash_cap = cap;
    return 0;
}

/* The atom of id in *out (a new one in walk 1). */
static int atom_of(dump_load *D, long long id, dump_atom **out)
{
    uint32_t j = hash_of(id, D->hash_cap);
    for (; D->hash[j]; j = (j + 1) & (D->hash_cap - 1))
        if (D->atoms[D->hash[j] - 1].id == id) {
            *out = &D->atoms[D->hash[j] - 1];
            return 0;
        }
    if (D->walk == 2) /* cannot happen: walk 1 saw the same file */
        return fail(D, LC_ERR_INTERNAL, "atom %lld unknown", id);
    if (D->natoms >= LC_MAX_PRIMITIVES)
        return fail(D, LC_ERR_LIMIT, "more than %u atoms", (unsigned)LC_MAX_PRIMITIVES);
    if (D->natoms == D->atoms_cap) {
        uint32_t cap = D->atoms_cap ? 2 * D->atoms_cap : 1024;
        dump_atom *a = realloc(D->atoms, (size_t)cap * sizeof *a);
        if (!a)
            return lc_err(D->err, LC_ERR_NOMEM, "%s: out of memory for %u atoms", D->file, cap);
        D->atoms = a, D->atoms_cap = cap;
    }
    D->atoms[D->natoms] = (dump_atom){.id = id, .last = -1};
    D->hash[j] = ++D->natoms;
    *out = &D->atoms[D->natoms - 1];
    return 2 * (uint64_t)D->natoms > D->hash_cap ? grow_hash(D) : 0;
}

/* ---- positions */

/* r = H s for the box's upper triangular cell matrix. */
static void cell_times(const double h[6], const double s[3], double r[3])
{
    r[0] = h[0] * s[0] + h[3] * s[1] + h[4] * s[2];
    r[1] = h[1] * s[1] + h[5] * s[2];
    r[2] = h[2] * s[2];
}

/* The shortest periodic image of displacement d. */
static void minimum_image(const dump_load *D, double d[3])
{
    const double *h = D->h;
    double s[3];
    s[2] = d[2] / h[2];
    s[1] = (d[1] - h[5] * s[2]) / h[1];
    s[0] = (d[0] - h[3] * s[1] - h[4] * s[2]) / h[0];
    for (int k = 0; k < 3; k++)
        if (D->periodic[k])
            s[k] -= nearbyint(s[k]);
    cell_times(h, s, d);
}

/* The atom's unwrapped position from the row's values (raw: the position
 * columns, img: the image flags), and its stored position for the next frame. */
static void unwrap(dump_load *D, dump_atom *a, int continues, const double raw[3], const double img[3], double out[3])
{
    double r[3] = {raw[0], raw[1], raw[2]};
    if (D->src == SRC_XS || D->src == SRC_XSU) {
        cell_times(D->h, raw, r);
        for (int k = 0; k < 3; k++)
            r[k] += D->lo[k];
    }
    if (D->src == SRC_XU || D->src == SRC_XSU) {
        memcpy(out, r, sizeof r);
    } else if (D->images) {
        double shift[3];
        cell_times(D->h, img, shift);
        for (int k = 0; k < 3; k++)
            out[k] = r[k] + shift[k];
    } else if (continues) {
        double d[3] = {r[0] - a->wrapped[0], r[1] - a->wrapped[1], r[2] - a->wrapped[2]};
        minimum_image(D, d);
        for (int k = 0; k < 3; k++)
            out[k] = a->prev[k] + d[k];
    } else {
        memcpy(out, r, sizeof r);
    }
    memcpy(a->wrapped, r, sizeof r);
}

static double distance(const double a[3], const double b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/* A run ended in walk 1: remember its line (kept runs only). */
static int close_run(dump_load *D, dump_atom *a)
{
    if (a->run == 1)
        D->single++;
    if (a->run < 2)
        return 0;
    int rc;
    if ((rc = lc_io_u32vec_push(&D->close_atom, (uint32_t)(a - D->atoms), LC_MAX_PRIMITIVES, D->file, "lines",
                                D->err)) ||
        (rc = lc_io_u32vec_push(&D->close_len, a->run, LC_MAX_PRIMITIVES, D->file, "lines", D->err)))
        return rc;
    a->line++;
    return 0;
}

/* Walk 2: vertex k of the atom's current line, when the share holds it. */
static void store(dump_load *D, const dump_atom *a, uint32_t k, const double pos[3], const float *vals, double speed,
                  double disp)
{
    const lc_io_part *P = D->part;
    if (!lc_io_part_keeps(P, a->line))
        return;
    size_t v = (size_t)D->s->line_offsets[a->line - P->first] + k;
    for (int j = 0; j < 3; j++)
        D->s->positions[3 * v + j] = (float)pos[j];
    for (int j = 0; j < D->nattr; j++)
        D->attr[j][v] = vals[j];
    D->speed[v] = (float)speed;
    D->disp[v] = (float)disp;
    D->timestep[v] = (float)(k == 0 && a->run > 1 ? D->step_prev : D->step_now); /* k 0 is stored with k 1 */
}

/* One row of ATOMS: checked in both walks, stored in the second. */
static int atom_row(dump_load *D, const char *ls, const char *le)
{
    const char **fs = D->fs, **fe = D->fe;
    int m = split(ls, le, fs, fe, MAX_COLUMNS);
    if (m != D->ncol)
        return fail(D, LC_ERR_INVALID, "%d values, ITEM: ATOMS names %d columns", m < 0 ? MAX_COLUMNS + 1 : m, D->ncol);
    double idv, raw[3], img[3] = {0, 0, 0};
    float vals[MAX_ATTR];
    int c = D->col_id;
    if (!field_number(fs[c], fe[c], &idv) || idv != floor(idv) || fabs(idv) > 9.0e15)
        return fail(D, LC_ERR_INVALID, "id: '%.*s' is not an integer", (int)(fe[c] - fs[c] < 40 ? fe[c] - fs[c] : 40),
                    fs[c]);
    for (int k = 0; k < 3; k++) {
        c = D->col_pos[k];
        if (!field_number(fs[c], fe[c], &raw[k]) || !isfinite(raw[k]))
            return bad_number(D, "position", fs[c], fe[c]);
        c = D->col_img[k];
        if (D->images && (!field_number(fs[c], fe[c], &img[k]) || img[k] != floor(img[k]) || fabs(img[k]) > 1e9))
            return fail(D, LC_ERR_INVALID, "image flag '%.*s' is not an integer",
                        (int)(fe[c] - fs[c] < 40 ? fe[c] - fs[c] : 40), fs[c]);
    }
    if (!D->typed) { /* text columns (element names) are skipped, as point tables skip them */
        for (int j = 0; j < D->nattr; j++) {
            double x;
            c = D->col_attr[j];
            if (field_number(fs[c], fe[c], &x))
                continue;
            if (lc_io_part_speaks(D->part))
                LC_WARN(LC_IO_LOG, "%s: line %zu: column '%s' is not numeric, skipped", D->file, D->line,
                        D->attr_name[j]);
            D->nattr--;
            memmove(D->attr_name[j], D->attr_name[j + 1], (size_t)(D->nattr - j) * sizeof D->attr_name[0]);
            memmove(&D->col_attr[j], &D->col_attr[j + 1], (size_t)(D->nattr - j) * sizeof D->col_attr[0]);
            j--;
        }
        D->typed = 1;
    }
    for (int j = 0; j < D->nattr; j++) {
        double x;
        c = D->col_attr[j];
        if (!field_number(fs[c], fe[c], &x))
            return bad_number(D, D->attr_name[j], fs[c], fe[c]);
        vals[j] = (float)x;
    }
    dump_atom *a = NULL;
    int rc = atom_of(D, (long long)idv, &a);
    if (rc)
        return rc;
    if (a->last == D->frame)
        return fail(D, LC_ERR_INVALID, "atom id %lld appears twice in the frame", a->id);
    int continues = a->last == D->frame - 1 && a->run > 0;
    a->last = D->frame;
    if (D->walk == 1) {
        if (!continues && (rc = close_run(D, a)))
            return rc;
        a->run = continues ? a->run + 1 : 1;
        if (a->run > LC_MAX_VERTICES)
            return fail(D, LC_ERR_LIMIT, "more than %u frames", (unsigned)LC_MAX_VERTICES);
        return 0;
    }
    double pos[3];
    unwrap(D, a, continues, raw, img, pos);
    float *pend = D->pending + (size_t)(a - D->atoms) * (size_t)D->nattr;
    if (!continues) {
        if (a->run >= 2)
            a->line++;
        a->run = 1;
        memcpy(a->first, pos, sizeof pos);
        memcpy(pend, vals, (size_t)D->nattr * sizeof *vals);
    } else {
        double step = distance(pos, a->prev);
        if (++a->run == 2)
            store(D, a, 0, a->first, pend, step, 0);
        store(D, a, a->run - 1, pos, vals, step, distance(pos, a->first));
    }
    memcpy(a->prev, pos, sizeof pos);
    return 0;
}

/* One frame from its first ITEM line on. */
static int read_frame(dump_load *D)
{
    const char *ls, *le, *rest = NULL;
    double natoms = -1, v;
    int rc;
    D->have_box = 0;
    for (;;) {
        if (!next_line(D, &ls, &le))
            return fail(D, LC_ERR_INVALID, "the file ends before ITEM: ATOMS");
        if (ls == le)
            continue;
        if (item_is(ls, le, "TIMESTEP") || item_is(ls, le, "TIME") || item_is(ls, le, "UNITS")) {
            int units = item_is(ls, le, "UNITS") != NULL, step = !units && !item_is(ls, le, "TIME");
            if ((rc = value_line(D,
                                 units                     ? "UNITS"
                                 : item_is(ls, le, "TIME") ? "TIME"
                                                           : "TIMESTEP",
                                 units ? NULL : &v)))
                return rc;
            if (step)
                D->step_now = v;
        } else if (item_is(ls, le, "NUMBER OF ATOMS")) {
            if ((rc = value_line(D, "NUMBER OF ATOMS", &natoms)))
                return rc;
            if (!(natoms >= 0) || natoms != floor(natoms) || natoms > (double)(D->end - D->p + 1) / 2)
                return fail(D, LC_ERR_INVALID, "NUMBER OF ATOMS %g: not a count the %zu bytes left can hold", natoms,
                            (size_t)(D->end - D->p));
        } else if ((rest = item_is(ls, le, "BOX BOUNDS"))) {
            if ((rc = read_box(D, rest, le)))
                return rc;
        } else if ((rest = item_is(ls, le, "ATOMS"))) {
            break;
        } else {
            return fail(D, LC_ERR_INVALID, "expected an ITEM: line of a LAMMPS dump, found '%.*s'",
                        (int)(le - ls < 40 ? le - ls : 40), ls);
        }
    }
    if (natoms < 0)
        return fail(D, LC_ERR_INVALID, "ITEM: ATOMS before ITEM: NUMBER OF ATOMS");
    if ((rc = read_columns(D, rest, le)))
        return rc;
    if (natoms * 2 * D->ncol > (double)(D->end - D->p) + 1)
        return fail(D, LC_ERR_INVALID, "%.0f atoms of %d columns cannot fit in the %zu bytes left", natoms, D->ncol,
                    (size_t)(D->end - D->p));
    for (uint64_t i = 0; i < (uint64_t)natoms; i++) {
        if (!next_line(D, &ls, &le))
            return fail(D, LC_ERR_INVALID, "the file ends after %llu of %.0f atoms", (unsigned long long)i, natoms);
        if ((rc = atom_row(D, ls, le)))
            return rc;
    }
    return 0;
}

static int walk(dump_load *D)
{
    D->p = D->data, D->line = 0, D->frame = 0, D->have_columns = D->walk == 2;
    for (uint32_t i = 0; i < D->natoms; i++)
        D->atoms[i].last = -1, D->atoms[i].run = 0;
    for (;; D->frame++) {
        while (D->p < D->end && (is_blank(*D->p) || *D->p == '\n'))
            D->line += *D->p++ == '\n';
        if (D->p >= D->end)
            break;
        lc_io_progress_report(&D->progress, (size_t)(D->p - D->data) + (D->walk == 2 ? (size_t)(D->end - D->data) : 0),
                              2 * (size_t)(D->end - D->data));
        D->step_prev = D->step_now;
        D->step_now = (double)D->frame;
        int rc = read_frame(D);
        if (rc)
            return rc;
    }
    if (D->frame == 0)
        return lc_io_fail(D->err, LC_ERR_INVALID, D->file, "line", 1, "no frame (expected ITEM: TIMESTEP)");
    if (D->walk == 1)
        for (uint32_t i = 0; i < D->natoms; i++) {
            int rc = close_run(D, &D->atoms[i]);
            if (rc)
                return rc;
        }
    return 0;
}

static int by_id(const void *a, const void *b)
{
    long long x = ((const dump_atom *)a)->id, y = ((const dump_atom *)b)->id;
    return (x > y) - (x < y);
}

/* After walk 1: the atoms in id order, every line's length in that order, and
 * each atom's first line. */
static int order_lines(dump_load *D)
{
    uint32_t *first = malloc(((size_t)D->natoms + 1) * sizeof *first);
    uint32_t *rank = malloc(((size_t)D->natoms + 1) * sizeof *rank);
    D->line_len = malloc(((size_t)D->close_len.n + 1) * sizeof *D->line_len);
    if (!first || !rank || !D->line_len) {
        free(first), free(rank);
        return lc_err(D->err, LC_ERR_NOMEM, "%s: out of memory for %zu lines", D->file, D->close_len.n);
    }
    for (uint32_t i = 0; i < D->natoms; i++)
        D->atoms[i].run = i; /* the slot before sorting */
    qsort(D->atoms, D->natoms, sizeof *D->atoms, by_id);
    uint32_t line = 0;
    for (uint32_t i = 0; i < D->natoms; i++) {
        rank[D->atoms[i].run] = i;
        first[i] = line;
        line += D->atoms[i].line;
        D->atoms[i].line = first[i]; /* now a cursor */
    }
    for (size_t r = 0; r < D->close_len.n; r++) /* runs end in time order per atom */
        D->line_len[D->atoms[rank[D->close_atom.v[r]]].line++] = D->close_len.v[r];
    for (uint32_t i = 0; i < D->natoms; i++)
        D->atoms[i].line = first[i];
    D->lines = D->close_len.n;
    free(first), free(rank);
    return grow_hash(D); /* the slots moved */
}

static int load_dump(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    dump_load *D = calloc(1, sizeof *D);
    if (!D)
        return lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    D->data = data ? data : "";
    D->end = D->data + (data ? size : 0);
    D->file = name, D->err = err, D->part = part, D->walk = 1;
    lc_io_progress_start(&D->progress, name);
    lc_scene *s = NULL;
    int rc = grow_hash(D);
    if (rc || (rc = walk(D)) || (rc = order_lines(D)))
        goto done;
    for (uint64_t l = 0; l < D->lines; l++) {
        D->points += D->line_len[l];
        if (D->points > LC_MAX_VERTICES) {
            rc = lc_err(err, LC_ERR_LIMIT, "%s: more than %u points", name, (unsigned)LC_MAX_VERTICES);
            goto done;
        }
        if ((rc = lc_io_part_count(part, D->line_len[l], name, err)))
            goto done;
    }
    if (lc_io_part_speaks(part) && D->single)
        LC_WARN(LC_IO_LOG, "%s: %llu atoms seen in one frame only (no line) dropped", name,
                (unsigned long long)D->single);
    if (D->lines == 0) {
        rc = lc_io_fail(err, LC_ERR_INVALID, name, "line", D->line,
                        "no atom appears in two consecutive frames (%lld frames read)", D->frame);
        goto done;
    }
    if ((rc = lc_io_part_choose(part, (uint32_t)D->lines, D->points, name, err)))
        goto done;
    uint32_t lines = part->last - part->first;
    s = D->s = lc_scene_create(name, LC_PRIM_LINES);
    if (!s) {
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
        goto done;
    }
    if ((rc = lc_scene_alloc_vertices(s, (uint32_t)part->points, 0, err)))
        goto done;
    s->line_offsets = calloc((size_t)lines + 1, sizeof *s->line_offsets);
    s->line_count = lines;
    D->pending = malloc(((size_t)D->natoms * (size_t)D->nattr + 1) * sizeof *D->pending);
    if (!s->line_offsets || !D->pending) {
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for %u lines", name, lines);
        goto done;
    }
    for (uint32_t l = 0; l < lines; l++)
        s->line_offsets[l + 1] = s->line_offsets[l] + D->line_len[part->first + l];
    char aname[LC_NAME_LEN];
    for (int j = 0; j < D->nattr + 3; j++) {
        float *values = malloc(((size_t)part->points + 1) * sizeof *values);
        if (!values) {
            rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory for attributes", name);
            goto done;
        }
        lc_scene_unique_attribute_name(s,
                                       j < D->nattr        ? D->attr_name[j]
                                       : j == D->nattr     ? "speed"
                                       : j == D->nattr + 1 ? "displacement"
                                                           : "timestep",
                                       aname);
        int idx = lc_scene_add_attribute(s, aname, values, err);
        if (idx < 0) {
            rc = idx;
            goto done;
        }
        *(j < D->nattr        ? &D->attr[j]
          : j == D->nattr     ? &D->speed
          : j == D->nattr + 1 ? &D->disp
                              : &D->timestep) = s->attributes[idx].values;
    }
    D->walk = 2;
    if ((rc = walk(D)))
        goto done;
    lc_io_set_defaults(s);
    snprintf(s->default_importance, sizeof s->default_importance, "%s", s->attributes[D->nattr].name);
done:
    if (rc) {
        lc_scene_destroy(s);
        s = NULL;
    }
    lc_io_u32vec_free(&D->close_atom);
    lc_io_u32vec_free(&D->close_len);
    free(D->line_len), free(D->atoms), free(D->hash), free(D->pending), free(D);
    *out = s;
    return rc;
}

int lc_load_dump_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    lc_io_part whole = {0};
    return load_dump(data, size, name, &whole, out, err);
}

int lc_load_dump(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_dump_memory, out, err);
}

int lc_load_dump_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return lc_io_load_path_part(path, load_dump, rank, size, out, err);
}
