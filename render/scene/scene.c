/* Scene core: ownership of the CPU arrays and the named attributes. */
#include "scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

lc_scene *lc_scene_create(const char *name, lc_prim_type type)
{
    lc_scene *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    if (name)
        snprintf(s->name, sizeof s->name, "%s", name);
    s->type = type;
    return s;
}

/* The cached levels of detail (scene.h lod), through the owner's free. */
static void free_lod(lc_scene *s)
{
    if (s->lod && s->lod_free)
        s->lod_free(s->lod);
    s->lod = NULL;
    s->lod_free = NULL;
}

static void free_attributes(lc_scene *s)
{
    for (int i = 0; i < s->attribute_count; i++)
        free(s->attributes[i].values);
    memset(s->attributes, 0, sizeof s->attributes);
    s->attribute_count = 0;
}

void lc_scene_destroy(lc_scene *s)
{
    if (!s)
        return;
    free(s->positions);
    free(s->rgb);
    free(s->normals);
    free(s->tangents);
    free(s->line_offsets);
    free(s->triangles);
    free_attributes(s);
    lc_elements_free(&s->elements);
    free_lod(s);
    free(s);
}

int lc_scene_alloc_vertices(lc_scene *s, uint32_t n, int with_rgb, lc_error *err)
{
    if (!s)
        return lc_err(err, LC_ERR_INVALID, "scene: NULL scene");
    if (n > LC_MAX_VERTICES)
        return lc_err(err, LC_ERR_LIMIT, "%s: %u vertices exceed the limit of %u", s->name, n, LC_MAX_VERTICES);
    /* Everything per-vertex belongs to the old vertex count; attributes of a
     * different length would be read out of bounds, so they go too. */
    free(s->positions);
    free(s->rgb);
    free(s->normals);
    free(s->tangents);
    s->positions = s->rgb = s->normals = s->tangents = NULL;
    free_attributes(s);
    lc_elements_free(&s->elements);
    free_lod(s);
    s->finalized = 0;
    s->vertex_count = 0;
    size_t count = (size_t)(n ? n : 1) * 3;
    s->positions = malloc(count * sizeof(float));
    if (with_rgb)
        s->rgb = malloc(count * sizeof(float));
    if (!s->positions || (with_rgb && !s->rgb)) {
        free(s->positions);
        free(s->rgb);
        s->positions = s->rgb = NULL;
        return lc_err(err, LC_ERR_NOMEM, "%s: cannot allocate %u vertices", s->name, n);
    }
    s->vertex_count = n;
    return LC_OK;
}

int lc_scene_find_attribute(const lc_scene *s, const char *name)
{
    if (!s || !name)
        return -1;
    for (int i = 0; i < s->attribute_count; i++)
        if (strcmp(s->attributes[i].name, name) == 0)
            return i;
    return -1;
}

int lc_scene_time_attribute(const lc_scene *s, const char *name)
{
    if (name && name[0])
        return lc_scene_find_attribute(s, name);
    static const char *const usual[] = {"time", "t", "frame", "timestep"};
    for (size_t i = 0; i < sizeof usual / sizeof usual[0]; i++) {
        int a = lc_scene_find_attribute(s, usual[i]);
        if (a >= 0)
            return a;
    }
    return -1;
}

void lc_scene_unique_attribute_name(const lc_scene *s, const char *want, char out[LC_NAME_LEN])
{
    snprintf(out, LC_NAME_LEN, "%s", want && want[0] ? want : "attribute");
    char base[LC_NAME_LEN];
    memcpy(base, out, LC_NAME_LEN);
    /* At most LC_MAX_ATTRIBUTES names are taken, so one of the first
     * LC_MAX_ATTRIBUTES + 1 suffixes is free. */
    for (int k = 2; lc_scene_find_attribute(s, out) >= 0 && k <= LC_MAX_ATTRIBUTES + 2; k++) {
        char suffix[16];
        int n = snprintf(suffix, sizeof suffix, "_%d", k);
        int keep = (int)strlen(base);
        if (keep > LC_NAME_LEN - 1 - n)
            keep = LC_NAME_LEN - 1 - n;
        snprintf(out, LC_NAME_LEN, "%.*s%s", keep, base, suffix);
    }
}

/* Ownership of values passes in every case: on failure they are freed here, so
 * a caller's error path never has to (and must not) free them. */
int lc_scene_add_attribute(lc_scene *s, const char *name, float *values, lc_error *err)
{
    if (!s) {
        free(values);
        return lc_err(err, LC_ERR_INVALID, "scene: NULL scene");
    }
    if (!name || !name[0]) {
        free(values);
        return lc_err(err, LC_ERR_INVALID, "%s: attribute without a name", s->name);
    }
    if (strlen(name) >= LC_NAME_LEN) {
        free(values);
        return lc_err(err, LC_ERR_INVALID, "%s: attribute name '%.32s...' longer than %d bytes", s->name, name,
                      LC_NAME_LEN - 1);
    }
    if (!values)
        return lc_err(err, LC_ERR_INVALID, "%s: attribute '%s' has no values", s->name, name);
    int i = lc_scene_find_attribute(s, name);
    if (i >= 0) {
        if (s->attributes[i].values != values)
            free(s->attributes[i].values);
    } else {
        if (s->attribute_count >= LC_MAX_ATTRIBUTES) {
            free(values);
            return lc_err(err, LC_ERR_LIMIT, "%s: more than %d attributes (at '%s')", s->name, LC_MAX_ATTRIBUTES, name);
        }
        i = s->attribute_count++;
        snprintf(s->attributes[i].name, sizeof s->attributes[i].name, "%s", name);
    }
    s->attributes[i].values = values;
    s->attributes[i].categorical = false; /* lc_scene_finalize marks the file's own */
    s->attributes[i].min = 0.0f;
    s->attributes[i].max = 0.0f;
    return i;
}

const char *lc_prim_type_name(lc_prim_type t)
{
    switch (t) {
    case LC_PRIM_POINTS: return "points";
    case LC_PRIM_LINES: return "lines";
    case LC_PRIM_TRIANGLES: return "triangles";
    }
    return "unknown";
}

uint64_t lc_scene_primitive_count(const lc_scene *s)
{
    if (!s)
        return 0;
    switch (s->type) {
    case LC_PRIM_POINTS: return s->vertex_count;
    case LC_PRIM_LINES: {
        if (!s->line_offsets)
            return 0;
        uint64_t n = 0;
        for (uint32_t i = 0; i < s->line_count; i++) {
            uint32_t a = s->line_offsets[i], b = s->line_offsets[i + 1];
            if (b > a)
                n += b - a - 1;
        }
        return n;
    }
    case LC_PRIM_TRIANGLES: return s->triangle_count;
    }
    return 0;
}

void lc_scene_memory_of(const lc_scene *s, lc_scene_memory *out)
{
    memset(out, 0, sizeof *out);
    if (!s)
        return;
    size_t v = s->vertex_count, f = sizeof(float);
    out->positions = s->positions ? 3 * v * f : 0;
    out->colors = s->rgb ? 3 * v * f : 0;
    out->frames = 3 * v * f * (!!s->normals + !!s->tangents);
    out->attributes = 0;
    for (int i = 0; i < s->attribute_count; i++)
        out->attributes += s->attributes[i].values ? v * f : 0;
    if (s->line_offsets)
        out->topology += ((size_t)s->line_count + 1) * sizeof(uint32_t);
    if (s->triangles)
        out->topology += 3 * (size_t)s->triangle_count * sizeof(uint32_t);
    const lc_elements *e = &s->elements;
    if (e->vertex_elements)
        out->elements += 4 * v * (sizeof(uint32_t) + sizeof(float));
    if (e->adjacency_offsets)
        out->elements += ((size_t)e->count + 1 + e->adjacency_count) * sizeof(uint32_t);
    out->total = out->positions + out->colors + out->frames + out->topology + out->attributes + out->elements;
}

size_t lc_scene_bytes(const lc_scene *s)
{
    lc_scene_memory m;
    lc_scene_memory_of(s, &m);
    return m.total;
}

void lc_scene_release_vertex_arrays(lc_scene *s)
{
    if (!s || s->released)
        return;
    s->released_rgb = s->rgb != NULL;
    free(s->positions);
    free(s->rgb);
    free(s->normals);
    free(s->tangents);
    free(s->triangles);
    s->positions = s->rgb = s->normals = s->tangents = NULL;
    s->triangles = NULL;
    for (int i = 0; i < s->attribute_count; i++) {
        free(s->attributes[i].values);
        s->attributes[i].values = NULL;
    }
    lc_elements *e = &s->elements;
    free(e->vertex_elements);
    free(e->vertex_weights);
    free(e->adjacency_offsets);
    free(e->adjacency);
    e->vertex_elements = NULL, e->vertex_weights = NULL;
    e->adjacency_offsets = e->adjacency = NULL;
    free_lod(s);
    s->released = 1;
}

int lc_scene_has_rgb(const lc_scene *s) { return s->rgb != NULL || s->released_rgb; }
