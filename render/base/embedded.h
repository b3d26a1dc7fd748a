/* Files embedded into the binary at build time by cmake/embed.cmake. */
#ifndef LC_EMBEDDED_H
#define LC_EMBEDDED_H

#include <stddef.h>

typedef struct lc_embedded_file {
    const char *path;          /* relative to the embedded folder, e.g. "p1_importance.glsl" */
    const unsigned char *data; /* NUL-terminated */
    size_t size;               /* without the NUL */
} lc_embedded_file;

/* Looks up path in a {NULL}-terminated table; NULL if absent. */
const lc_embedded_file *lc_embedded_find(const lc_embedded_file *table, const char *path);

#endif
