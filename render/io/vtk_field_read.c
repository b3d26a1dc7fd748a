/* VTK legacy vector fields: STRUCTURED_POINTS and RECTILINEAR_GRID with
 * POINT_DATA VECTORS (tokens from vtk_lex.c), and the field-source opener. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "nc_field.h"
#include "vtk_field.h"
#include "vtk_internal.h"

typedef enum { GRID_NONE = 0, GRID_POINTS, GRID_RECTILINEAR } grid_type;

typedef struct field_load {
    vtk_load L; /* the tokenizer's state; L.s stays NULL */
    grid_type grid;
    uint64_t dims[3]; /* 0 until DIMENSIONS */
    double origin[3], spacing[3];
    int have_origin, have_spacing;
    double *coords[3]; /* RECTILINEAR_GRID axes */
    float *vectors;    /* the first POINT_DATA VECTORS */
    char vectors_name[64];
} field_load;

static uint64_t node_count(const field_load *F) { return F->dims[0] * F->dims[1] * F->dims[2]; }

/* ORIGIN / SPACING: three numbers written as text also in BINARY files. */
static int read_triple(vtk_load *L, const char *what, double out[3])
{
    char w[MAX_WORD];
    for (int a = 0; a < 3; a++) {
        int rc = vtk_need_word(L, w, what);
        if (rc)
            return rc;
        char *end;
        out[a] = strtod(w, &end);
        if (end == w || *end || !isfinite(out[a]))
            return fail_kw(L, LC_ERR_INVALID, "%s %c: bad number '%.40s'", what, "xyz"[a], w);
    }
    return vtk_end_keyword_line(L);
}

static int read_dimensions(field_load *F)
{
    vtk_load *L = &F->L;
    if (F->dims[0])
        return fail_kw(L, LC_ERR_INVALID, "second DIMENSIONS");
    for (int a = 0; a < 3; a++) {
        int rc = vtk_need_count(L, "DIMENSIONS", &F->dims[a]);
        if (rc)
            return rc;
        if (F->dims[a] < 2)
            return fail_kw(L, LC_ERR_INVALID,
                           "DIMENSIONS %c is %llu: a field needs at least 2 nodes per axis (extrude a 2-D field "
                           "to 2 layers)",
                           "xyz"[a], (unsigned long long)F -> dims[a]);
        if (F->dims[a] > LC_FIELD_MAX_NODES)
            return fail_kw(L, LC_ERR_LIMIT, "DIMENSIONS %c of %llu exceeds the limit of %llu nodes", "xyz"[a],
                           (unsigned long long)F -> dims[a], (unsigned long long)LC_FIELD_MAX_NODES);
    }
    if (F->dims[0] * F->dims[1] > LC_FIELD_MAX_NODES || node_count(F) > LC_FIELD_MAX_NODES)
        return fail_kw(L, LC_ERR_LIMIT, "DIMENSIONS %llu x %llu x %llu exceed the limit of %llu nodes",
                       (unsigned long long)F->dims[0], (unsigned long long)F->dims[1], (unsigned long long)F->dims[2],
                       (unsigned long long)LC_FIELD_MAX_NODES);
    /* Nothing is allocated per node until VECTORS, whose count is checked against the bytes left. */
    return vtk_end_keyword_line(L);
}

/* X_COORDINATES n type, then n strictly increasing values. */
static int read_axis(field_load *F, int a, const char *kw)
{
    vtk_load *L = &F->L;
    uint64_t n;
    vtype t;
    int rc;
    if (F->grid != GRID_RECTILINEAR)
        return fail_kw(L, LC_ERR_INVALID, "%s outside a RECTILINEAR_GRID", kw);
    if (!F->dims[0])
        return fail_kw(L, LC_ERR_INVALID, "%s before DIMENSIONS", kw);
    if (F->coords[a])
        return fail_kw(L, LC_ERR_INVALID, "second %s", kw);
    if ((rc = vtk_need_count(L, kw, &n)) || (rc = vtk_need_type(L, kw, &t)) || (rc = vtk_end_keyword_line(L)))
        return rc;
    if (n != F->dims[a])
        return fail_kw(L, LC_ERR_INVALID, "%s has %llu values, DIMENSIONS says %llu", kw, (unsigned long long)n,
                       (unsigned long long)F->dims[a]);
    if ((rc = vtk_check_room(L, n, t, kw, n)))
        return rc;
    double *c = malloc((size_t)n * sizeof *c);
    if (!c)
        return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for %s", L->file, kw);
    F->coords[a] = c;
    for (uint64_t i = 0; i < n; i++) {
        size_t line = L->line, pos = L->pos;
        if ((rc = vtk_read_value(L, t, &c[i], kw)))
            return rc;
        if (!isfinite(c[i]) || (i && !(c[i] > c[i - 1])))
            return vtk_fail_at(L, LC_ERR_INVALID, line, pos, "%s value %llu (%g) is not finite or not increasing", kw,
                               (unsigned long long)i, c[i]);
    }
    return 0;
}

/* Skips `count` values of an array the field does not use. */
static int skip_values(vtk_load *L, uint64_t count, vtype t, const char *what)
{
    int rc = vtk_check_room(L, count, t, what, count);
    return rc ? rc : vtk_read_floats(L, t, count, NULL, 1, what);
}

/* VECTORS name type: the first one becomes the field, later ones are skipped. */
static int read_vectors(field_load *F, uint64_t tuples, int point_data)
{
    vtk_load *L = &F->L;
    char name[MAX_WORD];
    vtype t;
    int rc;
    if ((rc = vtk_need_word(L, name, "VECTORS name")) || (rc = vtk_need_type(L, "VECTORS", &t)) ||
        (rc = vtk_end_keyword_line(L)))
        return rc;
    if (tuples > UINT64_MAX / 3)
        return fail_kw(L, LC_ERR_INVALID, "VECTORS count exceeds the file size");
    if (!point_data || F->vectors)
        return skip_values(L, 3 * tuples, t, "VECTORS");
    if ((rc = vtk_check_room(L, 3 * tuples, t, "VECTORS count", tuples)))
        return rc;
    F->vectors = malloc((size_t)(3 * tuples) * sizeof *F->vectors + 1);
    if (!F->vectors)
        return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for %llu vectors", L->file, (unsigned long long)tuples);
    vtk_decode_name(name, F->vectors_name, sizeof F->vectors_name);
    return vtk_read_floats(L, t, 3 * tuples, F->vectors, 1, "VECTORS");
}

/* SCALARS name type [ncomp] [LOOKUP_TABLE name]: skipped. */
static int skip_scalars(vtk_load *L, uint64_t tuples)
{
    char name[MAX_WORD];
    vtype t;
    uint64_t ncomp;
    int rc = vtk_scalars_header(L, name, &t, &ncomp);
    if (rc)
        return rc;
    if (ncomp == 0 || ncomp > 4 || tuples > UINT64_MAX / ncomp)
        return fail_kw(L, LC_ERR_INVALID, "SCALARS has %llu components (1 to 4)", (unsigned long long)ncomp);
    return skip_values(L, tuples * ncomp, t, "SCALARS");
}

/* FIELD name n, then n arrays "name ncomp ntuples type": skipped. */
static int skip_field_data(vtk_load *L)
{
    char name[MAX_WORD];
    uint64_t narrays;
    int rc;
    if ((rc = vtk_need_word(L, name, "FIELD name")) || (rc = vtk_need_count(L, "FIELD array count", &narrays)) ||
        (rc = vtk_end_keyword_line(L)))
        return rc;
    for (uint64_t i = 0; i < narrays; i++) {
        uint64_t ncomp, ntuples;
        vtype t;
        int null;
        if ((rc = vtk_field_array_header(L, name, &ncomp, &ntuples, &t, &null)))
            return rc;
        if (null)
            continue;
        if (ncomp && ntuples > UINT64_MAX / ncomp)
            return fail_kw(L, LC_ERR_INVALID, "FIELD array size exceeds the file size");
        if ((rc = skip_values(L, ncomp * ntuples, t, "FIELD array")))
            return rc;
        vtk_skip_metadata(L);
    }
    return 0;
}

static int read_dataset_line(field_load *F)
{
    vtk_load *L = &F->L;
    char w[MAX_WORD];
    int rc = vtk_need_word(L, w, "dataset type");
    if (rc)
        return rc;
    if (F->grid)
        return fail_kw(L, LC_ERR_INVALID, "second DATASET");
    if (strcasecmp(w, "STRUCTURED_POINTS") == 0)
        F->grid = GRID_POINTS;
    else if (strcasecmp(w, "RECTILINEAR_GRID") == 0)
        F->grid = GRID_RECTILINEAR;
    else
        return fail_kw(L, LC_ERR_UNSUPPORTED,
                       "dataset type '%.40s' is not a vector field (STRUCTURED_POINTS or RECTILINEAR_GRID)", w);
    return vtk_end_keyword_line(L);
}

static int parse(field_load *F)
{
    vtk_load *L = &F->L;
    char kw[MAX_WORD];
    int got, rc;
    section sec = SEC_NONE;
    uint64_t tuples = 0;
    if ((rc = vtk_read_preamble(L)))
        return rc;
    for (;;) {
        vtk_skip_ws(L);
        L->kw_line = L->line, L->kw_pos = L->pos;
        if ((rc = vtk_next_word(L, kw, &got)))
            return rc;
        if (!got)
            break;
        if (strcasecmp(kw, "DATASET") == 0)
            rc = read_dataset_line(F);
        else if (strcasecmp(kw, "FIELD") == 0)
            rc = skip_field_data(L);
        else if (strcasecmp(kw, "METADATA") == 0)
            vtk_skip_metadata_block(L);
        else if (!F->grid)
            return fail_kw(L, LC_ERR_INVALID, "expected DATASET, found '%.40s'", kw);
        else if (strcasecmp(kw, "DIMENSIONS") == 0)
            rc = read_dimensions(F);
        else if (strcasecmp(kw, "ORIGIN") == 0 && F->grid == GRID_POINTS)
            rc = read_triple(L, "ORIGIN", F->origin), F->have_origin = 1;
        else if ((strcasecmp(kw, "SPACING") == 0 || strcasecmp(kw, "ASPECT_RATIO") == 0) && F->grid == GRID_POINTS) {
            if (!(rc = read_triple(L, kw, F->spacing)))
                for (int a = 0; a < 3; a++)
                    if (!(F->spacing[a] > 0))
                        return fail_kw(L, LC_ERR_INVALID, "%s %c is %g (must be positive)", kw, "xyz"[a],
                                       F -> spacing[a]);
            F->have_spacing = 1;
        } else if (strcasecmp(kw, "X_COORDINATES") == 0)
            rc = read_axis(F, 0, "X_COORDINATES");
        else if (strcasecmp(kw, "Y_COORDINATES") == 0)
            rc = read_axis(F, 1, "Y_COORDINATES");
        else if (strcasecmp(kw, "Z_COORDINATES") == 0)
            rc = read_axis(F, 2, "Z_COORDINATES");
        else if (strcasecmp(kw, "POINT_DATA") == 0 || strcasecmp(kw, "CELL_DATA") == 0) {
            int point = strcasecmp(kw, "POINT_DATA") == 0;
            if (!F->dims[0])
                return fail_kw(L, LC_ERR_INVALID, "%s before DIMENSIONS", kw);
            if ((rc = vtk_need_count(L, kw, &tuples)) || (rc = vtk_end_keyword_line(L)))
                return rc;
            if (point && tuples != node_count(F))
                return fail_kw(L, LC_ERR_INVALID, "POINT_DATA count %llu differs from the %llu grid nodes",
                               (unsigned long long)tuples, (unsigned long long)node_count(F));
            sec = point ? SEC_POINT : SEC_CELL;
        } else if (sec == SEC_NONE)
            return fail_kw(L, LC_ERR_INVALID, "unknown or misplaced keyword '%.40s'", kw);
        else if (strcasecmp(kw, "VECTORS") == 0)
            rc = read_vectors(F, tuples, sec == SEC_POINT);
        else if (strcasecmp(kw, "NORMALS") == 0) {
            char name[MAX_WORD];
            vtype t;
            if (!(rc = vtk_need_word(L, name, "NORMALS name")) && !(rc = vtk_need_type(L, "NORMALS", &t)) &&
                !(rc = vtk_end_keyword_line(L)))
                rc = tuples > UINT64_MAX / 3 ? fail_kw(L, LC_ERR_INVALID, "NORMALS count exceeds the file size")
                                             : skip_values(L, 3 * tuples, t, "NORMALS");
        } else if (strcasecmp(kw, "SCALARS") == 0)
            rc = skip_scalars(L, tuples);
        else
            return fail_kw(L, LC_ERR_INVALID,
                           "unknown keyword '%.40s' (a field reads VECTORS, skips SCALARS, "
                           "NORMALS and FIELD arrays)",
                           kw);
        if (rc)
            return rc;
    }
    if (!F->grid)
        return fail_here(L, LC_ERR_INVALID, "no DATASET");
    if (!F->dims[0])
        return fail_here(L, LC_ERR_INVALID, "file ends without DIMENSIONS");
    if (F->grid == GRID_RECTILINEAR)
        for (int a = 0; a < 3; a++)
            if (!F->coords[a])
                return fail_here(L, LC_ERR_INVALID, "file ends without %c_COORDINATES", "XYZ"[a]);
    if (!F->vectors)
        return fail_here(L, LC_ERR_INVALID, "file ends without POINT_DATA VECTORS");
    return 0;
}

/* Uniform axes from ORIGIN and SPACING (VTK's defaults: 0 and 1). */
static int uniform_axes(field_load *F)
{
    for (int a = 0; a < 3; a++) {
        double o = F->have_origin ? F->origin[a] : 0.0, s = F->have_spacing ? F->spacing[a] : 1.0;
        F->coords[a] = malloc((size_t)F->dims[a] * sizeof *F->coords[a]);
        if (!F->coords[a])
            return lc_err(F->L.err, LC_ERR_NOMEM, "%s: out of memory for the grid", F->L.file);
        for (uint64_t i = 0; i < F->dims[a]; i++)
            F->coords[a][i] = o + s * (double)i;
        if (!isfinite(F->coords[a][F->dims[a] - 1]) || !(F->coords[a][F->dims[a] - 1] > F->coords[a][0]))
            return lc_err(F->L.err, LC_ERR_INVALID, "%s: the grid's %c extent is not finite", F->L.file, "xyz"[a]);
    }
    return 0;
}

int lc_load_vtk_field_memory(const void *data, size_t size, const char *name, lc_field **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    field_load F;
    memset(&F, 0, sizeof F);
    F.L.data = data ? data : (const void *)"";
    F.L.size = data ? size : 0;
    F.L.file = name;
    F.L.err = err;
    int rc = parse(&F);
    if (!rc && F.grid == GRID_POINTS)
        rc = uniform_axes(&F);
    if (rc) {
        for (int a = 0; a < 3; a++)
            free(F.coords[a]);
        free(F.vectors);
        return rc;
    }
    uint32_t dims[3] = {(uint32_t)F.dims[0], (uint32_t)F.dims[1], (uint32_t)F.dims[2]};
    char stem[128];
    lc_io_stem(name, stem, sizeof stem);
    rc = lc_field_create_grid(stem, F.grid == GRID_POINTS ? LC_FIELD_UNIFORM : LC_FIELD_RECTILINEAR, dims, F.coords,
                              F.vectors, out, err);
    if (!rc)
        snprintf((*out)->vectors_name, sizeof(*out)->vectors_name, "%s", F.vectors_name);
    return rc;
}

int lc_load_vtk_field(const char *path, lc_field **out, lc_error *err)
{
    *out = NULL;
    lc_io_file f;
    int rc = lc_io_file_open(path, &f, err);
    if (rc)
        return rc;
    rc = lc_load_vtk_field_memory(f.data, f.size, lc_io_basename(path), out, err);
    lc_io_file_close(&f);
    return rc;
}

static int declares_grid(const char *data, size_t size, const char *name)
{
    (void)name;
    size_t n = size < 4096 ? size : 4096;
    const char *p = memmem(data, n, "DATASET", 7);
    if (!p)
        return 0;
    p += 7;
    while (p < data + n && (*p == ' ' || *p == '\t'))
        p++;
    size_t left = (size_t)(data + n - p);
    return (left >= 17 && strncasecmp(p, "STRUCTURED_POINTS", 17) == 0) ||
           (left >= 16 && strncasecmp(p, "RECTILINEAR_GRID", 16) == 0);
}

int lc_vtk_file_is_field(const char *path) { return lc_io_file_test(path, declares_grid); }

int lc_field_is_source(const char *spec)
{
    if (strncmp(spec, "demo:", 5) == 0)
        return lc_field_is_demo(spec + 5);
    size_t n = strlen(spec);
    if (n > 3 && strcasecmp(spec + n - 3, ".nc") == 0)
        return lc_nc_file_is_field(spec);
    return n > 4 && strcasecmp(spec + n - 4, ".vtk") == 0 && lc_vtk_file_is_field(spec);
}

int lc_field_open(const char *spec, lc_field **out, lc_error *err)
{
    if (strncmp(spec, "demo:", 5) == 0)
        return lc_field_demo_create(spec + 5, out, err);
    size_t n = strlen(spec);
    if (n > 3 && strcasecmp(spec + n - 3, ".nc") == 0)
        return lc_load_nc_field(spec, out, err);
    return lc_load_vtk_field(spec, out, err);
}
