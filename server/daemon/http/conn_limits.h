/* Connections that have not completed a request yet (no full header): each
 * must send its header within a deadline, one client address may hold only so
 * many of them, and all together only so many; a new connection beyond a cap
 * closes the oldest such connection (of that address first). So a few hundred
 * slow sockets cannot fill the connection limit and starve everyone else, and
 * a fresh request (a health probe from the same address included) always gets
 * in: it is the newest, and it leaves this state within milliseconds.
 * Connections that sent a whole request (keep-alive, WebSocket) are not
 * counted; libmicrohttpd's idle timeout covers them.
 * Threading: the callbacks run on libmicrohttpd's threads; one mutex. */
#ifndef LC_CONN_LIMITS_H
#define LC_CONN_LIMITS_H

#include <microhttpd.h>
#include <stdint.h>

#define LC_CONN_HEADER_DEADLINE 10.0 /* seconds from accept to a whole request header */
#define LC_CONN_PENDING_PER_CLIENT 32
#define LC_CONN_PENDING_TOTAL 128

/* MHD_OPTION_NOTIFY_CONNECTION's callback (cls unused). */
void lc_conn_limits_notify(void *cls, struct MHD_Connection *c, void **socket_context,
                           enum MHD_ConnectionNotificationCode code);
/* From the access handler's first call: c has sent a whole request header. */
void lc_conn_limits_request(struct MHD_Connection *c);
/* The client a connection comes from, as a key: a hash of its address (not
 * its port, so that many connections of one client count as one). What
 * fairness and the ownership of jobs key on. */
uint64_t lc_conn_client_key(struct MHD_Connection *c);
/* Connections closed so far for the deadline and for the caps. */
void lc_conn_limits_counts(uint64_t *deadline, uint64_t *evicted);

#endif
