/* libFuzzer harness for the point-table (CSV/TSV/XYZ) reader (fuzz_scene_loader.h). */
#include "fuzz_scene_loader.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_scene_loader(lc_load_csv_memory, lc_load_csv_part, "fuzz.csv", data, size);
}
