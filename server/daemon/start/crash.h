/* Last words of `lucent serve`: a fatal signal (a fault, an abort, a
 * libmicrohttpd panic) prints its name and the faulting thread's stack to
 * stderr before the process dies as it would have (the default action, so a
 * core dump and the exit status stay the signal's). A daemon that vanishes
 * from under its clients then leaves its cause in the log.
 * Threading: lc_crash_report_install once from the main thread at start-up. */
#ifndef LC_CRASH_H
#define LC_CRASH_H

/* Installs the handlers; a no-op in sanitizer builds, whose own reports are
 * fuller. */
void lc_crash_report_install(void);

#endif
