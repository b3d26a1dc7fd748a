/* Lookup in the tables of build-time embedded files. */
#include "embedded.h"

#include <string.h>

const lc_embedded_file *lc_embedded_find(const lc_embedded_file *table, const char *path)
{
    for (; table && table->path; table++)
        if (strcmp(table->path, path) == 0)
            return table;
    return NULL;
}
