/* live.c: the live view's HTTP server (live.h) on libmicrohttpd, outside the core (which keeps
 * to libc and libm): one thread per connection, so a viewer that stops reading blocks only its
 * own thread. The run's side is a slot holding the newest frame under a mutex (publish copies
 * into it and signals); each stream's reader waits for a frame newer than the one it sent, then
 * sends it as one Server-Sent Event. The frame's text is written with mote_buf (core/buf.c). */
#include "mote/live.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>

#include "live_page.h"

#define MAX_VIEWERS 8
/* Connections at once (viewers, page loads, control requests): well above the viewers, so that a
 * few idle or slow connections (slowloris) leave room for new ones; each connection idle for
 * IDLE_SECONDS is closed (a stream sends at least a comment a second, so it is never idle). */
#define MAX_CONNECTIONS 64
#define IDLE_SECONDS 10
/* A connection must have sent its whole request head within HEADER_SECONDS of its start: the
 * idle timeout alone let 64 connections trickling a header line every few seconds hold every
 * slot for as long as they liked (issue 52). A watchdog cuts the slow ones. */
#define HEADER_SECONDS 5.0

/* A connection, from its start until it closes: its socket, when it began, whether its request
 * head has arrived (the handler was called). */
typedef struct conn_rec {
    struct conn_rec *next, *prev;
    int fd;
    double t0;
    int handled, cut;
} conn_rec;
/* How long mote_live_stop lets connected viewers take the final frame before it closes them. */
#define FINAL_GRACE_SECONDS 2.0

struct mote_live {
    struct MHD_Daemon *d;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    char *frame;       /* "data: {...}\n\n" */
    size_t len, cap;
    uint64_t seq;      /* frames published */
    int viewers, paused, stopping;
    int closing;       /* the run is over: viewers get the last frame, then their stream ends */
    unsigned port;     /* the bound port, for the Host check */
    double last;       /* wall time of the last frame */
    double gap;        /* the next frame's wait after it (mote_pace_gap; 0 before the first) */
    char *page;        /* the page, its lines joined */
    conn_rec *conns;   /* the open connections (under mu) */
    pthread_t watch;   /* the watchdog of slow request heads */
    pthread_cond_t wcv;
    int watching;
};

/* ---- slow request heads ------------------------------------------------------------------------ */

static void notify(void *cls, struct MHD_Connection *c, void **socket_context,
                   enum MHD_ConnectionNotificationCode toe)
{
    mote_live *l = cls;
    if (toe == MHD_CONNECTION_NOTIFY_STARTED) {
        conn_rec *r = calloc(1, sizeof *r);
        const union MHD_ConnectionInfo *ci =
            MHD_get_connection_info(c, MHD_CONNECTION_INFO_CONNECTION_FD);
        if (!r || !ci) {
            free(r);
            return;
        }
        r->fd = ci->connect_fd;
        r->t0 = mote_wall_seconds();
        pthread_mutex_lock(&l->mu);
        r->next = l->conns;
        if (l->conns)
            l->conns->prev = r;
        l->conns = r;
        pthread_mutex_unlock(&l->mu);
        *socket_context = r;
    } else if (toe == MHD_CONNECTION_NOTIFY_CLOSED && *socket_context) {
        conn_rec *r = *socket_context;
        pthread_mutex_lock(&l->mu);
        if (r->prev)
            r->prev->next = r->next;
        else
            l->conns = r->next;
        if (r->next)
            r->next->prev = r->prev;
        pthread_mutex_unlock(&l->mu);
        free(r);
        *socket_context = NULL;
    }
}

/* The request head of c has arrived: the watchdog leaves it alone. */
static void head_arrived(mote_live *l, struct MHD_Connection *c)
{
    const union MHD_ConnectionInfo *ci =
        MHD_get_connection_info(c, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    conn_rec *r = ci ? (conn_rec *)ci->socket_context : NULL;
    if (r) {
        pthread_mutex_lock(&l->mu);
        r->handled = 1;
        pthread_mutex_unlock(&l->mu);
    }
}

/* Four times a second: shut the sockets of connections whose request head is late (their
 * threads then see the end of the stream and close them). */
static void *watchdog(void *arg)
{
    mote_live *l = arg;
    pthread_mutex_lock(&l->mu);
    while (l->watching) {
        const double now = mote_wall_seconds();
        for (conn_rec *r = l->conns; r; r = r->next)
            if (!r->handled && !r->cut && now - r->t0 > HEADER_SECONDS) {
                shutdown(r->fd, SHUT_RDWR);
                r->cut = 1;
            }
        const struct timespec until = mote_deadline(0.25);
        pthread_cond_timedwait(&l->wcv, &l->mu, &until);
    }
    pthread_mutex_unlock(&l->mu);
    return NULL;
}

/* ---- the stream -------------------------------------------------------------------------------- */

typedef struct {
    mote_live *l;
    uint64_t sent;     /* the last frame sent */
    char *pending;     /* what is left of the frame being sent */
    size_t len, off;
} viewer;

static ssize_t stream_read(void *cls, uint64_t pos, char *out, size_t max)
{
    (void)pos;
    viewer *v = cls;
    mote_live *l = v->l;
    if (v->off < v->len) { /* the rest of a frame */
        size_t k = v->len - v->off < max ? v->len - v->off : max;
        memcpy(out, v->pending + v->off, k);
        v->off += k;
        return (ssize_t)k;
    }
    pthread_mutex_lock(&l->mu);
    if (l->closing && l->seq == v->sent) { /* the final frame is out: end the stream */
        pthread_mutex_unlock(&l->mu);
        return MHD_CONTENT_READER_END_OF_STREAM;
    }
    if (!l->stopping && l->seq == v->sent) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_sec += 1;
        pthread_cond_timedwait(&l->cv, &l->mu, &until);
    }
    if (l->stopping) {
        pthread_mutex_unlock(&l->mu);
        return MHD_CONTENT_READER_END_OF_STREAM;
    }
    if (l->seq == v->sent) { /* nothing new for a second: a comment keeps the line open */
        pthread_mutex_unlock(&l->mu);
        static const char keep[] = ": waiting\n\n";
        size_t k = sizeof keep - 1 < max ? sizeof keep - 1 : max;
        memcpy(out, keep, k);
        return (ssize_t)k;
    }
    char *p = realloc(v->pending, l->len ? l->len : 1);
    if (!p) {
        pthread_mutex_unlock(&l->mu);
        return MHD_CONTENT_READER_END_WITH_ERROR;
    }
    v->pending = p;
    memcpy(p, l->frame, l->len);
    v->len = l->len;
    v->off = 0;
    v->sent = l->seq;
    pthread_mutex_unlock(&l->mu);
    return stream_read(cls, pos, out, max);
}

static void stream_free(void *cls)
{
    viewer *v = cls;
    pthread_mutex_lock(&v->l->mu);
    v->l->viewers--;
    pthread_cond_broadcast(&v->l->cv); /* (mote_live_stop waits for the viewers to leave) */
    pthread_mutex_unlock(&v->l->mu);
    free(v->pending);
    free(v);
}

/* ---- requests ---------------------------------------------------------------------------------- */

static enum MHD_Result reply(struct MHD_Connection *c, unsigned status, const char *type,
                             const char *body)
{
    struct MHD_Response *r =
        MHD_create_response_from_buffer(strlen(body), (void *)body, MHD_RESPMEM_PERSISTENT);
    if (!r)
        return MHD_NO;
    MHD_add_response_header(r, "Content-Type", type);
    MHD_add_response_header(r, "Cache-Control", "no-store");
    MHD_add_response_header(r, "X-Content-Type-Options", "nosniff");
    enum MHD_Result ret = MHD_queue_response(c, status, r);
    MHD_destroy_response(r);
    return ret;
}

/* The Host header names this server: "localhost" or an IPv4 address, with our port. A name that
 * resolves here through someone else's DNS (DNS rebinding) is refused. No Host (HTTP/1.0) is
 * accepted: browsers always send one. */
static int host_ok(const mote_live *l, const char *host)
{
    if (!host)
        return 1;
    const char *colon = strrchr(host, ':');
    char name[64];
    const size_t n = colon ? (size_t)(colon - host) : strlen(host);
    if (n == 0 || n >= sizeof name)
        return 0;
    memcpy(name, host, n);
    name[n] = '\0';
    char *end;
    const unsigned long port = colon ? strtoul(colon + 1, &end, 10) : 80;
    if (colon && (end == colon + 1 || *end))
        return 0;
    struct in_addr a;
    return port == l->port && (strcmp(name, "localhost") == 0 || inet_pton(AF_INET, name, &a) == 1);
}

/* A request that changes the run (pause, resume) comes from the page itself: it carries the
 * header X-Mote-Control (which no form and no cross-site request without a preflight can send;
 * the preflight's OPTIONS gets 405) and, if it has an Origin, that is the page's own. */
static int control_ok(struct MHD_Connection *c, const char *host)
{
    if (!MHD_lookup_connection_value(c, MHD_HEADER_KIND, "X-Mote-Control"))
        return 0;
    const char *origin = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Origin");
    if (!origin)
        return 1;
    return host && strncmp(origin, "http://", 7) == 0 && strcmp(origin + 7, host) == 0;
}

static enum MHD_Result handle(void *cls, struct MHD_Connection *c, const char *url,
                              const char *method, const char *version, const char *upload,
                              size_t *upload_size, void **state)
{
    (void)version;
    (void)upload;
    mote_live *l = cls;
    head_arrived(l, c);
    static int marker;
    const int post = strcmp(method, "POST") == 0, get = strcmp(method, "GET") == 0;
    if (!get && !post)
        return reply(c, MHD_HTTP_METHOD_NOT_ALLOWED, "text/plain", "method not allowed\n");
    if (*state == NULL) { /* the headers: answer once the body (if any) is in */
        *state = &marker;
        return MHD_YES;
    }
    if (*upload_size) { /* a body is read and ignored; the memory limit bounds it */
        *upload_size = 0;
        return MHD_YES;
    }
    const char *host = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Host");
    if (!host_ok(l, host))
        return reply(c, MHD_HTTP_MISDIRECTED_REQUEST, "text/plain",
                     "this server answers to localhost or its address only\n");
    if (get && strcmp(url, "/") == 0)
        return reply(c, MHD_HTTP_OK, "text/html; charset=utf-8", l->page);
    if (post && (strcmp(url, "/pause") == 0 || strcmp(url, "/resume") == 0)) {
        if (!control_ok(c, host))
            return reply(c, MHD_HTTP_FORBIDDEN, "text/plain",
                         "only the page itself pauses and resumes the run\n");
        pthread_mutex_lock(&l->mu);
        l->paused = url[1] == 'p';
        pthread_cond_broadcast(&l->cv);
        pthread_mutex_unlock(&l->mu);
        return reply(c, MHD_HTTP_OK, "text/plain", url[1] == 'p' ? "paused\n" : "running\n");
    }
    if (get && strcmp(url, "/stream") == 0) {
        pthread_mutex_lock(&l->mu);
        const int full = l->viewers >= MAX_VIEWERS;
        if (!full)
            l->viewers++;
        const uint64_t now = l->seq;
        pthread_mutex_unlock(&l->mu);
        if (full)
            return reply(c, MHD_HTTP_SERVICE_UNAVAILABLE, "text/plain", "too many viewers\n");
        viewer *v = calloc(1, sizeof *v);
        struct MHD_Response *r =
            v ? MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 64 * 1024, stream_read, v,
                                                  stream_free)
              : NULL;
        if (!r) {
            if (v)
                stream_free(v);
            else {
                pthread_mutex_lock(&l->mu);
                l->viewers--;
                pthread_mutex_unlock(&l->mu);
            }
            return MHD_NO;
        }
        v->l = l;
        v->sent = now ? now - 1 : 0; /* the newest frame first */
        MHD_add_response_header(r, "Content-Type", "text/event-stream");
        MHD_add_response_header(r, "Cache-Control", "no-store");
        enum MHD_Result ret = MHD_queue_response(c, MHD_HTTP_OK, r);
        MHD_destroy_response(r);
        return ret;
    }
    return reply(c, MHD_HTTP_NOT_FOUND, "text/plain", "not found\n");
}

/* ---- the run's side ---------------------------------------------------------------------------- */

static void stop_watchdog(mote_live *l)
{
    pthread_mutex_lock(&l->mu);
    const int was = l->watching;
    l->watching = 0;
    pthread_cond_broadcast(&l->wcv);
    pthread_mutex_unlock(&l->mu);
    if (was)
        pthread_join(l->watch, NULL);
}

int mote_live_start(mote_live **out, const char *bind, int port, char url[128], mote_err *err)
{
    *out = NULL;
    if (port < 0 || port > 65535)
        return mote_fail(err, MOTE_EINVAL, "live: port %d is not 0 ... 65535", port);
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons((uint16_t)port);
    const char *host = bind ? bind : "127.0.0.1";
    if (inet_pton(AF_INET, host, &a.sin_addr) != 1)
        return mote_fail(err, MOTE_EINVAL, "live: bind=%s is not an IPv4 address", host);
    mote_live *l = calloc(1, sizeof *l);
    if (!l)
        return mote_fail(err, MOTE_ENOMEM, "live: out of memory");
    size_t plen = 1;
    const size_t nlines = sizeof mote_live_page_lines / sizeof mote_live_page_lines[0];
    for (size_t k = 0; k < nlines; k++)
        plen += strlen(mote_live_page_lines[k]) + 1;
    l->page = malloc(plen);
    if (!l->page) {
        free(l);
        return mote_fail(err, MOTE_ENOMEM, "live: out of memory");
    }
    l->page[0] = '\0';
    for (size_t k = 0, at = 0; k < nlines; k++) {
        const size_t n = strlen(mote_live_page_lines[k]);
        memcpy(l->page + at, mote_live_page_lines[k], n);
        l->page[at + n] = '\n';
        l->page[at + n + 1] = '\0';
        at += n + 1;
    }
    pthread_mutex_init(&l->mu, NULL);
    pthread_cond_init(&l->cv, NULL);
    pthread_cond_init(&l->wcv, NULL);
    l->watching = 1;
    if (pthread_create(&l->watch, NULL, watchdog, l) != 0) {
        l->watching = 0;
        pthread_cond_destroy(&l->wcv);
        pthread_cond_destroy(&l->cv);
        pthread_mutex_destroy(&l->mu);
        free(l->page);
        free(l);
        return mote_fail(err, MOTE_ENOMEM, "live: cannot start the server's watchdog thread");
    }
    l->d = MHD_start_daemon(MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_THREAD_PER_CONNECTION, 0,
                            NULL, NULL, handle, l, MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&a,
                            MHD_OPTION_CONNECTION_LIMIT, (unsigned)MAX_CONNECTIONS,
                            MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)16384,
                            MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)IDLE_SECONDS,
                            MHD_OPTION_NOTIFY_CONNECTION, notify, l, MHD_OPTION_END);
    if (!l->d) {
        stop_watchdog(l);
        pthread_cond_destroy(&l->wcv);
        pthread_cond_destroy(&l->cv);
        pthread_mutex_destroy(&l->mu);
        free(l->page);
        free(l);
        return mote_fail(err, MOTE_EIO, "live: cannot serve on %s:%d (is the port taken?)", host,
                         port);
    }
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(l->d, MHD_DAEMON_INFO_BIND_PORT);
    l->port = info ? (unsigned)info->port : (unsigned)port;
    snprintf(url, 128, "http://%s:%u/", host, l->port);
    *out = l;
    return MOTE_OK;
}

void mote_live_stop(mote_live *l)
{
    if (!l)
        return;
    /* every connected viewer takes the final frame, for up to FINAL_GRACE_SECONDS */
    pthread_mutex_lock(&l->mu);
    l->closing = 1;
    l->paused = 0;
    pthread_cond_broadcast(&l->cv);
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += (time_t)FINAL_GRACE_SECONDS;
    while (l->viewers > 0)
        if (pthread_cond_timedwait(&l->cv, &l->mu, &until) == ETIMEDOUT)
            break;
    l->stopping = 1;
    pthread_cond_broadcast(&l->cv);
    pthread_mutex_unlock(&l->mu);
    MHD_stop_daemon(l->d);
    stop_watchdog(l);
    pthread_cond_destroy(&l->wcv);
    pthread_cond_destroy(&l->cv);
    pthread_mutex_destroy(&l->mu);
    free(l->frame);
    free(l->page);
    free(l);
}

int mote_live_due(mote_live *l, int now)
{
    pthread_mutex_lock(&l->mu);
    const int v = l->viewers;
    pthread_mutex_unlock(&l->mu);
    return v > 0 && (now || mote_wall_seconds() - l->last >= l->gap);
}

void mote_live_publish(mote_live *l, const char *json, size_t len, double cost)
{
    l->last = mote_wall_seconds();
    l->gap = mote_pace_gap(1.0 / 30, cost);
    pthread_mutex_lock(&l->mu);
    const size_t need = len + 9;
    if (need > l->cap) {
        char *p = realloc(l->frame, need);
        if (!p) {
            pthread_mutex_unlock(&l->mu);
            return; /* dropped */
        }
        l->frame = p;
        l->cap = need;
    }
    memcpy(l->frame, "data: ", 6);
    memcpy(l->frame + 6, json, len);
    memcpy(l->frame + 6 + len, "\n\n", 2);
    l->len = len + 8;
    l->seq++;
    pthread_cond_broadcast(&l->cv);
    pthread_mutex_unlock(&l->mu);
}

void mote_live_hold(mote_live *l)
{
    pthread_mutex_lock(&l->mu);
    while (l->paused && !l->stopping)
        pthread_cond_wait(&l->cv, &l->mu);
    pthread_mutex_unlock(&l->mu);
}

uint64_t mote_live_frames(mote_live *l)
{
    pthread_mutex_lock(&l->mu);
    const uint64_t n = l->seq;
    pthread_mutex_unlock(&l->mu);
    return n;
}

int mote_live_viewers(mote_live *l)
{
    pthread_mutex_lock(&l->mu);
    const int v = l->viewers;
    pthread_mutex_unlock(&l->mu);
    return v;
}
