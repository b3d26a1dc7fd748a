/* VTK legacy reader (POLYDATA, ASCII and big-endian BINARY, classic and 5.1
 * OFFSETS/CONNECTIVITY cell layouts): cells, points, attributes and the
 * section structure; tokens and values come from vtk_lex.c. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vtk.h"
#include "vtk_internal.h"

/* ---- cells */

typedef enum { CELL_VERTS, CELL_LINES, CELL_POLYS, CELL_STRIPS } cell_kind;

static const char *cell_name[] = {"VERTICES", "LINES", "POLYGONS", "TRIANGLE_STRIPS"};

/* Turns the cell in L->cell into lines or triangles. */
static int emit_cell(vtk_load *L, cell_kind kind)
{
    const uint32_t *v = L->cell.v;
    size_t n = L->cell.n;
    int rc;
    L->cell_count++;
    if (kind == CELL_VERTS)
        return 0; /* the scene is all points anyway when nothing else is given */
    if (kind == CELL_LINES) {
        if (n < 2)
            return 0;
        if ((rc = lc_io_u32vec_reserve(&L->line_idx, n, LC_MAX_VERTICES, L->file, "line vertices", L->err)))
            return rc;
        memcpy(L->line_idx.v + L->line_idx.n, v, n * sizeof *v);
        L->line_idx.n += n;
        return lc_io_u32vec_push(&L->line_off, (uint32_t)L->line_idx.n, (size_t)LC_MAX_PRIMITIVES + 1, L->file, "lines",
                                 L->err);
    }
    if (n < 3)
        return 0;
    if ((rc = lc_io_u32vec_reserve(&L->triangles, 3 * (n - 2), 3 * (size_t)LC_MAX_PRIMITIVES, L->file,
                                   "triangle indices", L->err)))
        return rc;
    uint32_t *t = L->triangles.v + L->triangles.n;
    for (size_t j = 0; j + 2 < n; j++, t += 3) {
        if (kind == CELL_POLYS) { /* fan around the first corner */
            t[0] = v[0], t[1] = v[j + 1], t[2] = v[j + 2];
        } else if (j % 2 == 0) { /* strips alternate winding to keep a consistent orientation */
            t[0] = v[j], t[1] = v[j + 1], t[2] = v[j + 2];
        } else {
            t[0] = v[j + 1], t[1] = v[j], t[2] = v[j + 2];
        }
    }
    L->triangles.n += 3 * (n - 2);
    return 0;
}

/* Classic layout: "LINES n size", then n cells "k i0 .. ik-1" holding size
 * integers in all. */
static int read_cells_classic(vtk_load *L, cell_kind kind, uint64_t ncells, uint64_t size)
{
    const char *what = cell_name[kind];
    int rc;
    if (size < ncells)
        return fail_kw(L, LC_ERR_INVALID, "%s size %llu is smaller than its %llu cells", what, (unsigned long long)size,
                       (unsigned long long)ncells);
    uint64_t used = 0;
    for (uint64_t c = 0; c < ncells; c++) {
        double k;
        if ((rc = vtk_read_value(L, VT_I32, &k, what)))
            return rc;
        if (used >= size || !(k >= 0) || k != floor(k) || k > (double)(size - used - 1))
            return fail_here(L, LC_ERR_INVALID, "%s cell %llu: point count %.17g exceeds the declared size %llu", what,
                             (unsigned long long)c, k, (unsigned long long)size);
        used += 1 + (uint64_t)k;
        L->cell.n = 0;
        if ((rc = lc_io_u32vec_reserve(&L->cell, (size_t)k, LC_MAX_VERTICES, L->file, "cell points", L->err)))
            return rc;
        for (uint32_t j = 0; j < (uint32_t)k; j++)
            if ((rc = vtk_read_index(L, VT_I32, &L->cell.v[j], what)))
                return rc;
        L->cell.n = (size_t)k;
        if ((rc = emit_cell(L, kind)))
            return rc;
    }
    if (used != size)
        return fail_kw(L, LC_ERR_INVALID, "%s size %llu does not match its cells (%llu values)", what,
                       (unsigned long long)size, (unsigned long long)used);
    return 0;
}

/* 5.1 layout: "LINES noffsets nconn", "OFFSETS type" + noffsets values,
 * "CONNECTIVITY type" + nconn point ids. The offsets are read into memory
 * (bounded by the file size) because they precede the ids they slice. */
static int read_cells_offsets(vtk_load *L, cell_kind kind, uint64_t noffsets, uint64_t nconn)
{
    const char *what = cell_name[kind];
    char w[MAX_WORD];
    vtype t;
    int rc;
    lc_io_u32vec offs = {0};
    vtk_skip_ws(L);
    L->kw_line = L->line, L->kw_pos = L->pos;
    if ((rc = vtk_need_word(L, w, "OFFSETS")))
        return rc;
    if ((rc = vtk_need_type(L, "OFFSETS", &t)) || (rc = vtk_end_keyword_line(L)))
        return rc;
    if (!vtk_is_integer_type(t))
        return fail_kw(L, LC_ERR_INVALID, "%s OFFSETS are not integers", what);
    if ((rc = vtk_check_room(L, noffsets, t, "OFFSETS count", noffsets)))
        return rc;
    if (noffsets > (uint64_t)LC_MAX_PRIMITIVES + 1)
        return fail_kw(L, LC_ERR_LIMIT, "%s: %llu cells exceed the limit of %u", what, (unsigned long long)noffsets - 1,
                       (unsigned)LC_MAX_PRIMITIVES);
    if (noffsets && (rc = lc_io_u32vec_reserve(&offs, (size_t)noffsets, (size_t)LC_MAX_PRIMITIVES + 1, L->file,
                                               "cell offsets", L->err)))
        return rc;
    for (uint64_t i = 0; i < noffsets; i++) {
        double v;
        if ((rc = vtk_read_value(L, t, &v, "OFFSETS")))
            goto done;
        /* Offsets start at 0, never decrease and end at the connectivity size. */
        double prev = i ? offs.v[i - 1] : 0;
        if (!(v >= prev) || v != floor(v) || v > (double)nconn || (i == 0 && v != 0)) {
            rc = fail_here(L, LC_ERR_INVALID,
                           "%s offset %llu is %.17g (must start at 0, not decrease and stay "
                           "within %llu)",
                           what, (unsigned long long)i, v, (unsigned long long)nconn);
            goto done;
        }
        offs.v[offs.n++] = (uint32_t)v;
    }
    if (noffsets && offs.v[noffsets - 1] != nconn) {
        rc = fail_here(L, LC_ERR_INVALID, "%s offsets end at %u, not at the connectivity size %llu", what,
                       offs.v[noffsets - 1], (unsigned long long)nconn);
        goto done;
    }
    vtk_skip_ws(L);
    L->kw_line = L->line, L->kw_pos = L->pos;
    if ((rc = vtk_need_word(L, w, "CONNECTIVITY")))
        goto done;
    if (strcasecmp(w, "CONNECTIVITY") != 0) {
        rc = fail_here(L, LC_ERR_INVALID, "expected CONNECTIVITY in %s, found '%.40s'", what, w);
        goto done;
    }
    if ((rc = vtk_need_type(L, "CONNECTIVITY", &t)) || (rc = vtk_end_keyword_line(L)))
        goto done;
    if (!vtk_is_integer_type(t)) {
        rc = fail_kw(L, LC_ERR_INVALID, "%s CONNECTIVITY is not integer", what);
        goto done;
    }
    if ((rc = vtk_check_room(L, nconn, t, "CONNECTIVITY size", nconn)))
        goto done;
    for (uint64_t c = 0; c + 1 < noffsets; c++) {
        uint32_t k = offs.v[c + 1] - offs.v[c];
        L->cell.n = 0;
        if ((rc = lc_io_u32vec_reserve(&L->cell, k, LC_MAX_VERTICES, L->file, "cell points", L->err)))
            goto done;
        for (uint32_t j = 0; j < k; j++)
            if ((rc = vtk_read_index(L, t, &L->cell.v[j], what)))
                goto done;
        L->cell.n = k;
        if ((rc = emit_cell(L, kind)))
            goto done;
    }
done:
    lc_io_u32vec_free(&offs);
    return rc;
}

static int read_cells(vtk_load *L, cell_kind kind)
{
    const char *what = cell_name[kind];
    uint64_t a, b;
    int rc;
    if (!L->npoints)
        return fail_kw(L, LC_ERR_INVALID, "%s before POINTS", what);
    if ((rc = vtk_need_count(L, "cell count", &a)) || (rc = vtk_need_count(L, "cell size", &b)))
        return rc;
    if ((rc = vtk_end_keyword_line(L)))
        return rc;
    if (vtk_at_keyword(L, "OFFSETS", 0))
        return read_cells_offsets(L, kind, a, b);
    char label[64];
    snprintf(label, sizeof label, "%s size", what);
    if ((rc = vtk_check_room(L, b, VT_I32, label, b)))
        return rc;
    return read_cells_classic(L, kind, a, b);
}

/* ---- points and attributes */

static int read_points(vtk_load *L)
{
    uint64_t n;
    vtype t;
    int rc;
    if (L->npoints)
        return fail_kw(L, LC_ERR_INVALID, "duplicate POINTS");
    if ((rc = vtk_need_count(L, "POINTS count", &n)) || (rc = vtk_need_type(L, "POINTS", &t)) ||
        (rc = vtk_end_keyword_line(L)))
        return rc;
    if (n == 0)
        return fail_kw(L, LC_ERR_INVALID, "no points");
    if (n > UINT64_MAX / 3 || (rc = vtk_check_room(L, 3 * n, t, "POINTS count", n)))
        return rc ? rc : fail_kw(L, LC_ERR_INVALID, "POINTS count %llu exceeds the file size", (unsigned long long)n);
    if (n > LC_MAX_VERTICES)
        return fail_kw(L, LC_ERR_LIMIT, "POINTS count %llu exceeds the limit of %u", (unsigned long long)n,
                       (unsigned)LC_MAX_VERTICES);
    if ((rc = lc_scene_alloc_vertices(L->s, (uint32_t)n, 0, L->err)))
        return rc;
    for (uint64_t i = 0; i < n; i++) {
        size_t line = L->line, pos = L->pos;
        if ((rc = vtk_read_floats(L, t, 3, L->s->positions + 3 * i, 1, "POINTS")))
            return rc;
        const float *p = L->s->positions + 3 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            vtk_skip_ws(L);
            return vtk_fail_at(L, LC_ERR_INVALID, L->binary ? line : L->line, pos,
                               "point %llu has a non-finite or out-of-range coordinate", (unsigned long long)i);
        }
    }
    L->npoints = (uint32_t)n;
    return 0;
}

/* Attribute slot check: beyond LC_IO_MAX_FILE_ATTRIBUTES arrays are dropped. */
static int room_for_attributes(vtk_load *L, int n) { return L->s->attribute_count + n <= LC_IO_MAX_FILE_ATTRIBUTES; }

/* Reads `tuples` x `ncomp` values. In POINT_DATA, keep says what to make:
 * 1 = one attribute per component (name, or name_0..), 2 = the vector
 * magnitude as name_magnitude, 0 = drop. */
static int read_array(vtk_load *L, const char *raw_name, vtype t, uint64_t ncomp, uint64_t tuples, int keep)
{
    char name[LC_NAME_LEN];
    vtk_decode_name(raw_name, name, sizeof name);
    if (ncomp == 0 || ncomp > 1024)
        return fail_kw(L, LC_ERR_INVALID, "array '%.40s' has %llu components", name, (unsigned long long)ncomp);
    if (tuples > UINT64_MAX / ncomp)
        return fail_kw(L, LC_ERR_INVALID, "array '%.40s' size exceeds the file size", name);
    char label[LC_NAME_LEN + 16];
    snprintf(label, sizeof label, "'%s' size", name);
    int rc = vtk_check_room(L, tuples * ncomp, t, label, tuples * ncomp);
    if (rc)
        return rc;
    if (L->sec != SEC_POINT)
        keep = 0;
    int nattr = keep == 1 ? (int)ncomp : 1;
    if (keep == 1 && ncomp > 16) { /* a spectrum or a matrix, not scalars to look at */
        LC_WARN(LC_IO_LOG, "%s: array '%s' has %llu components; skipped", L->file, name, (unsigned long long)ncomp);
        keep = 0;
    }
    if (keep && !room_for_attributes(L, nattr)) {
        L->skipped_attrs++;
        keep = 0;
    }
    if (!keep)
        return vtk_read_floats(L, t, tuples * ncomp, NULL, 1, name);
    /* tuples == npoints here (checked by POINT_DATA). */
    float *vals = malloc((size_t)tuples * (size_t)ncomp * sizeof *vals + 1);
    if (!vals)
        return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for array '%s'", L->file, name);
    if ((rc = vtk_read_floats(L, t, tuples * ncomp, vals, 1, name))) {
        free(vals);
        return rc;
    }
    if (keep == 2) { /* magnitude, computed in place into the first tuples floats */
        for (uint64_t i = 0; i < tuples; i++) {
            double m = 0;
            for (uint64_t c = 0; c < ncomp; c++)
                m += (double)vals[i * ncomp + c] * vals[i * ncomp + c];
            vals[i] = (float)sqrt(m);
        }
        char mname[LC_NAME_LEN];
        snprintf(mname, sizeof mname, "%.*s_magnitude", LC_NAME_LEN - 11, name);
        int idx = lc_scene_add_attribute(L->s, mname, vals, L->err);
        return idx < 0 ? idx : 0;
    }
    if (ncomp == 1) {
        int idx = lc_scene_add_attribute(L->s, name, vals, L->err);
        return idx < 0 ? idx : 0;
    }
    for (uint64_t c = 0; c < ncomp; c++) {
        float *comp = malloc((size_t)tuples * sizeof *comp + 1);
        if (!comp) {
            free(vals);
            return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for array '%s'", L->file, name);
        }
        for (uint64_t i = 0; i < tuples; i++)
            comp[i] = vals[i * ncomp + c];
        char cname[LC_NAME_LEN];
        snprintf(cname, sizeof cname, "%.*s_%u", LC_NAME_LEN - 6, name, (unsigned)c);
        int idx = lc_scene_add_attribute(L->s, cname, comp, L->err);
        if (idx < 0) {
            free(vals);
            return idx;
        }
    }
    free(vals);
    return 0;
}

static int read_scalars(vtk_load *L, uint64_t tuples)
{
    char name[MAX_WORD];
    vtype t;
    uint64_t ncomp;
    int rc = vtk_scalars_header(L, name, &t, &ncomp);
    if (rc)
        return rc;
    return read_array(L, name, t, ncomp, tuples, 1);
}

/* COLOR_SCALARS name n: floats in [0,1] (ASCII) or uchar (binary). */
static int read_color_scalars(vtk_load *L, uint64_t tuples)
{
    char name[MAX_WORD];
    uint64_t ncomp;
    int rc;
    if ((rc = vtk_need_word(L, name, "COLOR_SCALARS name")) ||
        (rc = vtk_need_count(L, "COLOR_SCALARS count", &ncomp)) || (rc = vtk_end_keyword_line(L)))
        return rc;
    vtype t = L->binary ? VT_U8 : VT_F32;
    if (ncomp == 0 || ncomp > 1024)
        return fail_kw(L, LC_ERR_INVALID, "COLOR_SCALARS has %llu components", (unsigned long long)ncomp);
    if (tuples > UINT64_MAX / ncomp ||
        (rc = vtk_check_room(L, tuples * ncomp, t, "COLOR_SCALARS size", tuples * ncomp)))
        return rc ? rc : fail_kw(L, LC_ERR_INVALID, "COLOR_SCALARS size exceeds the file size");
    if (L->sec != SEC_POINT || (ncomp != 3 && ncomp != 4) || L->s->rgb) {
        if (L->sec == SEC_POINT)
            LC_WARN(LC_IO_LOG, "%s: COLOR_SCALARS '%s' with %llu components skipped", L->file, name,
                    (unsigned long long)ncomp);
        return vtk_read_floats(L, t, tuples * ncomp, NULL, 1, "COLOR_SCALARS");
    }
    float *rgb = malloc(3 * (size_t)tuples * sizeof *rgb + 1);
    if (!rgb)
        return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for colours", L->file);
    for (uint64_t i = 0; i < tuples; i++)
        for (uint64_t c = 0; c < ncomp; c++) {
            double v;
            if ((rc = vtk_read_value(L, t, &v, "COLOR_SCALARS"))) {
                free(rgb);
                return rc;
            }
            if (L->binary)
                v /= 255.0;
            if (c < 3)
                rgb[3 * i + c] = (float)(v > 0 ? (v < 1 ? v : 1) : 0); /* NaN becomes 0 */
        }
    L->s->rgb = rgb;
    return 0;
}

/* FIELD name k, then k arrays "name ncomp ntuples type". */
static int read_field(vtk_load *L, uint64_t tuples)
{
    char w[MAX_WORD], name[MAX_WORD];
    uint64_t narrays;
    int rc;
    if ((rc = vtk_need_word(L, w, "FIELD name")) || (rc = vtk_need_count(L, "FIELD array count", &narrays)))
        return rc;
    for (uint64_t i = 0; i < narrays; i++) {
        uint64_t ncomp, ntuples;
        vtype t;
        int null;
        if ((rc = vtk_field_array_header(L, name, &ncomp, &ntuples, &t, &null)))
            return rc;
        if (null)
            continue;
        int keep = L->sec == SEC_POINT && ncomp == 1 && ntuples == tuples;
        if (L->sec == SEC_POINT && !keep)
            LC_WARN(LC_IO_LOG, "%s: field array '%s' (%llu components, %llu tuples) skipped", L->file, name,
                    (unsigned long long)ncomp, (unsigned long long)ntuples);
        if ((rc = read_array(L, name, t, ncomp, ntuples, keep)))
            return rc;
        vtk_skip_metadata(L);
    }
    return 0;
}

/* LOOKUP_TABLE name n: n RGBA entries (floats in ASCII, uchar in binary). */
static int skip_lookup_table(vtk_load *L)
{
    char name[MAX_WORD];
    uint64_t n;
    int rc;
    if ((rc = vtk_need_word(L, name, "LOOKUP_TABLE name")) || (rc = vtk_need_count(L, "LOOKUP_TABLE size", &n)) ||
        (rc = vtk_end_keyword_line(L)))
        return rc;
    vtype t = L->binary ? VT_U8 : VT_F32;
    if (n > UINT64_MAX / 4 || (rc = vtk_check_room(L, 4 * n, t, "LOOKUP_TABLE size", n)))
        return rc ? rc
                  : fail_kw(L, LC_ERR_INVALID, "LOOKUP_TABLE size %llu exceeds the file size", (unsigned long long)n);
    return vtk_read_floats(L, t, 4 * n, NULL, 1, "LOOKUP_TABLE");
}

/* "KEYWORD name type" arrays with a fixed component count. */
static int read_named_array(vtk_load *L, const char *kw, uint64_t ncomp, int keep, uint64_t tuples)
{
    char name[MAX_WORD];
    vtype t;
    int rc;
    if ((rc = vtk_need_word(L, name, kw)))
        return rc;
    if (strcasecmp(kw, "TEXTURE_COORDINATES") == 0 && (rc = vtk_need_count(L, "TEXTURE_COORDINATES dimension", &ncomp)))
        return rc;
    if ((rc = vtk_need_type(L, kw, &t)) || (rc = vtk_end_keyword_line(L)))
        return rc;
    return read_array(L, name, t, ncomp, tuples, keep);
}

static int read_data_count(vtk_load *L, const char *kw, uint64_t *out)
{
    int rc = vtk_need_count(L, kw, out);
    if (rc)
        return rc;
    return vtk_end_keyword_line(L);
}

/* "# vtk DataFile Version x.y", a title line, ASCII|BINARY. */
int vtk_read_preamble(vtk_load *L)
{
    static const char magic[] = "# vtk DataFile Version";
    size_t n = sizeof magic - 1;
    L->line = 1;
    if (L->size < n || strncasecmp((const char *)L->data, magic, n) != 0)
        return fail_here(L, LC_ERR_INVALID, "not a VTK legacy file (missing '# vtk DataFile Version')");
    L->pos = n;
    char w[MAX_WORD];
    int got, rc;
    while (L->pos < L->size && (L->data[L->pos] == ' ' || L->data[L->pos] == '\t'))
        L->pos++;
    L->version_major = L->pos < L->size && L->data[L->pos] >= '0' && L->data[L->pos] <= '9' ? L->data[L->pos] - '0' : 0;
    vtk_skip_line(L);
    vtk_skip_line(L); /* the title: free text */
    L->kw_line = L->line, L->kw_pos = L->pos;
    if ((rc = vtk_next_word(L, w, &got)))
        return rc;
    if (got && strcasecmp(w, "BINARY") == 0)
        L->binary = 1;
    else if (!got || strcasecmp(w, "ASCII") != 0)
        return fail_kw(L, LC_ERR_INVALID, "expected ASCII or BINARY, found '%.40s'", w);
    return 0;
}

static int parse(vtk_load *L)
{
    char kw[MAX_WORD], w[MAX_WORD];
    int got, rc, have_dataset = 0;
    uint64_t tuples = 0; /* of the current POINT_DATA / CELL_DATA section */
    if ((rc = vtk_read_preamble(L)))
        return rc;
    for (;;) {
        vtk_skip_ws(L);
        L->kw_line = L->line, L->kw_pos = L->pos;
        if ((rc = vtk_next_word(L, kw, &got)))
            return rc;
        if (!got)
            break;
        if (strcasecmp(kw, "DATASET") == 0) {
            if ((rc = vtk_need_word(L, w, "dataset type")))
                return rc;
            if (have_dataset)
                return fail_kw(L, LC_ERR_INVALID, "second DATASET");
            if (strcasecmp(w, "POLYDATA") != 0)
                return fail_kw(L, LC_ERR_UNSUPPORTED, "dataset type '%.40s' is not supported (only POLYDATA)", w);
            have_dataset = 1;
            if ((rc = vtk_end_keyword_line(L)))
                return rc;
            continue;
        }
        if (strcasecmp(kw, "FIELD") == 0) { /* dataset field data (before DATASET too), or point/cell arrays */
            if ((rc = read_field(L, tuples)))
                return rc;
            continue;
        }
        if (strcasecmp(kw, "METADATA") == 0) {
            vtk_skip_metadata_block(L);
            continue;
        }
        if (!have_dataset)
            return fail_kw(L, LC_ERR_INVALID, "expected DATASET, found '%.40s'", kw);
        if (strcasecmp(kw, "POINTS") == 0)
            rc = read_points(L);
        else if (strcasecmp(kw, "VERTICES") == 0)
            rc = read_cells(L, CELL_VERTS);
        else if (strcasecmp(kw, "LINES") == 0)
            rc = read_cells(L, CELL_LINES);
        else if (strcasecmp(kw, "POLYGONS") == 0)
            rc = read_cells(L, CELL_POLYS);
        else if (strcasecmp(kw, "TRIANGLE_STRIPS") == 0)
            rc = read_cells(L, CELL_STRIPS);
        else if (strcasecmp(kw, "POINT_DATA") == 0) {
            if (!L->npoints)
                return fail_kw(L, LC_ERR_INVALID, "POINT_DATA before POINTS");
            if ((rc = read_data_count(L, "POINT_DATA count", &tuples)))
                return rc;
            if (tuples != L->npoints)
                return fail_kw(L, LC_ERR_INVALID, "POINT_DATA count %llu differs from the %u points",
                               (unsigned long long)tuples, L->npoints);
            L->sec = SEC_POINT;
        } else if (strcasecmp(kw, "CELL_DATA") == 0) {
            if ((rc = read_data_count(L, "CELL_DATA count", &tuples)))
                return rc;
            L->sec = SEC_CELL;
        } else if (L->sec == SEC_NONE) {
            return fail_kw(L, LC_ERR_INVALID, "unknown or misplaced keyword '%.40s'", kw);
        } else if (strcasecmp(kw, "SCALARS") == 0)
            rc = read_scalars(L, tuples);
        else if (strcasecmp(kw, "COLOR_SCALARS") == 0)
            rc = read_color_scalars(L, tuples);
        else if (strcasecmp(kw, "LOOKUP_TABLE") == 0)
            rc = skip_lookup_table(L);
        else if (strcasecmp(kw, "VECTORS") == 0)
            rc = read_named_array(L, kw, 3, 2, tuples);
        else if (strcasecmp(kw, "NORMALS") == 0)
            rc = read_named_array(L, kw, 3, 0, tuples);
        else if (strcasecmp(kw, "TEXTURE_COORDINATES") == 0)
            rc = read_named_array(L, kw, 0, 0, tuples);
        else if (strcasecmp(kw, "TENSORS") == 0)
            rc = read_named_array(L, kw, 9, 0, tuples);
        else if (strcasecmp(kw, "TENSORS6") == 0)
            rc = read_named_array(L, kw, 6, 0, tuples);
        else if (strcasecmp(kw, "GLOBAL_IDS") == 0 || strcasecmp(kw, "PEDIGREE_IDS") == 0)
            rc = read_named_array(L, kw, 1, 0, tuples);
        else
            return fail_kw(L, LC_ERR_INVALID, "unknown keyword '%.40s'", kw);
        if (rc)
            return rc;
    }
    if (!have_dataset)
        return fail_here(L, LC_ERR_INVALID, "no DATASET");
    if (!L->npoints)
        return fail_here(L, LC_ERR_INVALID, "file ends without POINTS");
    if (L->skipped_attrs)
        LC_WARN(LC_IO_LOG, "%s: %llu arrays skipped (at most %d attributes)", L->file,
                (unsigned long long)L->skipped_attrs, LC_IO_MAX_FILE_ATTRIBUTES);
    return 0;
}

/* Lines win over surfaces (as in PLY and OBJ), surfaces over points. */
/* A process's share of the lines (lc_scene_read_file_part): the whole lines
 * lc_scene_shard would give it, gathered from the points parsed whole. */
static int assemble_part(vtk_load *L, size_t line_count)
{
    lc_io_part *P = L->part;
    const uint32_t *off = L->line_off.v;
    int rc = 0;
    for (size_t l = 0; l < line_count && !rc; l++)
        rc = lc_io_part_count(P, off[l + 1] - off[l], L->file, L->err);
    if (rc || (rc = lc_io_part_choose(P, (uint32_t)line_count, off[line_count], L->file, L->err)))
        return rc;
    uint32_t n = P->last - P->first, *share = malloc(((size_t)n + 1) * sizeof *share);
    if (!share)
        return lc_err(L->err, LC_ERR_NOMEM, "%s: out of memory for %u lines", L->file, n);
    for (uint32_t l = 0; l <= n; l++)
        share[l] = off[P->first + l] - off[P->first];
    return lc_io_make_lines(&L->s, L->line_idx.v + off[P->first], share[n], share, n, L->file, L->err);
}

static int assemble(vtk_load *L)
{
    size_t line_count = L->line_off.n - 1;
    if (lc_io_part_active(L->part) && line_count == 0)
        return lc_err(L->err, LC_ERR_UNSUPPORTED, "%s: no LINES: only polylines are read in parts", L->file);
    if (line_count > 0 && lc_io_part_active(L->part)) {
        int rc = assemble_part(L, line_count);
        if (rc)
            return rc;
    } else if (line_count > 0) {
        if (L->triangles.n)
            LC_WARN(LC_IO_LOG, "%s: %zu triangles ignored because the file has lines", L->file, L->triangles.n / 3);
        uint32_t *offsets = L->line_off.v;
        memset(&L->line_off, 0, sizeof L->line_off); /* ownership moves to the scene */
        int rc = lc_io_make_lines(&L->s, L->line_idx.v, L->line_idx.n, offsets, (uint32_t)line_count, L->file, L->err);
        if (rc)
            return rc;
    } else if (L->triangles.n) {
        L->s->type = LC_PRIM_TRIANGLES;
        L->s->triangle_count = (uint32_t)(L->triangles.n / 3);
        L->s->triangles = L->triangles.v;
        memset(&L->triangles, 0, sizeof L->triangles);
    } else {
        L->s->type = LC_PRIM_POINTS;
    }
    lc_io_set_defaults(L->s);
    return 0;
}

static int load_vtk(const void *data, size_t size, const char *name, lc_io_part *part, lc_scene **out, lc_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    vtk_load L;
    memset(&L, 0, sizeof L);
    L.part = part;
    L.data = data ? data : (const void *)"";
    L.size = data ? size : 0;
    L.file = name;
    L.err = err;
    L.s = lc_scene_create(name, LC_PRIM_POINTS);
    int rc;
    if (!L.s)
        rc = lc_err(err, LC_ERR_NOMEM, "%s: out of memory", name);
    else if (!(rc = lc_io_u32vec_push(&L.line_off, 0, (size_t)LC_MAX_PRIMITIVES + 1, name, "lines", err)) &&
             !(rc = parse(&L)))
        rc = assemble(&L);
    lc_io_u32vec_free(&L.cell);
    lc_io_u32vec_free(&L.line_idx);
    lc_io_u32vec_free(&L.line_off);
    lc_io_u32vec_free(&L.triangles);
    if (rc) {
        lc_scene_destroy(L.s);
        return rc;
    }
    *out = L.s;
    return 0;
}

int lc_load_vtk_memory(const void *data, size_t size, const char *name, lc_scene **out, lc_error *err)
{
    return load_vtk(data, size, name, NULL, out, err);
}

int lc_load_vtk(const char *path, lc_scene **out, lc_error *err)
{
    return lc_io_load_path(path, lc_load_vtk_memory, out, err);
}

int lc_load_vtk_part(const char *path, int rank, int size, lc_scene **out, lc_error *err)
{
    return lc_io_load_path_part(path, load_vtk, rank, size, out, err);
}

static int has_lines(const char *data, size_t size, const char *name)
{
    (void)name;
    return size > 0 && memmem(data, size, "\nLINES ", 7) != NULL;
}

int lc_vtk_file_has_lines(const char *path) { return lc_io_file_test(path, has_lines); }
