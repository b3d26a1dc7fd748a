/* Shutdown signals of `lucent serve`: SIGINT and SIGTERM are taken by one
 * watcher thread for the whole life of the process, so that they are honoured
 * during start-up too. A signal before lc_signals_serving cancels the load
 * (lc_cancel: readers, finalize, elements and the level of detail stop at their
 * next check) and the process exits with a message; should start-up not come
 * back within LC_SIGNALS_GRACE seconds (a GL call, a demo being generated), the
 * watcher ends the process itself. After lc_signals_serving, a signal wakes
 * lc_signals_wait for the ordered shutdown.
 * Threading: lc_signals_start from the main thread before any other thread
 * exists (the mask is inherited); the rest from any thread. */
#ifndef LC_SIGNALS_H
#define LC_SIGNALS_H

#include "lc_base.h"

#define LC_SIGNALS_GRACE 3.0

int lc_signals_start(lc_error *err);
/* Start-up is over: a signal from now on means an ordered shutdown. */
void lc_signals_serving(void);
/* Blocks until SIGINT or SIGTERM (at once when one came already); returns it. */
int lc_signals_wait(void);
/* The first signal received, 0 = none. */
int lc_signals_received(void);
/* "SIGINT", "SIGTERM". */
const char *lc_signals_name(int sig);

#endif
