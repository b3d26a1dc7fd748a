/* The embedded web client's files as the daemon serves them: lookup by URL,
 * content type and a stable ETag.
 * Threading: pure functions over read-only tables; any thread. */
#ifndef LC_SERVER_WEB_FILES_H
#define LC_SERVER_WEB_FILES_H

#include "embedded.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LC_WEB_ETAG_LEN 24 /* quoted 16 hex digits + NUL */

/* The file for url ("/" is index.html; ".." never matches), its content type
 * and ETag (an FNV-1a hash of the content: the files change only with the
 * binary), or NULL. */
const lc_embedded_file *lc_web_file(const char *url, const char **type, char etag[LC_WEB_ETAG_LEN]);

#ifdef __cplusplus
}
#endif
#endif
