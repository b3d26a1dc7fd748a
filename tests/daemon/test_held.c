/* What requests hold of the memory budget (held.c) and a surface's curve
 * sizes (surface_memory.c), in process: a reservation grows while the
 * datasets' base and everything held fit the limit, fails beyond it with
 * what is free, shrinks always; kinds add up; a curve's bytes follow the
 * tracer's doubling from 64 vertices. */
#include <stdint.h>

#include "held.h"
#include "lc_test.h"
#include "surface_memory.h"
#include "trace.h"

int main(void)
{
    const uint64_t limit = 1000, base = 100;
    uint64_t a = 0, b = 0, free_bytes = 0;
    CHECK(lc_held_reserve(LC_HELD_SURFACES, &a, 500, limit, base, NULL) == 0 && a == 500, "500 fit beside 100");
    CHECK(lc_held(LC_HELD_SURFACES) == 500 && lc_held_total() == 500, "held 500 (%llu)",
          (unsigned long long)lc_held_total());
    CHECK(lc_held_reserve(LC_HELD_SURFACES, &b, 401, limit, base, &free_bytes) == -1 && b == 0 && free_bytes == 400,
          "401 more do not fit: 400 free (%llu), nothing reserved", (unsigned long long)free_bytes);
    CHECK(lc_held_total() == 500, "a refusal changes nothing");
    lc_held_add(LC_HELD_STREAMLINE_SETS, 100);
    CHECK(lc_held_reserve(LC_HELD_SURFACES, &b, 301, limit, base, &free_bytes) == -1 && free_bytes == 300,
          "a streamline set's 100 count too: 300 free (%llu)", (unsigned long long)free_bytes);
    CHECK(lc_held_reserve(LC_HELD_SURFACES, &b, 300, limit, base, NULL) == 0 && lc_held_total() == 900,
          "300 fit exactly (total %llu)", (unsigned long long)lc_held_total());
    CHECK(lc_held_reserve(LC_HELD_SURFACES, &a, 600, limit, base, &free_bytes) == -1 && free_bytes == 500 && a == 500,
          "growing 500 to 600 with nothing left fails; free to that holder: its own 500 (%llu)",
          (unsigned long long)free_bytes);
    CHECK(lc_held_reserve(LC_HELD_SURFACES, &a, 200, limit, base, NULL) == 0 && a == 200 && lc_held_total() == 600,
          "shrinking always succeeds (total %llu)", (unsigned long long)lc_held_total());
    CHECK(lc_held_reserve(LC_HELD_SURFACES, &a, 5000, 0, base, NULL) == 0 && a == 5000, "no limit: anything fits");
    lc_held_reserve(LC_HELD_SURFACES, &a, 0, 0, 0, NULL);
    lc_held_reserve(LC_HELD_SURFACES, &b, 0, 0, 0, NULL);
    lc_held_add(LC_HELD_STREAMLINE_SETS, -100);
    CHECK(lc_held_total() == 0 && lc_held(LC_HELD_SURFACES) == 0 && lc_held(LC_HELD_STREAMLINE_SETS) == 0,
          "everything given back");

    /* Curves: 8 floats a vertex in arrays doubled from 64, and the curve's slot. */
    const uint64_t slot = sizeof(lc_trace_curve), v = 8 * sizeof(float);
    CHECK(lc_surface_curve_bytes(1) == 64 * v + slot && lc_surface_curve_bytes(64) == 64 * v + slot,
          "up to 64 vertices: one array of 64");
    CHECK(lc_surface_curve_bytes(65) == 128 * v + slot && lc_surface_curve_bytes(1000) == 1024 * v + slot,
          "65 -> 128, 1000 -> 1024");
    return lc_test_finish();
}
