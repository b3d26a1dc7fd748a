/* Accounting of connections without a whole request yet (conn_limits.h). */
#include "conn_limits.h"

#include <netinet/in.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#include "lc_base.h"

#define MOD "http"

typedef struct pending {
    struct pending *prev, *next; /* in accept order, oldest first */
    int fd;
    bool listed;
    double accepted;
    unsigned char addr[16]; /* the client's address (IPv4 in the first 4 bytes) */
} pending;

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static pending *oldest, *newest;
static int count;
static uint64_t closed_deadline, closed_evicted;
static double last_warning;

static void unlink_entry(pending *p)
{
    if (!p->listed)
        return;
    *(p->prev ? &p->prev->next : &oldest) = p->next;
    *(p->next ? &p->next->prev : &newest) = p->prev;
    p->prev = p->next = NULL;
    p->listed = false;
    count--;
}

/* Ends the connection: libmicrohttpd sees the socket shut and closes it
 * itself (the descriptor stays valid until its CLOSED notice, which takes the
 * lock we hold, so it cannot be another connection's by now). */
static void drop(pending *p)
{
    shutdown(p->fd, SHUT_RDWR);
    unlink_entry(p);
}

static void client_address(struct MHD_Connection *c, unsigned char out[16])
{
    memset(out, 0, 16);
    const union MHD_ConnectionInfo *ci = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
    const struct sockaddr *sa = ci ? ci->client_addr : NULL;
    if (sa && sa->sa_family == AF_INET)
        memcpy(out, &((const struct sockaddr_in *)sa)->sin_addr, 4);
    else if (sa && sa->sa_family == AF_INET6)
        memcpy(out, &((const struct sockaddr_in6 *)sa)->sin6_addr, 16);
}

uint64_t lc_conn_client_key(struct MHD_Connection *c)
{
    unsigned char a[16];
    client_address(c, a);
    uint64_t h = 1469598103934665603ULL; /* FNV-1a */
    for (int i = 0; i < 16; i++)
        h = (h ^ a[i]) * 1099511628211ULL;
    return h;
}

/* Makes room for p: drops the connections past the deadline, then the
 * oldest of p's address beyond its cap, then the oldest beyond the total. */
static void admit(pending *p)
{
    int same = 0;
    pending *first_same = NULL;
    for (pending *q = oldest, *next; q; q = next) {
        next = q->next;
        if (p->accepted - q->accepted > LC_CONN_HEADER_DEADLINE) {
            drop(q);
            closed_deadline++;
        } else if (memcmp(q->addr, p->addr, 16) == 0) {
            first_same = first_same ? first_same : q;
            same++;
        }
    }
    pending *victim = same >= LC_CONN_PENDING_PER_CLIENT ? first_same : count >= LC_CONN_PENDING_TOTAL ? oldest : NULL;
    if (victim) {
        drop(victim);
        closed_evicted++;
        if (p->accepted - last_warning > 10.0) {
            last_warning = p->accepted;
            LC_WARN(MOD,
                    "many connections without a request: closing the oldest (%llu so far; %llu past the %.0f s "
                    "header deadline)",
                    (unsigned long long)closed_evicted, (unsigned long long)closed_deadline, LC_CONN_HEADER_DEADLINE);
        }
    }
    p->prev = newest;
    *(newest ? &newest->next : &oldest) = p;
    newest = p;
    p->listed = true;
    count++;
}

void lc_conn_limits_notify(void *cls, struct MHD_Connection *c, void **socket_context,
                           enum MHD_ConnectionNotificationCode code)
{
    (void)cls;
    if (code == MHD_CONNECTION_NOTIFY_STARTED) {
        pending *p = calloc(1, sizeof *p);
        const union MHD_ConnectionInfo *fd = MHD_get_connection_info(c, MHD_CONNECTION_INFO_CONNECTION_FD);
        *socket_context = p;
        if (!p || !fd)
            return; /* not accounted: at worst one connection escapes the caps */
        p->fd = fd->connect_fd;
        p->accepted = lc_now();
        client_address(c, p->addr);
        pthread_mutex_lock(&lock);
        admit(p);
        pthread_mutex_unlock(&lock);
    } else if (code == MHD_CONNECTION_NOTIFY_CLOSED && *socket_context) {
        pending *p = *socket_context;
        pthread_mutex_lock(&lock);
        unlink_entry(p);
        pthread_mutex_unlock(&lock);
        free(p);
        *socket_context = NULL;
    }
}

void lc_conn_limits_request(struct MHD_Connection *c)
{
    const union MHD_ConnectionInfo *ci = MHD_get_connection_info(c, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    pending *p = ci ? ci->socket_context : NULL;
    if (!p)
        return;
    pthread_mutex_lock(&lock);
    unlink_entry(p);
    pthread_mutex_unlock(&lock);
}

void lc_conn_limits_counts(uint64_t *deadline, uint64_t *evicted)
{
    pthread_mutex_lock(&lock);
    *deadline = closed_deadline;
    *evicted = closed_evicted;
    pthread_mutex_unlock(&lock);
}
