/* `lucent serve`: the daemon's entry point (flags, start-up, shutdown). */
#ifndef LC_SERVE_H
#define LC_SERVE_H

#ifdef __cplusplus
extern "C" {
#endif

/* `lucent serve [flags]`; argv[0] is "serve". Returns the process exit code:
 * 0 after a clean SIGINT/SIGTERM shutdown, 1 on start-up failure, 2 on usage
 * errors. Call once, from the main thread. */
int lc_serve_main(int argc, char **argv);

#ifdef __cplusplus
}
#endif
#endif
