/* libFuzzer harness for the NetCDF trajectory reader (classic-header check, then libnetcdf from memory)
 * (fuzz_scene_loader.h). */
#include "fuzz_scene_loader.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_scene_loader(lc_load_netcdf_memory, lc_load_netcdf_part, "fuzz.nc", data, size);
}
