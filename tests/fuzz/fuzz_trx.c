/* libFuzzer harness for the TRX reader (zip archives in memory) (fuzz_scene_loader.h). */
#include "fuzz_scene_loader.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_scene_loader(lc_load_trx_memory, lc_load_trx_part, "fuzz.trx", data, size);
}
