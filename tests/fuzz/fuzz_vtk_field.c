/* libFuzzer harness for the VTK legacy vector-field reader (fuzz_field_loader.h). */
#include "fuzz_field_loader.h"
#include "vtk_field.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_field_one(lc_load_vtk_field_memory, "fuzz.vtk", data, size);
}
