#!/bin/bash
# Entry point of the Lucent container image (installed as
# /usr/local/bin/lucent-entrypoint; tests/container runs it the same way).
#   lucent-entrypoint [SERVE-ARGS...]  lucent serve on $LUCENT_LISTEN (0.0.0.0:8080)
#                                      with the datasets found in $LUCENT_DATA (/data)
#   lucent-entrypoint health           exit 0 when /api/v1/health answers "ok" (HEALTHCHECK)
#   lucent-entrypoint lucent ARGS...   any other subcommand (render, info, bench, ...)
# Settings by environment (all optional):
#   LUCENT_LISTEN     listen address inside the container (default 0.0.0.0:8080)
#   LUCENT_DATA       dataset folder (default /data); ignored when SERVE-ARGS name --data
#   LUCENT_DEMO=1     also serve the built-in demos next to the datasets of LUCENT_DATA
#   LUCENT_WORKERS, LUCENT_ENCODERS, LUCENT_DEMO_SIZE, LUCENT_MAX_SESSIONS
#                     --workers, --encoders, --demo-size, --max-sessions
#   LUCENT_TOKEN, LUCENT_EGL_DEVICE, LUCENT_LOG_LEVEL are read by lucent itself.
set -euo pipefail
lucent=${LUCENT_BINARY:-/usr/local/bin/lucent}
listen=${LUCENT_LISTEN:-0.0.0.0:8080}

health() {
  local port=${listen##*:} host=127.0.0.1 status body
  [[ $listen == \[* ]] && host=::1
  exec 3<>"/dev/tcp/$host/$port" || return 1
  printf 'GET /api/v1/health HTTP/1.0\r\nHost: localhost\r\n\r\n' >&3
  IFS= read -r -t 5 status <&3 || return 1
  body=$(timeout 5 cat <&3) || return 1
  [[ $status == "HTTP/1."?" 200"* && $body == *'"status":"ok"'* ]]
}

case "${1:-}" in
  health) health; exit ;;
  lucent) shift; exec "$lucent" "$@" ;;
esac

args=(serve --listen "$listen")
[ -n "${LUCENT_WORKERS:-}" ] && args+=(--workers "$LUCENT_WORKERS")
[ -n "${LUCENT_ENCODERS:-}" ] && args+=(--encoders "$LUCENT_ENCODERS")
[ -n "${LUCENT_DEMO_SIZE:-}" ] && args+=(--demo-size "$LUCENT_DEMO_SIZE")
[ -n "${LUCENT_MAX_SESSIONS:-}" ] && args+=(--max-sessions "$LUCENT_MAX_SESSIONS")

# Datasets of the mounted folder (lucent serve loads every recognized file of
# it), unless the arguments name their own; an empty folder serves the demos.
data=${LUCENT_DATA:-/data}
own_data=0
for a in "$@"; do [[ $a == --data || $a == --data=* ]] && own_data=1; done
if [ "$own_data" = 0 ] && [ -d "$data" ] && [ -n "$(ls -A "$data" 2>/dev/null)" ]; then
  args+=(--data "$data")
  [ "${LUCENT_DEMO:-0}" = 1 ] && args+=(--demo)
fi
exec "$lucent" "${args[@]}" "$@"
