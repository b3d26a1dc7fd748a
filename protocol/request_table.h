/* The render request's field table (request_table.c) and its types: what
 * request.c needs to parse, check, emit and print any field. */
#ifndef LC_PROTOCOL_REQUEST_TABLE_H
#define LC_PROTOCOL_REQUEST_TABLE_H

#include "request_types.h"

#include <stddef.h>

typedef enum {
    T_INT,     /* int */
    T_NUM,     /* double */
    T_BOOL,    /* bool */
    T_STR,     /* char[size], any text shorter than size */
    T_ENUM,    /* int-sized enum, from a name table */
    T_NAME,    /* char[size], one of a name table (colormap) */
    T_VEC3,    /* double[3], finite */
    T_COLOR,   /* double[3] in [0,1] */
    T_RANGE,   /* double[2], finite; sets a bool */
    T_TERMS,   /* lc_importance_map's terms, an array of objects (request_lists.c) */
    T_FILTERS, /* lc_render_params' filters, an array of objects (request_lists.c) */
    T_CURVE,   /* lc_curve, an array of [x, y] points (request_lists.c) */
    T_RANGES,  /* lc_color_map's fixed ranges, an array of [lo, hi] (request_lists.c) */
    T_LAYERS,  /* lc_request's layers, an array of objects (request_layers.c) */
    T_SEED,    /* lc_surface_request's seed, an array of [x, y, z] points (request_lists.c) */
} ftype;

enum {
    LO_OPEN = 1,     /* lo excluded */
    HI_OPEN = 2,     /* hi excluded */
    SIZE_LIMIT = 4,  /* lo/hi come from the limits */
    CHECK_ONLY = 8,  /* validated, not stored (version) */
    ALWAYS_EMIT = 16 /* the flag records that the field was given; emitted either way */
};

typedef struct enum_name {
    const char *name;
    int value;
} enum_name;

typedef struct field {
    const char *section; /* NULL = top level */
    const char *name;    /* JSON key */
    const char *alias;   /* flat query-parameter name, NULL = dotted path only */
    ftype type;
    double lo, hi;
    int bounds;
    size_t offset; /* into lc_request */
    size_t size;   /* T_STR/T_NAME buffer size */
    long flag;     /* offset of a bool set when the field is given, -1 = none */
    const enum_name *names;
} field;

#define BIG 1e300 /* "any finite number"; reals from jansson are finite anyway */

extern const field lc_request_fields[];
extern const size_t lc_request_nfields;
extern const char *const lc_request_sections[]; /* the request's sections, in emission order */
extern const size_t lc_request_nsections;
extern const enum_name lc_request_method_names[];

#endif
