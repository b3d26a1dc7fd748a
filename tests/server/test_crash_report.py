"""A daemon that dies of a fatal signal says so in its log: the signal's name
and the stack of the thread it hit (server/daemon/start/crash.c), then ends
with the signal's default action, so its exit status is still the signal.
The signal is sent from outside to the main thread (tgkill), as a fault
arrives at the thread that faulted; the handler does not care where it came
from. (A kill() reaches any thread that does not block the signal, perhaps a
library's, whose stack holds no frame of lucent but the handler's.) Sanitizer
builds keep their own, fuller reports and are only checked for naming the
signal."""
import signal
import sys

from lucent_server import Check, Server, sanitized

binary = sys.argv[1]
check = Check()

for sig, name in ((signal.SIGSEGV, "SIGSEGV"), (signal.SIGABRT, "SIGABRT")):
    srv = Server(binary)
    status, _, _ = srv.request("GET", "/api/v1/health")
    check(status == 200, "the daemon serves before the signal (%d)" % status)
    rc = srv.stop(sig, main_thread=True)  # the exit status, once the log's last lines are in
    log = "\n".join(srv.log)
    if sanitized(binary):
        check(name[3:] in log or "DEADLYSIGNAL" in log or rc == -sig,
              "%s: a sanitizer build reports it its own way (rc %s)" % (name, rc))
        continue
    check(rc == -sig, "%s: the daemon ends by the signal itself (exit status %s)" % (name, rc))
    check("fatal signal %s" % name in log, "%s: the log names the signal:\n%s" % (name, "\n".join(srv.log[-12:])))
    frames = [line for line in srv.log if "lucent(" in line or "/lucent(" in line or "lucent[" in line]
    check(len(frames) >= 2, "%s: the log holds the stack (%d frames of lucent)" % (name, len(frames)))

check.done()
