/* VTK legacy reader, tokens and values: type names, words, counts, keywords,
 * and ASCII or big-endian binary numbers with bounds checks. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vtk_internal.h"

const int vtk_type_size[] = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};

vtype vtk_type_from_name(const char *s)
{
    /* "vtkIdType" is written as a 32-bit int by VTK's legacy writer; "long"
     * follows LP64, which is what every VTK binary of the last decade used. */
    static const struct {
        const char *name;
        vtype type;
    } names[] = {{"char", VT_I8},           {"signed_char", VT_I8},         {"unsigned_char", VT_U8},
                 {"short", VT_I16},         {"unsigned_short", VT_U16},     {"int", VT_I32},
                 {"unsigned_int", VT_U32},  {"vtkidtype", VT_I32},          {"long", VT_I64},
                 {"unsigned_long", VT_U64}, {"vtktypeint64", VT_I64},       {"vtktypeuint64", VT_U64},
                 {"long_long", VT_I64},     {"unsigned_long_long", VT_U64}, {"float", VT_F32},
                 {"double", VT_F64},        {"vtktypeint32", VT_I32},       {"vtktypeuint32", VT_U32}};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++)
        if (strcasecmp(s, names[i].name) == 0)
            return names[i].type;
    return VT_NONE;
}

int vtk_is_integer_type(vtype t) { return t >= VT_I8 && t <= VT_U64; }

/* Error at the current keyword: line for ASCII, byte offset for binary. */
int vtk_fail_at(vtk_load *L, int code, size_t line, size_t pos, const char *fmt, ...)
{
    char reason[LC_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    return lc_io_fail(L->err, code, L->file, L->binary ? "byte offset" : "line", L->binary ? pos : line, "%s", reason);
}
/* ---- tokens */

int vtk_is_space(unsigned char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

void vtk_skip_ws(vtk_load *L)
{
    while (L->pos < L->size && vtk_is_space(L->data[L->pos]))
        L->line += L->data[L->pos++] == '\n';
}

/* Next whitespace-separated word into w (NUL-terminated); 0 at end of file. */
int vtk_next_word(vtk_load *L, char *w, int *got)
{
    vtk_skip_ws(L);
    *got = 0;
    w[0] = '\0';
    if (L->pos >= L->size)
        return 0;
    size_t n = 0;
    while (L->pos + n < L->size && !vtk_is_space(L->data[L->pos + n])) {
        if (n + 1 >= MAX_WORD)
            return fail_here(L, LC_ERR_INVALID, "word longer than %d bytes", MAX_WORD - 1);
        if (L->data[L->pos + n] == '\0') /* would cut the C string short of what the file says */
            return fail_here(L, LC_ERR_INVALID, "NUL byte in a keyword line");
        w[n] = (char)L->data[L->pos + n];
        n++;
    }
    w[n] = '\0';
    L->pos += n;
    *got = 1;
    return 0;
}

/* A word the grammar requires; `what` says what was expected. */
int vtk_need_word(vtk_load *L, char *w, const char *what)
{
    int got, rc = vtk_next_word(L, w, &got);
    if (rc)
        return rc;
    if (!got)
        return fail_here(L, LC_ERR_INVALID, "file ends before %s", what);
    return 0;
}

int vtk_parse_count(const char *s, uint64_t *out)
{
    uint64_t v = 0;
    if (!*s)
        return -1;
    for (; *s; s++) {
        if (*s < '0' || *s > '9' || v > (UINT64_MAX - 9) / 10)
            return -1;
        v = v * 10 + (uint64_t)(*s - '0');
    }
    *out = v;
    return 0;
}

int vtk_need_count(vtk_load *L, const char *what, uint64_t *out)
{
    char w[MAX_WORD];
    int rc = vtk_need_word(L, w, what);
    if (rc)
        return rc;
    if (vtk_parse_count(w, out))
        return fail_kw(L, LC_ERR_INVALID, "bad %s '%.40s'", what, w);
    return 0;
}

int vtk_need_type(vtk_load *L, const char *what, vtype *out)
{
    char w[MAX_WORD];
    int rc = vtk_need_word(L, w, what);
    if (rc)
        return rc;
    *out = vtk_type_from_name(w);
    if (*out == VT_NONE)
        return fail_kw(L, LC_ERR_INVALID, "unsupported data type '%.40s' for %s", w, what);
    return 0;
}

/* Binary data starts right after the newline that ends its keyword line. */
int vtk_end_keyword_line(vtk_load *L)
{
    if (!L->binary)
        return 0;
    while (L->pos < L->size && L->data[L->pos] != '\n') {
        unsigned char c = L->data[L->pos];
        if (c != ' ' && c != '\t' && c != '\r')
            return fail_kw(L, LC_ERR_INVALID, "unexpected text after the keyword line");
        L->pos++;
    }
    if (L->pos < L->size) {
        L->pos++;
        L->line++;
    }
    return 0;
}

/* Skips the rest of the current line (ASCII headers, METADATA). */
void vtk_skip_line(vtk_load *L)
{
    while (L->pos < L->size && L->data[L->pos] != '\n')
        L->pos++;
    if (L->pos < L->size) {
        L->pos++;
        L->line++;
    }
}

/* Whether the next word is kw. Right after a keyword line (after_data = 0)
 * binary files are looked at exactly at pos, since skipping "whitespace"
 * there could walk into binary values. */
int vtk_at_keyword(const vtk_load *L, const char *kw, int after_data)
{
    size_t pos = L->pos, n = strlen(kw);
    if (!L->binary || after_data)
        while (pos < L->size && vtk_is_space(L->data[pos]))
            pos++;
    return L->size - pos >= n && strncasecmp((const char *)L->data + pos, kw, n) == 0 &&
           (pos + n == L->size || vtk_is_space(L->data[pos + n]));
}

/* VTK 5.x follows arrays with "METADATA" and lines of key/value pairs up to
 * a blank line; nothing in them matters for rendering. */
void vtk_skip_metadata_block(vtk_load *L)
{
    vtk_skip_line(L); /* the rest of the METADATA line */
    while (L->pos < L->size) {
        size_t p = L->pos;
        while (p < L->size && (L->data[p] == ' ' || L->data[p] == '\t' || L->data[p] == '\r'))
            p++;
        int blank = p >= L->size || L->data[p] == '\n';
        vtk_skip_line(L);
        if (blank)
            break;
    }
}

void vtk_skip_metadata(vtk_load *L)
{
    if (vtk_at_keyword(L, "METADATA", 1)) {
        vtk_skip_ws(L);
        vtk_skip_metadata_block(L);
    }
}

/* VTK 5.x escapes spaces and other bytes in names as %XX. */
void vtk_decode_name(const char *in, char *out, size_t n)
{
    size_t k = 0;
    for (size_t i = 0; in[i] && k + 1 < n; i++) {
        unsigned hi, lo;
        if (in[i] == '%' && in[i + 1] && in[i + 2] && sscanf(in + i + 1, "%1x%1x", &hi, &lo) == 2) {
            char c = (char)(hi * 16 + lo);
            out[k++] = c == ' ' ? '_' : c; /* attribute names travel in URLs and PLY headers */
            i += 2;
        } else {
            out[k++] = in[i];
        }
    }
    out[k] = '\0';
    if (!out[0]) /* "%00" and the like: a scene attribute needs a name */
        snprintf(out, n, "attribute");
}

/* ---- values */

/* Fails unless `count` values of type t can still fit in the file: a lying
 * count is caught here, before anything is allocated. An ASCII value takes at
 * least one digit and one separator. */
int vtk_check_room(vtk_load *L, uint64_t count, vtype t, const char *what, uint64_t shown)
{
    uint64_t left = L->size - L->pos;
    int over = L->binary ? count > left / (uint64_t)vtk_type_size[t] : count > (left + 1) / 2;
    if (over)
        return fail_kw(L, LC_ERR_INVALID, "%s %llu exceeds the file size", what, (unsigned long long)shown);
    return 0;
}

uint64_t vtk_get_be(const unsigned char *p, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v = v << 8 | p[i];
    return v;
}

/* Reads one value of type t. `what` names the array in messages. */
int vtk_read_value(vtk_load *L, vtype t, double *out, const char *what)
{
    if (L->binary) {
        int n = vtk_type_size[t];
        if ((size_t)n > L->size - L->pos)
            return fail_here(L, LC_ERR_INVALID, "file ends inside %s", what);
        uint64_t u = vtk_get_be(L->data + L->pos, n);
        L->pos += (size_t)n;
        switch (t) {
        case VT_I8: *out = (int8_t)u; break;
        case VT_I16: *out = (int16_t)u; break;
        case VT_I32: *out = (int32_t)u; break;
        case VT_I64: *out = (double)(int64_t)u; break;
        case VT_F32: {
            uint32_t b = (uint32_t)u;
            float f;
            memcpy(&f, &b, 4);
            *out = f;
            break;
        }
        case VT_F64: memcpy(out, &u, 8); break;
        default: *out = (double)u; break; /* unsigned */
        }
        return 0;
    }
    vtk_skip_ws(L);
    if (L->pos >= L->size)
        return fail_here(L, LC_ERR_INVALID, "file ends inside %s", what);
    const char *p = (const char *)L->data + L->pos, *end = (const char *)L->data + L->size;
    const char *q = lc_io_parse_double(p, end, out);
    if (!q || (q < end && !vtk_is_space((unsigned char)*q))) {
        size_t n = 0;
        while (p + n < end && n < 20 && !vtk_is_space((unsigned char)p[n]))
            n++;
        return fail_here(L, LC_ERR_INVALID, "bad number '%.*s' in %s", (int)n, p, what);
    }
    L->pos = (size_t)(q - (const char *)L->data);
    return 0;
}

/* Reads count values; out (count floats) may be NULL to drop them. Binary
 * arrays that are dropped are jumped over in one step. */
int vtk_read_floats(vtk_load *L, vtype t, uint64_t count, float *out, size_t stride, const char *what)
{
    if (!out && L->binary) {
        L->pos += (size_t)(count * (uint64_t)vtk_type_size[t]); /* vtk_check_room passed */
        return 0;
    }
    for (uint64_t i = 0; i < count; i++) {
        double v;
        int rc = vtk_read_value(L, t, &v, what);
        if (rc)
            return rc;
        if (out)
            out[i * stride] = (float)v;
    }
    return 0;
}

/* A point id: an integer within [0, npoints). */
int vtk_read_index(vtk_load *L, vtype t, uint32_t *out, const char *what)
{
    size_t line = L->line, pos = L->pos;
    double v;
    int rc = vtk_read_value(L, t, &v, what);
    if (rc)
        return rc;
    if (!(v >= 0 && v < L->npoints) || v != floor(v))
        return vtk_fail_at(L, LC_ERR_INVALID, line, pos, "%s: point index %.17g out of range (%u points)", what, v,
                           L->npoints);
    *out = (uint32_t)v;
    return 0;
}

int vtk_scalars_header(vtk_load *L, char *name, vtype *t, uint64_t *ncomp)
{
    char w[MAX_WORD];
    int got, rc;
    *ncomp = 1;
    if ((rc = vtk_need_word(L, name, "SCALARS name")) || (rc = vtk_need_type(L, "SCALARS", t)))
        return rc;
    /* The component count is optional: look at the rest of this line only. */
    size_t save_pos = L->pos, save_line = L->line;
    while (L->pos < L->size && (L->data[L->pos] == ' ' || L->data[L->pos] == '\t' || L->data[L->pos] == '\r'))
        L->pos++;
    if (L->pos < L->size && L->data[L->pos] != '\n') {
        if ((rc = vtk_need_count(L, "SCALARS component count", ncomp)))
            return rc;
    } else {
        L->pos = save_pos, L->line = save_line;
    }
    if ((rc = vtk_end_keyword_line(L)))
        return rc;
    if (vtk_at_keyword(L, "LOOKUP_TABLE", 0) &&
        ((rc = vtk_next_word(L, w, &got)) || (rc = vtk_need_word(L, w, "LOOKUP_TABLE name")) ||
         (rc = vtk_end_keyword_line(L))))
        return rc;
    return 0;
}

int vtk_field_array_header(vtk_load *L, char *name, uint64_t *ncomp, uint64_t *ntuples, vtype *t, int *null)
{
    int rc = vtk_need_word(L, name, "FIELD array name");
    if (rc)
        return rc;
    L->kw_line = L->line, L->kw_pos = L->pos;
    *null = strcasecmp(name, "NULL_ARRAY") == 0;
    if (*null)
        return 0;
    if ((rc = vtk_need_count(L, "FIELD array component count", ncomp)) ||
        (rc = vtk_need_count(L, "FIELD array tuple count", ntuples)) || (rc = vtk_need_type(L, "FIELD array", t)))
        return rc;
    return vtk_end_keyword_line(L);
}
