/* libFuzzer harness for the LAMMPS dump reader (fuzz_scene_loader.h). */
#include "fuzz_scene_loader.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_scene_loader(lc_load_dump_memory, lc_load_dump_part, "fuzz.dump", data, size);
}
