/* libFuzzer harness for the NetCDF vector-field reader (fuzz_field_loader.h). */
#include "fuzz_field_loader.h"
#include "nc_field.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_field_one(lc_load_nc_field_memory, "fuzz.nc", data, size);
}
