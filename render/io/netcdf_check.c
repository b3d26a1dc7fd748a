/* Bounded structural check of a NetCDF classic header (CDF-1, CDF-2, CDF-5)
 * before libnetcdf sees the bytes: libnetcdf 4.9 crashes on some malformed
 * headers (found by this project's mutation test), so every count, name,
 * type, dimension id and data offset is checked against the file first. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "io_util.h"
#include "netcdf_check.h"

#define TAG_DIMENSION 0x0A
#define TAG_VARIABLE 0x0B
#define TAG_ATTRIBUTE 0x0C
#define MAX_ITEMS 65536
#define MAX_NAME 256

typedef struct cursor {
    const unsigned char *p;
    size_t size, pos;
    int wide; /* CDF-5: 8-byte counts */
    const char *file;
    lc_error *err;
} cursor;

static int bad(cursor *c, const char *what)
{
    return lc_err(c->err, LC_ERR_INVALID, "%.80s: byte offset %zu: malformed NetCDF header (%s)", c->file, c->pos,
                  what);
}

static int take(cursor *c, size_t n, uint64_t *out)
{
    if (c->size - c->pos < n)
        return bad(c, "ends early");
    *out = n == 8 ? lc_io_get_u64(c->p + c->pos, 1) : lc_io_get_u32(c->p + c->pos, 1);
    c->pos += n;
    return 0;
}

static int count(cursor *c, uint64_t *out) { return take(c, c->wide ? 8 : 4, out); }

/* name = nelems chars, padded to 4; printable UTF-8 bytes, no NUL or '/'. */
static int name(cursor *c, char *out)
{
    uint64_t n;
    if (count(c, &n))
        return LC_ERR_INVALID;
    if (n == 0 || n > MAX_NAME || n > c->size - c->pos)
        return bad(c, "name length");
    for (uint64_t i = 0; i < n; i++) {
        unsigned char ch = c->p[c->pos + i];
        if (ch < 0x20 || ch == 0x7f || ch == '/')
            return bad(c, "name character");
    }
    memcpy(out, c->p + c->pos, (size_t)n);
    out[n] = '\0';
    uint64_t padded = (n + 3) & ~(uint64_t)3;
    if (padded > c->size - c->pos)
        return bad(c, "name padding");
    c->pos += (size_t)padded;
    return 0;
}

static int type_size(cursor *c, uint64_t type)
{
    static const int sizes[12] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};
    if (type < 1 || type > (c->wide ? 11u : 6u))
        return LC_ERR_INVALID;
    return sizes[type];
}

/* tag + nelems, or ABSENT (two zeros). */
static int list_head(cursor *c, uint64_t tag, uint64_t *n)
{
    uint64_t t;
    if (take(c, 4, &t) || count(c, n))
        return LC_ERR_INVALID;
    if (t == 0 && *n == 0)
        return 0;
    if (t != tag)
        return bad(c, "list tag");
    if (*n > MAX_ITEMS)
        return bad(c, "too many items");
    return 0;
}

static int attributes(cursor *c)
{
    uint64_t n;
    if (list_head(c, TAG_ATTRIBUTE, &n))
        return LC_ERR_INVALID;
    for (uint64_t i = 0; i < n; i++) {
        char nm[MAX_NAME + 1];
        uint64_t type, len;
        if (name(c, nm) || take(c, 4, &type) || count(c, &len))
            return LC_ERR_INVALID;
        int ts = type_size(c, type);
        if (ts <= 0)
            return bad(c, "attribute type");
        if (len > (c->size - c->pos) / (uint64_t)ts)
            return bad(c, "attribute length");
        uint64_t bytes = (len * (uint64_t)ts + 3) & ~(uint64_t)3;
        if (bytes > c->size - c->pos)
            return bad(c, "attribute values");
        c->pos += (size_t)bytes;
    }
    return 0;
}

int lc_netcdf_check_classic(const void *data, size_t size, const char *file, lc_error *err)
{
    cursor c = {.p = data, .size = size, .file = file, .err = err};
    if (size < 4 || memcmp(data, "CDF", 3) != 0)
        return 0; /* not classic: libnetcdf decides (NetCDF-4/HDF5) */
    int version = c.p[3];
    if (version != 1 && version != 2 && version != 5)
        return bad(&c, "version");
    c.wide = version == 5;
    c.pos = 4;
    uint64_t numrecs, ndims, nvars;
    if (take(&c, c.wide ? 8 : 4, &numrecs) || list_head(&c, TAG_DIMENSION, &ndims))
        return LC_ERR_INVALID;
    char names[64][MAX_NAME + 1];
    int record_dims = 0;
    for (uint64_t i = 0; i < ndims; i++) {
        uint64_t len;
        char nm[MAX_NAME + 1];
        if (name(&c, nm) || count(&c, &len))
            return LC_ERR_INVALID;
        record_dims += len == 0;
        for (uint64_t j = 0; j < i && j < 64; j++)
            if (strcmp(names[j], nm) == 0)
                return bad(&c, "duplicate dimension name");
        if (i < 64)
            memcpy(names[i], nm, sizeof nm);
    }
    if (record_dims > 1)
        return bad(&c, "more than one unlimited dimension");
    if (attributes(&c) || list_head(&c, TAG_VARIABLE, &nvars))
        return LC_ERR_INVALID;
    for (uint64_t v = 0; v < nvars; v++) {
        char nm[MAX_NAME + 1];
        uint64_t rank, type, vsize, begin;
        if (name(&c, nm) || count(&c, &rank))
            return LC_ERR_INVALID;
        if (rank > 1024)
            return bad(&c, "variable rank");
        for (uint64_t d = 0; d < rank; d++) {
            uint64_t id;
            if (count(&c, &id))
                return LC_ERR_INVALID;
            if (id >= ndims)
                return bad(&c, "dimension id");
        }
        if (attributes(&c) || take(&c, 4, &type))
            return LC_ERR_INVALID;
        if (type_size(&c, type) <= 0)
            return bad(&c, "variable type");
        if (count(&c, &vsize) || take(&c, version == 1 ? 4 : 8, &begin))
            return LC_ERR_INVALID;
        if (begin > size)
            return bad(&c, "variable data offset beyond the file");
    }
    return 0;
}
