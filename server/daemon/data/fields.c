/* The daemon's vector fields: loading, lookup and JSON descriptions (fields.h). */
#include "fields.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vtk_field.h"

#define MOD "datasets"

static int taken(const lc_fields *f, const char *name)
{
    for (int i = 0; i < f->count; i++)
        if (strcmp(f->items[i].field->name, name) == 0)
            return 1;
    return 0;
}

int lc_fields_add(lc_fields *f, const char *source, lc_error *err)
{
    if (f->count >= LC_MAX_FIELDS)
        return lc_err(err, LC_ERR_LIMIT, "%s: more than %d fields", source, LC_MAX_FIELDS);
    lc_field_entry *e = &f->items[f->count];
    memset(e, 0, sizeof *e);
    snprintf(e->source, sizeof e->source, "%s", source);
    double t0 = lc_now();
    int rc = lc_field_open(source, &e->field, err);
    if (rc)
        return rc;
    e->load_seconds = lc_now() - t0;
    char base[128];
    snprintf(base, sizeof base, "%s", e->field->name);
    if (strncmp(source, "demo:", 5) != 0 && strncmp(base, "demo:", 5) == 0)
        base[4] = '_'; /* names starting with demo: are the demos' */
    for (int k = 2; taken(f, base); k++)
        snprintf(base, sizeof base, "%.100s-%d", e->field->name, k);
    snprintf(e->field->name, sizeof e->field->name, "%s", base);
    const lc_field *fl = e->field;
    LC_INFO(MOD, "loaded field %s: %s, |v| in [%g, %g] in %.2f s", fl->name, lc_field_kind_name(fl->kind), fl->mag_min,
            fl->mag_max, e->load_seconds);
    f->count++;
    return 0;
}

int lc_fields_add_demos(lc_fields *f, lc_error *err)
{
    for (const char *const *n = lc_field_demo_names(); *n; n++) {
        char src[128];
        snprintf(src, sizeof src, "demo:%s", *n);
        if (lc_fields_find(f, src))
            continue;
        int rc = lc_fields_add(f, src, err);
        if (rc)
            return rc;
    }
    return 0;
}

const lc_field_entry *lc_fields_find(const lc_fields *f, const char *name)
{
    if (!f || !name || !name[0])
        return NULL;
    for (int i = 0; i < f->count; i++)
        if (strcmp(f->items[i].field->name, name) == 0)
            return &f->items[i];
    for (int i = 0; i < f->count; i++)
        if (strncmp(f->items[i].field->name, "demo:", 5) == 0 && strcmp(f->items[i].field->name + 5, name) == 0)
            return &f->items[i];
    return NULL;
}

void lc_fields_clear(lc_fields *f)
{
    for (int i = 0; f && i < f->count; i++)
        lc_field_destroy(f->items[i].field);
    if (f)
        f->count = 0;
}

static json_t *pair(double a, double b) { return json_pack("[f, f]", isfinite(a) ? a : 0.0, isfinite(b) ? b : 0.0); }

json_t *lc_field_info(const lc_field_entry *e)
{
    const lc_field *f = e->field;
    json_t *o = json_object();
    json_object_set_new(o, "name", json_string(f->name));
    json_object_set_new(o, "source", json_string(e->source));
    json_object_set_new(o, "kind", json_string("field"));
    const char *desc = strncmp(e->source, "demo:", 5) == 0 ? lc_field_demo_description(e->source + 5) : NULL;
    if (desc)
        json_object_set_new(o, "description", json_string(desc));
    json_t *grid = json_object();
    json_object_set_new(grid, "type", json_string(lc_field_kind_name(f->kind)));
    json_object_set_new(grid, "dims",
                        f->kind == LC_FIELD_ANALYTIC ? json_null()
                                                     : json_pack("[I, I, I]", (json_int_t)f->dims[0],
                                                                 (json_int_t)f->dims[1], (json_int_t)f->dims[2]));
    json_object_set_new(o, "grid", grid);
    json_t *b = json_array(); /* [[xmin, ymin, zmin], [xmax, ymax, zmax]] as for scenes */
    for (int k = 0; k < 2; k++)
        json_array_append_new(b, json_pack("[f, f, f]", f->bounds[3 * k], f->bounds[3 * k + 1], f->bounds[3 * k + 2]));
    json_object_set_new(o, "bounds", b);
    json_object_set_new(o, "timeDependent", json_boolean(f->time_dependent));
    json_object_set_new(o, "timeRange", pair(f->t0, f->t1));
    json_object_set_new(o, "magnitudeRange", pair(f->mag_min, f->mag_max));
    if (f->vectors_name[0])
        json_object_set_new(o, "vectors", json_string(f->vectors_name));
    json_object_set_new(o, "bytes", json_integer((json_int_t)lc_field_bytes(f)));
    return o;
}

json_t *lc_fields_json(const lc_fields *f)
{
    json_t *a = json_array();
    for (int i = 0; f && i < f->count; i++)
        json_array_append_new(a, lc_field_info(&f->items[i]));
    return a;
}
