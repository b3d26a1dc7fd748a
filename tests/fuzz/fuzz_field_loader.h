/* Shared body of the vector-field reader fuzz harnesses: load from memory,
 * check the error contract (an error has a message and no field; a field has
 * a valid grid) and sample at every cell corner and centre of a small grid. */
#ifndef LC_FUZZ_FIELD_LOADER_H
#define LC_FUZZ_FIELD_LOADER_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "field.h"

typedef int (*fuzz_field_loader)(const void *data, size_t size, const char *name, lc_field **out, lc_error *err);

static inline int fuzz_field_one(fuzz_field_loader load, const char *name, const uint8_t *data, size_t size)
{
    lc_field *f = NULL;
    lc_error err = {0};
    int rc = load(data, size, name, &f, &err);
    if (rc != 0) {
        if (f || !err.msg[0]) {
            fprintf(stderr, "fuzz: error %d without a message or with a field\n", rc);
            abort();
        }
        return 0;
    }
    if (!f) {
        fprintf(stderr, "fuzz: success without a field\n");
        abort();
    }
    for (int a = 0; a < 3; a++)
        if (f->dims[a] < 2 || !(f->bounds[a] < f->bounds[a + 3])) {
            fprintf(stderr, "fuzz: axis %d has %u nodes, bounds [%g, %g]\n", a, f->dims[a], f->bounds[a],
                    f->bounds[a + 3]);
            abort();
        }
    if (lc_field_node_count(f) <= 4096)
        for (int i = 0; i <= 8; i++) {
            double p[3], v[3];
            /* Corners are the bounds themselves: lo + (hi - lo) * 1 can round past hi. */
            for (int a = 0; a < 3; a++)
                p[a] = i == 8         ? f->bounds[a] + (f->bounds[a + 3] - f->bounds[a]) * 0.5
                       : (i >> a & 1) ? f->bounds[a + 3]
                                      : f->bounds[a];
            if (!lc_field_sample(f, p, 0.0, v) || !isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2])) {
                fprintf(stderr, "fuzz: sample %d outside or not finite\n", i);
                abort();
            }
        }
    lc_field_destroy(f);
    return 0;
}

#endif
