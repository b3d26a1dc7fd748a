/* The protocol's cost of one session update, two ways side by side in one run: the field rules run twice
 * (checked on a scratch request as a message arrives, then lc_proto_apply_request on a copy of the session's
 * request, as before request_patch.c) against a typed patch (lc_proto_patch_parse once, then lc_proto_patch_apply:
 * a copy of the given fields and the cross-field checks). Best of 5 rounds of N updates each.
 * Usage: update_bench [N] (default 20000). */
#include "request.h"
#include "request_patch.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + t.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    const char *updates[] = {
        "{\"camera\":{\"position\":[1,2,5],\"focalPoint\":[0,0,0],\"viewUp\":[0,1,0]}}",
        "{\"params\":{\"q\":3,\"bands\":7},\"color\":{\"colormap\":\"inferno\"}}",
        "{\"layers\":[{\"dataset\":\"a\",\"color\":{\"attribute\":\"v\"}},{\"dataset\":\"b\",\"filter\":[{"
        "\"attribute\":\"x\",\"gt\":1}]}]}",
    };
    const char *names[] = {"camera", "params", "layers (2)"};
    lc_request *base = malloc(sizeof *base), *work = malloc(sizeof *work), *scratch = malloc(sizeof *scratch);
    lc_request_default(work), lc_request_default(scratch);
    const char *b = "{\"layers\":[{\"dataset\":\"a\"},{\"dataset\":\"b\"}]}";
    lc_proto_error err;
    if (lc_proto_parse_request(b, strlen(b), NULL, base, &err))
        return 1;
    int n = argc > 1 ? atoi(argv[1]) : 20000;
    if (n < 1)
        n = 1;
    printf("| update | old: check on scratch + apply (us) | patch: parse + apply (us) | ratio |\n|---|---|---|---|\n");
    for (int u = 0; u < 3; u++) {
        json_error_t je;
        json_t *j = json_loads(updates[u], 0, &je);
        double best_old = 1e9, best_new = 1e9;
        for (int rep = 0; rep < 5; rep++) {
            double t0 = now();
            for (int i = 0; i < n; i++) {
                lc_request_release(scratch); /* an update of layers left a snapshot */
                lc_request_default(scratch);
                if (lc_proto_check_fields(j, NULL, scratch, &err))
                    return 2;
                lc_request_assign(work, base);
                if (lc_proto_apply_request(j, NULL, work, &err))
                    return 3;
            }
            double t1 = now();
            for (int i = 0; i < n; i++) {
                lc_request_patch *p;
                if (lc_proto_patch_parse(j, NULL, &p, &err))
                    return 4;
                lc_request_assign(work, base);
                if (lc_proto_patch_apply(p, NULL, work, &err))
                    return 5;
                lc_proto_patch_free(p);
            }
            double t2 = now();
            if (t1 - t0 < best_old)
                best_old = t1 - t0;
            if (t2 - t1 < best_new)
                best_new = t2 - t1;
        }
        printf("| %s | %.2f | %.2f | %.2f |\n", names[u], best_old / n * 1e6, best_new / n * 1e6, best_new / best_old);
        json_decref(j);
    }
    printf("sizeof(lc_request) = %zu bytes\n", sizeof(lc_request));
    lc_request_release(work), lc_request_release(base);
    return 0;
}
