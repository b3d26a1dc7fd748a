/* Errors, status codes and leveled logging shared by every Lucent module. */
#ifndef LC_BASE_H
#define LC_BASE_H

#include <stdarg.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes: 0 = ok, negative = error. The code says what kind of failure it
 * was so that upper layers can map it (the server maps to HTTP statuses). */
enum {
    LC_OK = 0,
    LC_ERR_INVALID = -1,     /* bad argument or malformed input */
    LC_ERR_IO = -2,          /* file could not be opened / read / written */
    LC_ERR_NOMEM = -3,       /* allocation failed */
    LC_ERR_LIMIT = -4,       /* input exceeds a configured cap */
    LC_ERR_GL = -5,          /* EGL / OpenGL failure */
    LC_ERR_NOT_FOUND = -6,   /* unknown dataset, attribute, name */
    LC_ERR_UNSUPPORTED = -7, /* feature not available here */
    LC_ERR_INTERNAL = -8,
    LC_ERR_CANCELLED = -9, /* stopped by lc_cancel (a signal during start-up), or a frame stopped at a yield point */
    LC_ERR_BUDGET = -10    /* the work exceeded the budget granted to the request (lc_work.h) */
};

#define LC_ERROR_MSG_LEN 256
#define LC_ERROR_FIELD_LEN 64

/* Filled by a failing call; msg names the input and the reason. field is the
 * request field at fault in the wire protocol's dotted form
 * ("importance.attribute"), or "" when the error is not about one: upper
 * layers report it as is and never parse msg for it. */
typedef struct lc_error {
    int code;
    char field[LC_ERROR_FIELD_LEN];
    char msg[LC_ERROR_MSG_LEN];
} lc_error;

/* Sets err (may be NULL; field becomes "") and returns code, so callers can
 * write `return lc_err(err, LC_ERR_IO, "%s: cannot open", path);`. */
int lc_err(lc_error *err, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* Like lc_err for an error about a request field: sets field and a message
 * that starts with it ("color.attribute: demo:abc has no attribute \"x\""). */
int lc_err_field(lc_error *err, int code, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Prefixes err->msg with "prefix: " (e.g. a file name), keeping the code. */
void lc_err_prefix(lc_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Short stable name of a status code ("invalid", "io", ...). */
const char *lc_status_name(int code);

/* Logging. One line per call: "2026-11-21T04:00:00.123Z INFO  [render] text".
 * The level check happens before the arguments are evaluated. Thread-safe. */
typedef enum { LC_LOG_ERROR = 0, LC_LOG_WARN = 1, LC_LOG_INFO = 2, LC_LOG_DEBUG = 3 } lc_log_level;

extern int lc_log_threshold; /* messages with level <= threshold are printed; default INFO */
void lc_log_set_level(lc_log_level level);
/* Parses "error|warn|info|debug"; returns -1 when unknown. */
int lc_log_parse_level(const char *name);
void lc_log_write(lc_log_level level, const char *module, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#define LC_LOG(level, module, ...)                                                                                     \
    do {                                                                                                               \
        if ((int)(level) <= lc_log_threshold)                                                                          \
            lc_log_write((level), (module), __VA_ARGS__);                                                              \
    } while (0)
#define LC_ERROR(module, ...) LC_LOG(LC_LOG_ERROR, module, __VA_ARGS__)
#define LC_WARN(module, ...) LC_LOG(LC_LOG_WARN, module, __VA_ARGS__)
#define LC_INFO(module, ...) LC_LOG(LC_LOG_INFO, module, __VA_ARGS__)
#define LC_DEBUG(module, ...) LC_LOG(LC_LOG_DEBUG, module, __VA_ARGS__)

/* Cancellation: a signal handler (or its watcher thread) calls lc_cancel;
 * long loops (readers' progress, finalize, elements, level of detail) poll
 * lc_cancelled and stop with lc_err_cancelled, so start-up ends cleanly.
 * A load budget (lc_load_budget: seconds from now for the calling thread,
 * 0 = none) makes lc_cancelled true past it too; lc_err_cancelled then says
 * which: LC_ERR_CANCELLED for a signal, LC_ERR_LIMIT for the budget. */
void lc_cancel(int sig);
int lc_cancelled(void);
int lc_err_cancelled(lc_error *err, const char *what);
void lc_load_budget(double seconds);

/* Monotonic clock in seconds. */
double lc_now(void);

#ifdef __cplusplus
}
#endif
#endif
