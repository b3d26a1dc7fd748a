/* libFuzzer harness for the VTK legacy reader: load from memory, and finalize what
 * loads so that the scene code sees every structure the parser can emit. */
#include <stdint.h>
#include <stdlib.h>

#include "loaders.h"
#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lc_log_threshold = LC_LOG_ERROR; /* warnings about skipped arrays would flood the output */
    lc_scene *s = NULL;
    lc_error err = {0};
    int rc = lc_load_vtk_memory(data, size, "fuzz.vtk", &s, &err);
    if (rc != 0) {
        if (s || !err.msg[0]) /* contract: an error leaves no scene and says why */
            abort();
        return 0;
    }
    if (!s)
        abort();
    /* Small budgets keep finalize fast on large fuzzed counts. */
    lc_elements_desc desc = {.line_budget = 64, .patch_count = 8};
    lc_scene_finalize(s, &desc, &err);
    lc_scene_destroy(s);
    return 0;
}
