/* lc_scene_shard: the shards of 1..4 ranks partition the primitives of lines,
 * points and surfaces, keep every vertex's element blend and the whole
 * scene's bounds, attribute statistics and element numbering. */
#include <string.h>

#include "demo.h"
#include "lc_test.h"
#include "lod.h"
#include "scene_shard.h"

/* Sum over the shard's primitives of a position checksum of their vertices,
 * so that the union of the shards can be compared with the whole. */
static double primitive_checksum(const lc_scene *s)
{
    double sum = 0;
    if (s->type == LC_PRIM_TRIANGLES) {
        for (uint32_t t = 0; t < 3 * s->triangle_count; t++)
            sum += s->positions[3 * s->triangles[t]] + 2.0 * s->positions[3 * s->triangles[t] + 1];
    } else {
        for (uint32_t v = 0; v < s->vertex_count; v++)
            sum += s->positions[3 * v] + 2.0 * s->positions[3 * v + 1];
    }
    return sum;
}

static uint64_t element_checksum(const lc_scene *s)
{
    uint64_t sum = 0;
    for (uint32_t v = 0; v < s->vertex_count; v++)
        sum +=
            s->elements.vertex_elements[4 * v + 3] * 2654435761u + (uint32_t)(1e6 * s->elements.vertex_weights[4 * v]);
    return sum;
}

/* Line shards simplify at the whole scene's thresholds: every level of
 * detail of every shard has the error of the whole's level of that number,
 * so a frame picks the same simplification on every rank. */
static void check_levels(const char *spec, uint64_t count)
{
    lc_error err = {0};
    lc_scene *full = NULL;
    lc_demo_desc desc = {.count = count};
    CHECK(lc_demo_create(spec, &desc, &full, &err) == 0, "%s: demo (%s)", spec, err.msg);
    lc_lod whole;
    if (!full || lc_lod_plan(full, &whole, &err) != 0) {
        lc_scene_destroy(full);
        return;
    }
    for (int size = 2; size <= 4; size++)
        for (int rank = 0; rank < size; rank++) {
            lc_scene *s = NULL;
            lc_lod part;
            if (lc_scene_shard(full, rank, size, &s, &err) != 0 || lc_lod_plan(s, &part, &err) != 0) {
                CHECK(0, "%s: shard %d/%d levels (%s)", spec, rank, size, err.msg);
                lc_scene_destroy(s);
                continue;
            }
            int same = part.count == whole.count;
            for (int i = 0; same && i < whole.count; i++)
                same = part.levels[i].error == whole.levels[i].error;
            CHECK(same, "%s: shard %d/%d has %d levels (first coarse error %g), the whole %d (%g)", spec, rank, size,
                  part.count, part.count > 1 ? part.levels[1].error : 0.0, whole.count,
                  whole.count > 1 ? whole.levels[1].error : 0.0);
            lc_lod_free(&part);
            lc_scene_destroy(s);
        }
    lc_lod_free(&whole);
    lc_scene_destroy(full);
}

static void check_demo(const char *name)
{
    lc_error err = {0};
    lc_scene *full = NULL;
    /* Points split at multiples of 1024 (the compact layout's position chunk): 5000 give every rank some. */
    lc_demo_desc desc = {.count = strcmp(name, "surface") == 0 ? 40 : strcmp(name, "points") == 0 ? 5000 : 60};
    CHECK(lc_demo_create(name, &desc, &full, &err) == 0, "%s: demo (%s)", name, err.msg);
    if (!full)
        return;
    double whole_sum = primitive_checksum(full);
    for (int size = 1; size <= 4; size++) {
        double sum = 0;
        uint64_t prims = 0, esum = 0;
        for (int rank = 0; rank < size; rank++) {
            lc_scene *s = NULL;
            CHECK(lc_scene_shard(full, rank, size, &s, &err) == 0, "%s: shard %d/%d (%s)", name, rank, size, err.msg);
            if (!s)
                continue;
            sum += primitive_checksum(s);
            prims += lc_scene_primitive_count(s);
            if (full->type != LC_PRIM_TRIANGLES)
                esum += element_checksum(s);
            CHECK(memcmp(s->bounds, full->bounds, sizeof s->bounds) == 0, "%s: shard keeps the bounds", name);
            CHECK(s->elements.count == full->elements.count &&
                      s->elements.adjacency_count == full->elements.adjacency_count,
                  "%s: shard keeps the element numbering", name);
            CHECK(s->attribute_count == full->attribute_count, "%s: shard keeps the attributes", name);
            for (int a = 0; a < s->attribute_count; a++)
                CHECK(s->attributes[a].p02 == full->attributes[a].p02 &&
                          s->attributes[a].max == full->attributes[a].max,
                      "%s: attribute %s keeps the whole range and percentiles", name, s->attributes[a].name);
            CHECK(size == 1 || lc_scene_bytes(s) < lc_scene_bytes(full), "%s: a shard of %d is smaller", name, size);
            if (full->type == LC_PRIM_POINTS && rank + 1 < size)
                CHECK(s->vertex_count % 1024 == 0, "points: shard %d/%d holds %u points, not whole chunks", rank, size,
                      s->vertex_count);
            lc_scene_destroy(s);
        }
        CHECK(prims == lc_scene_primitive_count(full), "%s: %d shards hold %llu of %llu primitives", name, size,
              (unsigned long long)prims, (unsigned long long)lc_scene_primitive_count(full));
        CHECK_NEAR(sum, whole_sum, 1e-6 * (1 + (whole_sum < 0 ? -whole_sum : whole_sum)), "primitive checksum");
        if (full->type != LC_PRIM_TRIANGLES)
            CHECK(esum == element_checksum(full), "%s: %d shards keep every vertex's elements", name, size);
    }
    lc_scene *bad = NULL;
    CHECK(lc_scene_shard(full, 3, 3, &bad, &err) == LC_ERR_INVALID && !bad, "%s: rank 3 of 3 is refused", name);
    lc_scene_destroy(full);
}

int main(void)
{
    check_demo("tornado");
    check_demo("points");
    check_demo("surface");
    check_levels("tornado", 300);
    check_levels("abc", 200);
    return lc_test_finish();
}
