/* Lookup of the embedded web client's files (web_files.h). */
#include "web_files.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

extern const lc_embedded_file lc_web_files[];

static const char *content_type(const char *path)
{
    static const struct {
        const char *ext, *type;
    } types[] = {{".html", "text/html; charset=utf-8"},
                 {".js", "text/javascript; charset=utf-8"},
                 {".mjs", "text/javascript; charset=utf-8"},
                 {".css", "text/css; charset=utf-8"},
                 {".svg", "image/svg+xml"},
                 {".png", "image/png"},
                 {".json", "application/json"},
                 {".ico", "image/x-icon"},
                 {".txt", "text/plain; charset=utf-8"}};
    const char *dot = strrchr(path, '.');
    for (size_t i = 0; dot && i < sizeof types / sizeof types[0]; i++)
        if (strcmp(dot, types[i].ext) == 0)
            return types[i].type;
    return "application/octet-stream";
}

const lc_embedded_file *lc_web_file(const char *url, const char **type, char etag[LC_WEB_ETAG_LEN])
{
    const char *path = (strcmp(url, "/") == 0) ? "index.html" : url + 1;
    const lc_embedded_file *f = strstr(path, "..") ? NULL : lc_embedded_find(lc_web_files, path);
    if (!f)
        return NULL;
    /* A stable validator; no-cache (set by the caller) makes browsers
     * revalidate after an upgrade. */
    uint64_t h = 1469598103934665603ULL;
    for (size_t i = 0; i < f->size; i++)
        h = (h ^ f->data[i]) * 1099511628211ULL;
    snprintf(etag, LC_WEB_ETAG_LEN, "\"%016llx\"", (unsigned long long)h);
    *type = content_type(path);
    return f;
}
