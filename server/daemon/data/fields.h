/* The daemon's vector fields: analytic demo fields and gridded files loaded
 * before the port opens (beside the scene datasets of datasets.h), and their
 * JSON descriptions for /api/v1/datasets. */
#ifndef LC_SERVER_FIELDS_H
#define LC_SERVER_FIELDS_H

#include <jansson.h>

#include "field.h"
#include "lc_base.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_MAX_FIELDS 64

/* One loaded field. Immutable once loaded; valid until lc_fields_destroy. */
typedef struct lc_field_entry {
    char source[512]; /* path or demo:NAME it came from */
    lc_field *field;  /* owned; field->name is the unique name */
    double load_seconds;
} lc_field_entry;

typedef struct lc_fields {
    int count;
    lc_field_entry items[LC_MAX_FIELDS];
} lc_fields;

/* Loads a field source (lc_field_is_source) and appends it; a name already
 * taken gets a numeric suffix. Thread: main, at start-up. */
int lc_fields_add(lc_fields *f, const char *source, lc_error *err);
/* Appends every demo field not loaded yet. */
int lc_fields_add_demos(lc_fields *f, lc_error *err);
/* By name; "NAME" also finds "demo:NAME". NULL when unknown. Any thread. */
const lc_field_entry *lc_fields_find(const lc_fields *f, const char *name);
/* Frees every field (not f itself). */
void lc_fields_clear(lc_fields *f);

/* New JSON object describing e: name, source, kind "field", grid {type,
 * dims (null for analytic)}, bounds [[min], [max]], timeDependent, timeRange,
 * magnitudeRange, vectors (the file's array name), bytes, description (demos).
 * Caller json_decref()s. Any thread. */
json_t *lc_field_info(const lc_field_entry *e);
/* A new array of every field's lc_field_info. */
json_t *lc_fields_json(const lc_fields *f);

#ifdef __cplusplus
}
#endif
#endif
