/* Fatal-signal report (crash.h). */
#include "crash.h"

#include <execinfo.h>
#include <signal.h>
#include <string.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define LC_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define LC_SANITIZED 1
#endif
#endif

static const int fatal[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};

static const char *fatal_name(int sig)
{
    switch (sig) {
    case SIGSEGV: return "SIGSEGV";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGABRT: return "SIGABRT";
    default: return "signal";
    }
}

static void say(const char *s) { (void)!write(STDERR_FILENO, s, strlen(s)); }

/* Only async-signal-safe calls: write, backtrace (its library is loaded at
 * install time, below) and backtrace_symbols_fd, which does not allocate. */
static void on_fatal(int sig)
{
    say("lucent serve: fatal signal ");
    say(fatal_name(sig));
    say("; the stack of the thread it hit:\n");
    void *frames[64];
    int n = backtrace(frames, 64);
    backtrace_symbols_fd(frames, n, STDERR_FILENO);
    say("lucent serve: (addr2line -f -e BINARY +OFFSET names a frame) ending with the signal's default action\n");
    /* SA_RESETHAND restored the default: returning re-runs a fault, and an
     * abort or a signal sent by another process is raised again. */
    raise(sig);
}

void lc_crash_report_install(void)
{
#ifndef LC_SANITIZED
    void *warm[1];
    backtrace(warm, 1); /* loads libgcc's unwinder now, not inside a handler */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_fatal;
    sa.sa_flags = (int)SA_RESETHAND | SA_NODEFER;
    sigemptyset(&sa.sa_mask);
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
        sigaction(fatal[i], &sa, NULL);
#endif
}
