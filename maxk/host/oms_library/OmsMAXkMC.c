/* libOmsMAXkMC: the OMS MAXk motion-control library API over a board served by maxk.
 *
 * The vendor's OmsMAXkMC.dll reaches a MAXk through its device driver: command text goes
 * into the board's command ring, replies come back in its response ring, and the done,
 * overtravel and slip flags, the switches and the positions are read from the PCI
 * shared memory. This library does the same through the map file of `maxk serve --shm`
 * (layout: docs/shared-memory.md), or through the board's TCP door where there is no map
 * (another machine; Windows). The command text of each function is the ASCII template
 * the vendor DLL carries (docs/oms-library.md). Where the board is found:
 * docs/oms-library.md, "Finding the board".
 *
 * One source for every platform: on Windows only the TCP transport is built. */

#define OMSMAXKMC_BUILD 1
#if !defined(_WIN32)
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE 1 /* glibc: flock, the BSD socket words */
#define _DARWIN_C_SOURCE 1 /* macOS: the same */
#endif

#if defined(_WIN32)
#include <winsock2.h> /* before windows.h, which the header includes */
#include <ws2tcpip.h>
#endif
#include "OmsMAXkMC.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(_WIN32)
typedef SOCKET oms_socket;
#define OMS_BAD_SOCKET INVALID_SOCKET
#define oms_close_socket closesocket
typedef CRITICAL_SECTION oms_mutex;
#define oms_mutex_init(m) InitializeCriticalSection(m)
#define oms_mutex_lock(m) EnterCriticalSection(m)
#define oms_mutex_unlock(m) LeaveCriticalSection(m)
#define oms_mutex_destroy(m) DeleteCriticalSection(m)
#define strncasecmp _strnicmp
#else
#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <pthread.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
typedef int oms_socket;
#define OMS_BAD_SOCKET (-1)
#define oms_close_socket close
typedef pthread_mutex_t oms_mutex;
#define oms_mutex_init(m) pthread_mutex_init((m), NULL)
#define oms_mutex_lock(m) pthread_mutex_lock(m)
#define oms_mutex_unlock(m) pthread_mutex_unlock(m)
#define oms_mutex_destroy(m) pthread_mutex_destroy(m)
#define OMS_HAVE_MAP 1
#ifndef MSG_NOSIGNAL /* macOS: SO_NOSIGPIPE on the socket instead */
#define MSG_NOSIGNAL 0
#endif
#endif

#define OMS_LIBRARY_VERSION "OmsMAXkMC v1.00 (maxk emulator library 1.0)"
#define OMS_DRIVER_VERSION "maxk map/TCP transport 1.0"
#define OMS_BOARDS 16
#define OMS_AXES 10
#define OMS_REPLY_MAX 80 /* the vendor demo's reply buffer: replies are cut to fit */
#define OMS_LINE_MAX 4096

static const char AXIS_LETTERS[OMS_AXES] = {'X', 'Y', 'Z', 'T', 'U', 'V', 'R', 'S', 'W', 'K'};

/* ---- the map (docs/shared-memory.md; maxk/host/memory_map.py) ------------------------ */
#define MAP_SIZE 0xE010u
#define MAP_MOTOR_XS 0x000u
#define MAP_ENCODER_XS 0x020u
#define MAP_LIMIT_WORD 0x040u
#define MAP_HOME_WORD 0x044u
#define MAP_FIRMWARE_FLAGS 0x048u
#define MAP_DIRECT_MAILBOX 0x04Cu
#define MAP_POSITION_REQUEST 0x050u
#define MAP_SNAP_MOTOR_XS 0x054u
#define MAP_SNAP_ENCODER_XS 0x074u
#define MAP_IO_WORD 0x09Cu
#define MAP_MOTOR_WK 0x0ACu
#define MAP_ENCODER_WK 0x0B4u
#define MAP_SNAP_MOTOR_WK 0x0BCu
#define MAP_SNAP_ENCODER_WK 0x0C4u
#define MAP_STATUS_WK 0x0CCu
#define MAP_CMD_INSERT 0x0F0u
#define MAP_CMD_PROCESS 0x0F4u
#define MAP_RESP_INSERT 0x0F8u
#define MAP_RESP_PROCESS 0x0FCu
#define MAP_CMD_RING 0x100u
#define MAP_RESP_RING 0x500u
#define MAP_RING_SIZE 1024u
#define MAP_ABSOLUTE_ENCODERS 0x3520u
#define MAP_ODBR 0xD000u
#define MAP_ODBR_CLEAR 0xD004u
#define MAP_OMR0 0xD008u
#define MAP_TICK 0xD010u
#define MAP_LAYOUT 0xD018u
#define DIRECT_KILL_ALL 1u
#define DIRECT_RESET 2u
#define ODBR_COMMAND_ERROR (1u << 24)
#define ODBR_W_NOTIFY (1u << 25)
#define ODBR_K_NOTIFY (1u << 26)
#define WK_DONE 0x1u
#define WK_OVERTRAVEL 0x2u
#define WK_SLIP 0x4u

enum oms_transport { OMS_MAP = 1, OMS_TCP = 2 };

typedef struct oms_board {
    int number; /* 1..16: the name's N */
    int transport;
    int refs; /* handles open on this board in this process */
    oms_mutex lock; /* one caller at a time per board: commands and replies stay paired */
    int map_fd; /* the map file, read and written with pread/pwrite (never mapped) */
    int map_lost; /* a read of the map came up short: it was truncated under us */
    char map_path[1024];
    oms_socket sock;
    char inbox[OMS_LINE_MAX]; /* received reply text not yet taken */
    size_t inbox_len;
    int skipping; /* inside a line too long for the inbox: dropped up to its line end */
    unsigned long dropped_lines; /* such lines dropped (MaxkOmsDroppedLines) */
    unsigned long notified; /* TCP: flag bits the board has notified, not yet cleared */
    eOMSBuffMode buffer_mode;
    long command_ms, response_ms;
} oms_board;

static oms_board *g_boards[OMS_BOARDS + 1];
#if defined(_WIN32)
static CRITICAL_SECTION g_registry;
static volatile LONG g_registry_ready;
static void registry_lock(void)
{
    if (InterlockedCompareExchange(&g_registry_ready, 1, 0) == 0) {
        InitializeCriticalSection(&g_registry);
        g_registry_ready = 2;
    }
    while (g_registry_ready != 2)
        Sleep(0);
    EnterCriticalSection(&g_registry);
}
static void registry_unlock(void) { LeaveCriticalSection(&g_registry); }
#else
static pthread_mutex_t g_registry = PTHREAD_MUTEX_INITIALIZER;
static void registry_lock(void) { pthread_mutex_lock(&g_registry); }
static void registry_unlock(void) { pthread_mutex_unlock(&g_registry); }
#endif

/* ---- time ----------------------------------------------------------------------------- */
static double now_ms(void)
{
#if defined(_WIN32)
    static LARGE_INTEGER freq;
    LARGE_INTEGER t;
    if (!freq.QuadPart)
        QueryPerformanceFrequency(&freq);
    QueryPerformanceCounter(&t);
    return (double)t.QuadPart * 1000.0 / (double)freq.QuadPart;
#else
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1000.0 + (double)t.tv_nsec / 1e6;
#endif
}

static void pause_us(long us)
{
#if defined(_WIN32)
    Sleep((DWORD)((us + 999) / 1000));
#else
    struct timespec t = {us / 1000000, (us % 1000000) * 1000};
    nanosleep(&t, NULL);
#endif
}

#if !defined(_WIN32)
/* The windows.h stand-in's Sleep and GetTickCount (include/windows.h). */
OMS_LINKAGE void OmsCompatSleep(DWORD ms) { pause_us((long)ms * 1000L); }
OMS_LINKAGE DWORD OmsCompatTickCount(void) { return (DWORD)(uint64_t)now_ms(); }
#endif

/* How long the library waits for the board to take a command and to answer it
 * (MAXK_OMS_COMMAND_TIMEOUT_MS / MAXK_OMS_RESPONSE_TIMEOUT_MS; default 2000 ms). */
static long env_ms(const char *name, long fallback)
{
    const char *text = getenv(name);
    char *end;
    long value;
    if (!text || !*text)
        return fallback;
    value = strtol(text, &end, 10);
    return (*end || value <= 0) ? fallback : value;
}

/* ---- the inbox ------------------------------------------------------------------------ */
/* Room for more reply text. An inbox full without a line end holds the start of a line
 * longer than any reply of a MAX board: that line is dropped, counted, up to its line end
 * (inbox_add), so later replies get through (issue 34: it used to fill the inbox for good
 * and every later query timed out). */
static size_t inbox_room(oms_board *b)
{
    if (b->inbox_len == sizeof b->inbox && !memchr(b->inbox, '\n', b->inbox_len) &&
        !memchr(b->inbox, '\r', b->inbox_len)) {
        b->inbox_len = 0;
        b->skipping = 1;
        b->dropped_lines++;
    }
    return sizeof b->inbox - b->inbox_len;
}

/* Append received text (at most inbox_room bytes), skipping the rest of a dropped line. */
static void inbox_add(oms_board *b, const char *data, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        if (b->skipping) {
            if (data[i] == '\n' || data[i] == '\r')
                b->skipping = 0;
            continue;
        }
        if (b->inbox_len < sizeof b->inbox)
            b->inbox[b->inbox_len++] = data[i];
    }
}

/* ---- map access (big-endian words) ----------------------------------------------------- */
/* The library never maps the file: it reads and writes it with pread/pwrite, which share
 * the page cache with every mapping of it. A map truncated under a mapping kills the
 * process that touches it (SIGBUS); a short pread is only a short read: the call then
 * returns COMMAND_TIME_OUT and the next call looks for a map served at the path again
 * (map_ready). */
#ifdef OMS_HAVE_MAP
static int map_read(oms_board *b, void *data, size_t n, unsigned offset)
{
    if (b->map_lost || offset + n > MAP_SIZE ||
        pread(b->map_fd, data, n, (off_t)offset) != (ssize_t)n) {
        b->map_lost = 1;
        return 0;
    }
    return 1;
}

static void map_write(oms_board *b, const void *data, size_t n, unsigned offset)
{
    if (b->map_lost || offset + n > MAP_SIZE ||
        pwrite(b->map_fd, data, n, (off_t)offset) != (ssize_t)n)
        b->map_lost = 1;
}

static uint32_t map_get(oms_board *b, unsigned offset)
{
    unsigned char raw[4] = {0, 0, 0, 0};
    map_read(b, raw, 4, offset);
    return (uint32_t)raw[0] << 24 | (uint32_t)raw[1] << 16 | (uint32_t)raw[2] << 8 | raw[3];
}

static void map_put(oms_board *b, unsigned offset, uint32_t value)
{
    unsigned char raw[4];
    raw[0] = (unsigned char)(value >> 24);
    raw[1] = (unsigned char)(value >> 16);
    raw[2] = (unsigned char)(value >> 8);
    raw[3] = (unsigned char)value;
    map_write(b, raw, 4, offset);
}

static long map_signed(oms_board *b, unsigned offset) { return (long)(int32_t)map_get(b, offset); }

static unsigned motor_offset(int axis)
{
    return axis < 8 ? MAP_MOTOR_XS + 4u * (unsigned)axis : MAP_MOTOR_WK + 4u * (unsigned)(axis - 8);
}
static unsigned encoder_offset(int axis)
{
    return axis < 8 ? MAP_ENCODER_XS + 4u * (unsigned)axis : MAP_ENCODER_WK + 4u * (unsigned)(axis - 8);
}
static unsigned snap_motor_offset(int axis)
{
    return axis < 8 ? MAP_SNAP_MOTOR_XS + 4u * (unsigned)axis
                    : MAP_SNAP_MOTOR_WK + 4u * (unsigned)(axis - 8);
}
static unsigned snap_encoder_offset(int axis)
{
    return axis < 8 ? MAP_SNAP_ENCODER_XS + 4u * (unsigned)axis
                    : MAP_SNAP_ENCODER_WK + 4u * (unsigned)(axis - 8);
}

/* Wait until a mailbox word reads 0 (the board took what was written there). */
static long map_mailbox_wait(oms_board *b, unsigned offset, uint32_t busy_value, long ms)
{
    double deadline = now_ms() + (double)ms;
    for (;;) {
        uint32_t v = map_get(b, offset);
        if (b->map_lost)
            return COMMAND_TIME_OUT;
        if (busy_value ? v != busy_value : v == 0)
            return SUCCESS;
        if (now_ms() > deadline)
            return COMMAND_TIME_OUT;
        pause_us(100);
    }
}

/* Wait until the board has refreshed its registers after what it just took (the tick
 * counter is written after the flags in each refresh), so a flag read next is current. */
static long map_settle(oms_board *b, long ms)
{
    double deadline = now_ms() + (double)ms;
    uint32_t tick = map_get(b, MAP_TICK);
    while (map_get(b, MAP_TICK) == tick) {
        if (b->map_lost || now_ms() > deadline)
            return COMMAND_TIME_OUT;
        pause_us(100);
    }
    return SUCCESS;
}

/* Wait until the board has taken all text written so far and refreshed after it. */
static long map_sync(oms_board *b, long ms)
{
    double deadline = now_ms() + (double)ms;
    uint32_t target = map_get(b, MAP_CMD_INSERT);
    while (map_get(b, MAP_CMD_PROCESS) != target) {
        if (b->map_lost || now_ms() > deadline)
            return COMMAND_TIME_OUT;
        pause_us(100);
    }
    return map_settle(b, ms);
}

static long map_write_text(oms_board *b, const char *text, size_t n)
{
    double deadline = now_ms() + (double)b->command_ms;
    while (n) {
        uint32_t insert = map_get(b, MAP_CMD_INSERT) % MAP_RING_SIZE;
        uint32_t process = map_get(b, MAP_CMD_PROCESS) % MAP_RING_SIZE;
        uint32_t room = (process + MAP_RING_SIZE - insert - 1u) % MAP_RING_SIZE;
        size_t chunk, first;
        if (b->map_lost)
            return COMMAND_TIME_OUT;
        if (!room) {
            if (now_ms() > deadline)
                return COMMAND_TIME_OUT;
            pause_us(100);
            continue;
        }
        chunk = n < room ? n : room;
        first = chunk < MAP_RING_SIZE - insert ? chunk : MAP_RING_SIZE - insert;
        map_write(b, text, first, MAP_CMD_RING + insert); /* up to the ring's end, then wrap */
        if (chunk > first)
            map_write(b, text + first, chunk - first, MAP_CMD_RING);
        map_put(b, MAP_CMD_INSERT, (uint32_t)((insert + chunk) % MAP_RING_SIZE));
        text += chunk;
        n -= chunk;
    }
    return SUCCESS;
}

/* Move what the response ring holds into the inbox, as much as it has room for (the
 * rest stays in the ring); 1 if anything came. */
static int map_pull(oms_board *b)
{
    char text[MAP_RING_SIZE];
    uint32_t insert = map_get(b, MAP_RESP_INSERT) % MAP_RING_SIZE;
    uint32_t process = map_get(b, MAP_RESP_PROCESS) % MAP_RING_SIZE;
    uint32_t n = (insert + MAP_RING_SIZE - process) % MAP_RING_SIZE, first;
    size_t room = inbox_room(b);
    if (!n || !room || b->map_lost)
        return 0;
    if (n > room)
        n = (uint32_t)room;
    first = n < MAP_RING_SIZE - process ? n : MAP_RING_SIZE - process;
    if (!map_read(b, text, first, MAP_RESP_RING + process) ||
        (n > first && !map_read(b, text + first, n - first, MAP_RESP_RING)))
        return 0;
    inbox_add(b, text, n);
    map_put(b, MAP_RESP_PROCESS, (process + n) % MAP_RING_SIZE);
    if ((process + n) % MAP_RING_SIZE == insert)
        map_put(b, MAP_OMR0, 0);
    return 1;
}
#endif /* OMS_HAVE_MAP */

/* ---- TCP access ---------------------------------------------------------------------- */
static long tcp_write_text(oms_board *b, const char *text, size_t n)
{
    double deadline = now_ms() + (double)b->command_ms;
    while (n) {
#if defined(_WIN32)
        int sent = send(b->sock, text, (int)n, 0);
        if (sent == SOCKET_ERROR) {
            if (WSAGetLastError() != WSAEWOULDBLOCK || now_ms() > deadline)
                return COMMAND_TIME_OUT;
            Sleep(1);
            continue;
        }
#else
        ssize_t sent = send(b->sock, text, n, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (sent < 0) {
            struct pollfd p = {b->sock, POLLOUT, 0};
            if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)
                return COMMAND_TIME_OUT;
            if (now_ms() > deadline)
                return COMMAND_TIME_OUT;
            poll(&p, 1, 10);
            continue;
        }
#endif
        text += sent;
        n -= (size_t)sent;
    }
    return SUCCESS;
}

/* Wait up to `ms` for bytes from the socket; 1 if any came, 0 on time out, -1 closed. */
static int tcp_pull(oms_board *b, long ms)
{
    char buffer[1024];
    long got;
    size_t room = inbox_room(b);
#if defined(_WIN32)
    fd_set readable;
    struct timeval tv = {ms / 1000, (ms % 1000) * 1000};
    FD_ZERO(&readable);
    FD_SET(b->sock, &readable);
    if (!room) /* complete lines fill it: they are taken first */
        return 0;
    if (room > sizeof buffer)
        room = sizeof buffer;
    if (select(0, &readable, NULL, NULL, &tv) <= 0)
        return 0;
    got = recv(b->sock, buffer, (int)room, 0);
#else
    struct pollfd p = {b->sock, POLLIN, 0};
    int ready;
    if (!room) /* complete lines fill it: they are taken first */
        return 0;
    if (room > sizeof buffer)
        room = sizeof buffer;
    ready = poll(&p, 1, (int)ms);
    if (ready <= 0)
        return 0;
    got = (long)recv(b->sock, buffer, room, 0);
#endif
    if (got <= 0)
        return -1;
    inbox_add(b, buffer, (size_t)got); /* never more than the room asked for */
    return 1;
}

/* ---- text in both directions ----------------------------------------------------------- */
static long write_text(oms_board *b, const char *text)
{
    size_t n = strlen(text);
    if (!n)
        return SUCCESS;
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP)
        return map_write_text(b, text, n);
#endif
    return tcp_write_text(b, text, n);
}

static unsigned long parse_hex(const char *text)
{
    return strtoul(text, NULL, 16);
}

/* Take one complete line out of the inbox; 1 if there was one. TCP notifications
 * (`%000 SSSSSSSS`) are folded into b->notified on the way and are not lines. */
static int take_line(oms_board *b, char *line, size_t size)
{
    for (;;) {
        size_t i, start = 0, len;
        char *end;
        while (start < b->inbox_len &&
               (b->inbox[start] == '\r' || b->inbox[start] == '\n' || b->inbox[start] == 0x06))
            start++;
        end = memchr(b->inbox + start, '\n', b->inbox_len - start);
        if (!end) {
            char *cr = memchr(b->inbox + start, '\r', b->inbox_len - start);
            end = cr;
        }
        if (!end) {
            memmove(b->inbox, b->inbox + start, b->inbox_len - start);
            b->inbox_len -= start;
            return 0;
        }
        len = (size_t)(end - (b->inbox + start));
        if (len >= 5 && memcmp(b->inbox + start, "%000 ", 5) == 0) {
            char word[16] = {0};
            memcpy(word, b->inbox + start + 5, len - 5 < 15 ? len - 5 : 15);
            b->notified |= parse_hex(word);
        } else {
            size_t keep = len < size - 1 ? len : size - 1;
            memcpy(line, b->inbox + start, keep);
            line[keep] = 0;
            for (i = keep; i > 0 && (line[i - 1] == ' ' || line[i - 1] == '\r'); i--)
                line[i - 1] = 0;
            start += len + 1;
            memmove(b->inbox, b->inbox + start, b->inbox_len - start);
            b->inbox_len -= start;
            return 1;
        }
        start += len + 1;
        memmove(b->inbox, b->inbox + start, b->inbox_len - start);
        b->inbox_len -= start;
    }
}

static long read_line(oms_board *b, char *line, size_t size)
{
    double deadline = now_ms() + (double)b->response_ms;
    for (;;) {
        if (take_line(b, line, size))
            return SUCCESS;
        if (now_ms() > deadline)
            return RESPONSE_TIME_OUT;
#ifdef OMS_HAVE_MAP
        if (b->transport == OMS_MAP) {
            if (!map_pull(b))
                pause_us(50);
            continue;
        }
#endif
        if (tcp_pull(b, 5) < 0)
            return RESPONSE_TIME_OUT;
    }
}

/* TCP: take in whatever is waiting, without blocking, and fold the notifications among
 * it into b->notified; reply lines stay in the inbox, in order, for their caller. */
static int tcp_drain(oms_board *b)
{
    size_t at = 0;
    int guard = 64, pulled = 0;
    if (b->transport != OMS_TCP)
        return 0;
    while (guard-- > 0 && tcp_pull(b, 0) > 0)
        pulled++;
    while (at < b->inbox_len) {
        char *end = memchr(b->inbox + at, '\n', b->inbox_len - at);
        size_t start = at, len;
        if (!end)
            break;
        while (start < b->inbox_len && (b->inbox[start] == '\r' || b->inbox[start] == 0x06))
            start++;
        len = (size_t)(end - (b->inbox + start));
        if (len >= 5 && memcmp(b->inbox + start, "%000 ", 5) == 0) {
            char word[16] = {0};
            size_t cut = (size_t)(end - b->inbox) + 1;
            memcpy(word, b->inbox + start + 5, len - 5 < 15 ? len - 5 : 15);
            b->notified |= parse_hex(word);
            memmove(b->inbox + at, b->inbox + cut, b->inbox_len - cut);
            b->inbox_len -= cut - at;
        } else {
            at = (size_t)(end - b->inbox) + 1;
        }
    }
    return pulled;
}

/* Before a query: replies nobody waits for any more (a call that timed out, a command
 * text holding two queries, a query sent with SendString) are dropped, so the reply
 * taken next is this query's. Notifications are kept. */
static void discard_replies(oms_board *b)
{
    char scratch[OMS_LINE_MAX];
    int guard = 64; /* the ring and the socket hold a bounded amount: a few passes */
    do {
        while (take_line(b, scratch, sizeof scratch)) {
        }
#ifdef OMS_HAVE_MAP
        if (b->transport == OMS_MAP && !map_pull(b))
            break;
#endif
        if (b->transport == OMS_TCP && !tcp_drain(b))
            break;
    } while (--guard > 0);
    while (take_line(b, scratch, sizeof scratch)) {
    }
}

/* Replies are cut to the 80 bytes the vendor's callers give (DEMO, the ctypes GUI). */
static void copy_reply(char *out, const char *line)
{
    size_t n = strlen(line);
    if (n > OMS_REPLY_MAX - 1)
        n = OMS_REPLY_MAX - 1;
    memcpy(out, line, n);
    out[n] = 0;
}

static long command(oms_board *b, const char *fmt, ...)
{
    char text[OMS_LINE_MAX];
    va_list args;
    int n;
    va_start(args, fmt);
    n = vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    if (n < 0 || (size_t)n >= sizeof text)
        return INVALID_PARAMETER;
    return write_text(b, text);
}

static long query(oms_board *b, char *reply, size_t size, const char *fmt, ...)
{
    char text[OMS_LINE_MAX];
    va_list args;
    int n;
    long rc;
    va_start(args, fmt);
    n = vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    if (n < 0 || (size_t)n >= sizeof text)
        return INVALID_PARAMETER;
    discard_replies(b);
    rc = write_text(b, text);
    return rc != SUCCESS ? rc : read_line(b, reply, size);
}

/* ---- handles --------------------------------------------------------------------------- */
/* A handle is the board's number (1..16) as a pointer: it survives code that keeps it
 * in an int, as ctypes callers do by default (the Windows driver's handles are small
 * numbers too). Handles of one board share its connection and its lock. */
static oms_board *board_of(HANDLE h)
{
    intptr_t n = (intptr_t)h;
    oms_board *b;
    if (n < 1 || n > OMS_BOARDS)
        return NULL;
    registry_lock();
    b = g_boards[n];
    registry_unlock();
    return b;
}

/* Where board N is: MAXK_OMSMAXK<N>, else a line `OmsMAXk<N> = WHERE` in the file named by
 * MAXK_OMS_CONFIG, else ~/.config/maxk/oms.conf, else /etc/maxk/oms.conf, else the map
 * `maxk serve --shm /dev/shm/maxk` makes (board N: /dev/shm/maxk<N> for N > 1).
 * WHERE is `shm:PATH`, `tcp:HOST:PORT` or a bare path (a map). */
static int config_line(const char *path, int number, char *where, size_t size)
{
    FILE *f = fopen(path, "r");
    char line[1024];
    int found = 0;
    if (!f)
        return 0;
    while (!found && fgets(line, sizeof line, f)) {
        char *p = line, *eq, *name_end, *value, *value_end;
        if (!strchr(line, '\n')) {
            /* no line end in the buffer: the line fits exactly, the file ends, or the line
             * is longer than any setting (1,023 characters). That one is skipped whole:
             * its tail is never read as a line of its own (issue 34). */
            int c = fgetc(f);
            if (c != EOF && c != '\n') {
                while (c != EOF && c != '\n')
                    c = fgetc(f);
                continue;
            }
        }
        while (isspace((unsigned char)*p))
            p++;
        if (*p == '#' || *p == ';' || !*p)
            continue;
        eq = strchr(p, '=');
        if (!eq)
            continue;
        name_end = eq;
        while (name_end > p && isspace((unsigned char)name_end[-1]))
            name_end--;
        if (name_end - p < 8 || strncasecmp(p, "OmsMAXk", 7) != 0 ||
            atoi(p + 7) != number)
            continue;
        {
            char *digits = p + 7;
            while (digits < name_end && isdigit((unsigned char)*digits))
                digits++;
            if (digits != name_end)
                continue;
        }
        value = eq + 1;
        while (isspace((unsigned char)*value))
            value++;
        value_end = value + strlen(value);
        while (value_end > value && isspace((unsigned char)value_end[-1]))
            value_end--;
        *value_end = 0;
        snprintf(where, size, "%s", value);
        found = 1;
    }
    fclose(f);
    return found;
}

static int locate(int number, char *where, size_t size)
{
    char name[32];
    const char *env, *home;
    char path[1024];
    snprintf(name, sizeof name, "MAXK_OMSMAXK%d", number);
    env = getenv(name);
    if (env && *env) {
        if (strlen(env) >= size)
            return 0; /* cut short it would name another place: no board */
        snprintf(where, size, "%s", env);
        return 1;
    }
    env = getenv("MAXK_OMS_CONFIG");
    if (env && *env)
        return config_line(env, number, where, size);
    home = getenv("HOME");
    if (home) {
        snprintf(path, sizeof path, "%s/.config/maxk/oms.conf", home);
        if (config_line(path, number, where, size))
            return 1;
    }
    if (config_line("/etc/maxk/oms.conf", number, where, size))
        return 1;
#ifdef OMS_HAVE_MAP
    if (number == 1)
        snprintf(where, size, "shm:/dev/shm/maxk");
    else
        snprintf(where, size, "shm:/dev/shm/maxk%d", number);
    return 1;
#else
    return 0;
#endif
}

#ifdef OMS_HAVE_MAP
/* Whether a map file is served now: its server holds an exclusive lock on it for as long
 * as it runs (docs/shared-memory.md); a shared lock we can take means nobody does. */
static int map_served(int fd)
{
    if (flock(fd, LOCK_SH | LOCK_NB) == 0) {
        flock(fd, LOCK_UN);
        return 0;
    }
    return 1;
}

/* Open the map at `path` if it is a whole map that a server serves; the handle's earlier
 * map (if any) is let go. The file's size is checked before anything is read. */
static int open_map(oms_board *b, const char *path)
{
    struct stat st;
    char tag[4];
    int fd = open(path, O_RDWR | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0)
        return 0;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || (size_t)st.st_size < MAP_SIZE ||
        !map_served(fd) || pread(fd, tag, 4, MAP_LAYOUT) != 4 || memcmp(tag, "MXK1", 4) != 0) {
        close(fd);
        return 0;
    }
    if (b->map_fd >= 0)
        close(b->map_fd);
    b->map_fd = fd;
    b->map_lost = 0;
    if (path != b->map_path)
        snprintf(b->map_path, sizeof b->map_path, "%s", path);
    /* replies left in the ring by an earlier host, or half a line of a server that went
     * away, are not ours */
    b->inbox_len = 0;
    b->skipping = 0;
    map_put(b, MAP_RESP_PROCESS, map_get(b, MAP_RESP_INSERT));
    return !b->map_lost;
}

/* Before every call through the map: the map is whole and served, else the path is
 * looked at again (a server restarted on it: issue 34). COMMAND_TIME_OUT while no
 * server serves a whole map there; the host gets a return code, never a signal. */
static long map_ready(oms_board *b)
{
    struct stat st;
    if (!b->map_lost && fstat(b->map_fd, &st) == 0 && (size_t)st.st_size >= MAP_SIZE &&
        map_served(b->map_fd))
        return SUCCESS;
    return open_map(b, b->map_path) ? SUCCESS : COMMAND_TIME_OUT;
}
#endif

/* connect(), but given up after `ms` (an address that never answers would otherwise
 * hold GetOmsHandle for the system's own limit, minutes). */
static int connect_within(oms_socket s, const struct addrinfo *ai, long ms)
{
#if defined(_WIN32)
    (void)ms;
    return connect(s, ai->ai_addr, (int)ai->ai_addrlen) == 0;
#else
    int flags = fcntl(s, F_GETFL, 0), error = 0;
    socklen_t len = sizeof error;
    struct pollfd p = {s, POLLOUT, 0};
    if (flags < 0 || fcntl(s, F_SETFL, flags | O_NONBLOCK) < 0)
        return 0;
    if (connect(s, ai->ai_addr, ai->ai_addrlen) != 0) {
        if (errno != EINPROGRESS || poll(&p, 1, (int)ms) != 1 ||
            getsockopt(s, SOL_SOCKET, SO_ERROR, &error, &len) != 0 || error != 0)
            return 0;
    }
    return fcntl(s, F_SETFL, flags) == 0;
#endif
}

static int open_tcp(oms_board *b, const char *where)
{
    char host[256];
    const char *colon = strrchr(where, ':');
    struct addrinfo hints, *found = NULL, *ai;
    oms_socket s = OMS_BAD_SOCKET;
    if (!colon || (size_t)(colon - where) >= sizeof host)
        return 0;
    memcpy(host, where, (size_t)(colon - where));
    host[colon - where] = 0;
#if defined(_WIN32)
    {
        WSADATA data;
        WSAStartup(MAKEWORD(2, 2), &data);
    }
#endif
    memset(&hints, 0, sizeof hints);
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    if (getaddrinfo(host, colon + 1, &hints, &found) != 0)
        return 0;
    for (ai = found; ai; ai = ai->ai_next) {
        s = socket(ai->ai_family, ai->ai_socktype, ai->ai_protocol);
        if (s == OMS_BAD_SOCKET)
            continue;
        if (connect_within(s, ai, env_ms("MAXK_OMS_COMMAND_TIMEOUT_MS", 2000)))
            break;
        oms_close_socket(s);
        s = OMS_BAD_SOCKET;
    }
    freeaddrinfo(found);
    if (s == OMS_BAD_SOCKET)
        return 0;
    {
        int one = 1;
        setsockopt(s, IPPROTO_TCP, TCP_NODELAY, (const char *)&one, sizeof one);
#ifdef SO_NOSIGPIPE
        setsockopt(s, SOL_SOCKET, SO_NOSIGPIPE, (const char *)&one, sizeof one);
#endif
    }
    b->sock = s;
    return 1;
}

static oms_board *open_board(int number)
{
    char where[1024];
    oms_board *b;
    if (!locate(number, where, sizeof where))
        return NULL;
    b = (oms_board *)calloc(1, sizeof *b);
    if (!b)
        return NULL;
    b->number = number;
    b->sock = OMS_BAD_SOCKET;
    b->map_fd = -1;
    b->buffer_mode = OMS_NORMAL_CMD_BUFFER_MODE;
    b->command_ms = env_ms("MAXK_OMS_COMMAND_TIMEOUT_MS", 2000);
    b->response_ms = env_ms("MAXK_OMS_RESPONSE_TIMEOUT_MS", 2000);
    if (strncmp(where, "tcp:", 4) == 0) {
        char line[OMS_LINE_MAX];
        if (open_tcp(b, where + 4)) {
            /* something answers there: a MAX board says so to WY (a port of anything
             * else is no board) */
            b->transport = OMS_TCP;
            if (query(b, line, sizeof line, "WY;") != SUCCESS || strncmp(line, "MAX", 3) != 0) {
                oms_close_socket(b->sock);
                b->transport = 0;
            }
        }
    }
#ifdef OMS_HAVE_MAP
    else if (strlen(where) < sizeof b->map_path &&
             open_map(b, strncmp(where, "shm:", 4) == 0 ? where + 4 : where)) {
        b->transport = OMS_MAP;
    }
#endif
    if (!b->transport) {
        free(b);
        return NULL;
    }
    oms_mutex_init(&b->lock);
    return b;
}

static int board_number(const char *name)
{
    const char *p = name;
    char *end;
    long n;
    if (!p)
        return 0;
    if (strncmp(p, "\\\\.\\", 4) == 0) /* the driver's device path, \\.\OmsMAXk1 */
        p += 4;
    if (strncasecmp(p, "OmsMAXk", 7) != 0 || !isdigit((unsigned char)p[7]))
        return 0;
    n = strtol(p + 7, &end, 10);
    if (*end || n < 1 || n > OMS_BOARDS)
        return 0;
    return (int)n;
}

HANDLE _stdcall GetOmsHandle(LPSTR name)
{
    int number = board_number(name);
    oms_board *b;
    if (!number)
        return NULL;
    registry_lock();
    b = g_boards[number];
    if (!b) {
        b = open_board(number);
        g_boards[number] = b;
    }
    if (b)
        b->refs++;
    registry_unlock();
    return b ? (HANDLE)(intptr_t)number : NULL;
}

void _stdcall CloseOmsHandle(HANDLE h)
{
    intptr_t n = (intptr_t)h;
    oms_board *b;
    if (n < 1 || n > OMS_BOARDS)
        return;
    registry_lock();
    b = g_boards[n];
    if (!b || --b->refs > 0) {
        registry_unlock();
        return;
    }
    g_boards[n] = NULL;
    registry_unlock();
    oms_mutex_lock(&b->lock); /* a call still running on another thread ends first */
    oms_mutex_unlock(&b->lock);
#ifdef OMS_HAVE_MAP
    if (b->map_fd >= 0)
        close(b->map_fd);
#endif
    if (b->sock != OMS_BAD_SOCKET)
        oms_close_socket(b->sock);
    oms_mutex_destroy(&b->lock);
    free(b);
}

/* The board's connection is usable (the map: whole and served; TCP: as it is). */
static long board_ready(oms_board *b)
{
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP)
        return map_ready(b);
#endif
    (void)b;
    return SUCCESS;
}

/* Every call takes the board for its whole exchange. */
#define BEGIN(h)                                                                         \
    oms_board *b = board_of(h);                                                          \
    long rc = SUCCESS;                                                                   \
    if (!b)                                                                              \
        return COMMAND_TIME_OUT;                                                         \
    oms_mutex_lock(&b->lock);                                                            \
    CHECK(board_ready(b));
#define END                                                                              \
    if (rc == SUCCESS && b->map_lost) /* what was read of a map cut short is no answer */ \
        rc = COMMAND_TIME_OUT;                                                           \
    oms_mutex_unlock(&b->lock);                                                          \
    return rc;
#define CHECK(call)                                                                      \
    do {                                                                                 \
        rc = (call);                                                                     \
        if (rc != SUCCESS)                                                               \
            goto done;                                                                   \
    } while (0)

/* A call's argument refused with the API's own code, before anything changes. */
#define REFUSE_IF(condition, code)                                                       \
    do {                                                                                 \
        if (condition) {                                                                 \
            rc = (code);                                                                 \
            goto done;                                                                   \
        }                                                                                \
    } while (0)

/* ---- axis masks ---------------------------------------------------------------------- */
static int single_axis(long mask)
{
    int i;
    for (i = 0; i < OMS_AXES; i++)
        if (mask == (1L << i))
            return i;
    return -1;
}

static int valid_axes(long mask) { return mask > 0 && (mask & ~(long)OMS_ALL_AXES) == 0; }

static long axes_value(const AXES_DATA *d, int i)
{
    const long *v = &d->X;
    return v[i];
}

static void axes_set(AXES_DATA *d, int i, long value)
{
    long *v = &d->X;
    v[i] = value;
}

static int valid_velocity(long v) { return v >= MIN_VELOCITY && v <= MAX_VELOCITY; }
static int valid_acceleration(long a) { return a >= MIN_ACCELERATION && a <= MAX_ACCELERATION; }

/* ---- general ----------------------------------------------------------------------------- */
long _stdcall ResetOmsController(HANDLE h)
{
    BEGIN(h)
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        map_put(b, MAP_DIRECT_MAILBOX, DIRECT_RESET);
        rc = map_mailbox_wait(b, MAP_DIRECT_MAILBOX, DIRECT_RESET, b->command_ms);
        if (rc == SUCCESS) /* the board answers again once power-up initialization ran */
            rc = map_mailbox_wait(b, MAP_FIRMWARE_FLAGS, 0xFFFFFFFFu, b->command_ms);
        b->inbox_len = 0;
        map_put(b, MAP_RESP_PROCESS, map_get(b, MAP_RESP_INSERT));
        goto done;
    }
#endif
    /* no mailbox over TCP: the reset command (RS) of the command language */
    CHECK(command(b, "RS;"));
    b->notified = 0;
done:
    END
}

static long send_and_get(HANDLE h, LPSTR cmd, LPSTR reply)
{
    char line[OMS_LINE_MAX];
    BEGIN(h)
    REFUSE_IF(!cmd || !reply, INVALID_PARAMETER);
    reply[0] = 0;
    discard_replies(b);
    CHECK(write_text(b, cmd));
    /* a command without its terminator still runs: the board ends it at the separator */
    if (cmd[0] && !strchr(";\r\n", cmd[strlen(cmd) - 1]))
        CHECK(write_text(b, ";"));
    CHECK(read_line(b, line, sizeof line));
    copy_reply(reply, line);
done:
    END
}

long _stdcall SendOmsQueryCommand(HANDLE h, LPSTR cmd, LPSTR reply) { return send_and_get(h, cmd, reply); }
long _stdcall SendAndGetString(HANDLE h, LPSTR cmd, LPSTR reply) { return send_and_get(h, cmd, reply); }

static long send_only(HANDLE h, LPSTR cmd)
{
    BEGIN(h)
    REFUSE_IF(!cmd, INVALID_PARAMETER);
    CHECK(write_text(b, cmd));
done:
    END
}

long _stdcall SendOmsTextCommand(HANDLE h, LPSTR cmd) { return send_only(h, cmd); }
long _stdcall SendString(HANDLE h, LPSTR cmd) { return send_only(h, cmd); }

long _stdcall GetCmdBufferFree(HANDLE h)
{
    oms_board *b = board_of(h);
    long free_bytes = 0;
    if (!b)
        return 0;
    oms_mutex_lock(&b->lock);
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP && map_ready(b) != SUCCESS) {
        free_bytes = 0; /* nothing serves the map: no room */
    } else if (b->transport == OMS_MAP) {
        uint32_t insert = map_get(b, MAP_CMD_INSERT) % MAP_RING_SIZE;
        uint32_t process = map_get(b, MAP_CMD_PROCESS) % MAP_RING_SIZE;
        free_bytes = (long)((process + MAP_RING_SIZE - insert - 1u) % MAP_RING_SIZE);
    } else
#endif
        free_bytes = MAP_RING_SIZE - 1; /* the TCP door takes text as it comes */
    oms_mutex_unlock(&b->lock);
    return free_bytes;
}

long _stdcall GetOmsControllerDescription(HANDLE h, LPSTR text)
{
    char line[OMS_LINE_MAX];
    BEGIN(h)
    REFUSE_IF(!text, INVALID_PARAMETER);
    text[0] = 0;
    CHECK(query(b, line, sizeof line, "WY;"));
    copy_reply(text, line);
done:
    END
}

void _stdcall GetOmsDriverVersion(HANDLE h, LPSTR text)
{
    (void)h;
    if (text)
        snprintf(text, OMS_REPLY_MAX, "%s", OMS_DRIVER_VERSION);
}

void _stdcall GetOmsDllVersion(LPSTR text, long size)
{
    if (text && size > 0)
        snprintf(text, (size_t)size, "%s", OMS_LIBRARY_VERSION);
}

long _stdcall OmsWait(long ms)
{
    if (ms > 0)
        pause_us(ms * 1000L);
    return SUCCESS;
}

/* ---- flags ------------------------------------------------------------------------------- */
/* Per-axis latched flags: bit 0 done, 1 overtravel, 2 slip (the map's W/K layout). */
static long axis_flag_bits(oms_board *b, unsigned out[OMS_AXES], unsigned long *command_error)
{
    int i;
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        uint32_t odbr = map_get(b, MAP_ODBR);
        for (i = 0; i < 8; i++)
            out[i] = ((odbr >> i) & 1u) | (((odbr >> (8 + i)) & 1u) << 1) |
                     (((odbr >> (16 + i)) & 1u) << 2);
        out[8] = map_get(b, MAP_STATUS_WK) & 7u;
        out[9] = map_get(b, MAP_STATUS_WK + 4) & 7u;
        if (command_error)
            *command_error = (odbr & ODBR_COMMAND_ERROR) ? 1 : 0;
        return SUCCESS;
    }
#endif
    tcp_drain(b);
    for (i = 0; i < 8; i++)
        out[i] = ((b->notified >> i) & 1u) | (((b->notified >> (8 + i)) & 1u) << 1) |
                 (((b->notified >> (16 + i)) & 1u) << 2);
    /* MAXnet word: W done 25, K done 26, W overtravel 27, K 28, W slip 29, K 30 */
    out[8] = ((b->notified >> 25) & 1u) | (((b->notified >> 27) & 1u) << 1) |
             (((b->notified >> 29) & 1u) << 2);
    out[9] = ((b->notified >> 26) & 1u) | (((b->notified >> 28) & 1u) << 1) |
             (((b->notified >> 30) & 1u) << 2);
    if (command_error)
        *command_error = (b->notified & ODBR_COMMAND_ERROR) ? 1 : 0;
    return SUCCESS;
}

/* Clear latched flags (bit 0 done, 1 overtravel, 2 slip) of the masked axes. The map's
 * clear mailbox takes X..S bit by bit; W and K have one notify bit each, so their done
 * flags are cleared with the command language's CA, their other flags with the bit. */
static long clear_axis_flags(oms_board *b, long axes, unsigned kinds)
{
    int i;
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        uint32_t mask = 0;
        long rc;
        int texted = 0;
        for (i = 0; i < 8; i++)
            if (axes & (1L << i)) {
                if (kinds & 1u)
                    mask |= 1u << i;
                if (kinds & 2u)
                    mask |= 1u << (8 + i);
                if (kinds & 4u)
                    mask |= 1u << (16 + i);
            }
        for (i = 8; i < 10; i++)
            if (axes & (1L << i)) {
                if (kinds & 6u)
                    mask |= i == 8 ? ODBR_W_NOTIFY : ODBR_K_NOTIFY;
                else if ((rc = command(b, "A%cCA;", AXIS_LETTERS[i])) != SUCCESS)
                    return rc;
                else
                    texted = 1;
            }
        if (!mask)
            return texted ? map_sync(b, b->command_ms) : SUCCESS;
        if ((rc = map_mailbox_wait(b, MAP_ODBR_CLEAR, 0, b->command_ms)) != SUCCESS)
            return rc;
        map_put(b, MAP_ODBR_CLEAR, mask);
        if ((rc = map_mailbox_wait(b, MAP_ODBR_CLEAR, 0, b->command_ms)) != SUCCESS)
            return rc;
        return map_settle(b, b->command_ms);
    }
#endif
    tcp_drain(b);
    for (i = 0; i < OMS_AXES; i++) {
        if (!(axes & (1L << i)))
            continue;
        if (i < 8) {
            if (kinds & 1u)
                b->notified &= ~(1UL << i);
            if (kinds & 2u)
                b->notified &= ~(1UL << (8 + i));
            if (kinds & 4u)
                b->notified &= ~(1UL << (16 + i));
        } else {
            if (kinds & 1u)
                b->notified &= ~(1UL << (17 + i));
            if (kinds & 2u)
                b->notified &= ~(1UL << (19 + i));
            if (kinds & 4u)
                b->notified &= ~(1UL << (21 + i));
        }
        if (kinds & 6u) {
            /* the board's overtravel and slip flags clear with RA (which clears its done
             * flag too: decision D in docs/oms-library.md); a later event notifies again */
            char line[OMS_LINE_MAX];
            long rc = query(b, line, sizeof line, "A%cRA;", AXIS_LETTERS[i]);
            if (rc != SUCCESS)
                return rc;
            tcp_drain(b);
            b->notified &= ~(i < 8 ? (1UL << i) | (1UL << (8 + i)) | (1UL << (16 + i))
                                   : (1UL << (17 + i)) | (1UL << (19 + i)) | (1UL << (21 + i)));
        } else if (kinds & 1u) {
            /* CA, then QA: its reply comes after any done notification already on its way,
             * so what arrives after it is news */
            char line[OMS_LINE_MAX];
            long rc = query(b, line, sizeof line, "A%cCA;QA;", AXIS_LETTERS[i]);
            if (rc != SUCCESS)
                return rc;
            b->notified &= ~(i < 8 ? 1UL << i : 1UL << (17 + i));
        }
    }
    return SUCCESS;
}

static long flags_mask(HANDLE h, long *out, unsigned kind)
{
    unsigned bits[OMS_AXES];
    int i;
    BEGIN(h)
    REFUSE_IF(!out, INVALID_PARAMETER);
    CHECK(axis_flag_bits(b, bits, NULL));
    *out = 0;
    for (i = 0; i < OMS_AXES; i++)
        if (bits[i] & kind)
            *out |= 1L << i;
done:
    END
}

long _stdcall GetDoneFlags(HANDLE h, long *axes) { return flags_mask(h, axes, 1u); }
long _stdcall GetAllOmsDoneFlags(HANDLE h, long *axes) { return flags_mask(h, axes, 1u); }
long _stdcall GetSlipFlags(HANDLE h, long *axes) { return flags_mask(h, axes, 4u); }
long _stdcall GetAllOmsSlipFlags(HANDLE h, long *axes) { return flags_mask(h, axes, 4u); }

static long axis_flag(HANDLE h, long axis, BOOL *out, unsigned kind)
{
    unsigned bits[OMS_AXES];
    int i = single_axis(axis);
    BEGIN(h)
    REFUSE_IF(i < 0, INVALID_AXIS_SELECTION);
    REFUSE_IF(!out, INVALID_PARAMETER);
    CHECK(axis_flag_bits(b, bits, NULL));
    *out = (bits[i] & kind) ? TRUE : FALSE;
done:
    END
}

long _stdcall GetOmsAxisDoneFlag(HANDLE h, long axis, BOOL *done) { return axis_flag(h, axis, done, 1u); }
long _stdcall GetOmsAxisSlipFlag(HANDLE h, long axis, BOOL *s) { return axis_flag(h, axis, s, 4u); }

static long clear_flags(HANDLE h, long axes, unsigned kind)
{
    BEGIN(h)
    REFUSE_IF(!valid_axes(axes), INVALID_AXIS_SELECTION);
    CHECK(clear_axis_flags(b, axes, kind));
done:
    END
}

long _stdcall ClrDoneFlags(HANDLE h, long axes) { return clear_flags(h, axes, 1u); }
long _stdcall ClrOmsDoneFlags(HANDLE h, long axes) { return clear_flags(h, axes, 1u); }
long _stdcall ClrSlipFlags(HANDLE h, long axes) { return clear_flags(h, axes, 4u); }
long _stdcall ClrOmsSlipFlags(HANDLE h, long axes) { return clear_flags(h, axes, 4u); }

/* The live limit switches in the library's layout: minus X..K bits 0..9, plus 10..19.
 * The map's word (Table 3-2) has minus X..S in bits 0..7, plus in 8..15, W/K minus in
 * 16/17 and plus in 24/25; QL over TCP has the same layout. */
static long limit_sensors(oms_board *b, long *out)
{
    unsigned long word;
    int i;
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        word = map_get(b, MAP_LIMIT_WORD);
    } else
#endif
    {
        char line[OMS_LINE_MAX];
        long rc = query(b, line, sizeof line, "QL;");
        if (rc != SUCCESS)
            return rc;
        word = parse_hex(line);
        /* QL reports raw levels: with limits active low an inactive input reads 1 */
        rc = query(b, line, sizeof line, "AX;LT?;");
        if (rc != SUCCESS)
            return rc;
        if (strchr(line, 'l') || strchr(line, 'L'))
            word = ~word & 0x030300FFFFUL;
    }
    *out = 0;
    for (i = 0; i < 8; i++) {
        if (word & (1UL << i))
            *out |= 1L << i;
        if (word & (1UL << (8 + i)))
            *out |= 1L << (10 + i);
    }
    for (i = 0; i < 2; i++) {
        if (word & (1UL << (16 + i)))
            *out |= 1L << (8 + i);
        if (word & (1UL << (24 + i)))
            *out |= 1L << (18 + i);
    }
    return SUCCESS;
}

/* Latched overtravel flags as limit bits: the side is the switch active now, else the
 * side the axis was travelling to (QA's direction letter). */
static long limit_flags(oms_board *b, long *out)
{
    unsigned bits[OMS_AXES];
    long sensors = 0, rc;
    int i;
    if ((rc = axis_flag_bits(b, bits, NULL)) != SUCCESS)
        return rc;
    *out = 0;
    for (i = 0; i < OMS_AXES; i++) {
        if (!(bits[i] & 2u))
            continue;
        if (!sensors && (rc = limit_sensors(b, &sensors)) != SUCCESS)
            return rc;
        if (sensors & ((1L << i) | (1L << (10 + i)))) {
            *out |= sensors & ((1L << i) | (1L << (10 + i)));
        } else {
            char line[OMS_LINE_MAX];
            if ((rc = query(b, line, sizeof line, "A%cQA;", AXIS_LETTERS[i])) != SUCCESS)
                return rc;
            *out |= line[0] == 'M' ? (1L << i) : (1L << (10 + i));
        }
    }
    return SUCCESS;
}

static long get_limit_flags(HANDLE h, long *out)
{
    BEGIN(h)
    REFUSE_IF(!out, INVALID_PARAMETER);
    CHECK(limit_flags(b, out));
done:
    END
}

long _stdcall GetLimitFlags(HANDLE h, long *limits) { return get_limit_flags(h, limits); }
long _stdcall GetAllOmsLimitFlags(HANDLE h, long *limits) { return get_limit_flags(h, limits); }

long _stdcall GetOmsAxisLimitFlag(HANDLE h, long axis, BOOL *limit) { return axis_flag(h, axis, limit, 2u); }

static long clear_limits(HANDLE h, long limits)
{
    long axes = (limits | (limits >> 10)) & OMS_ALL_AXES;
    BEGIN(h)
    REFUSE_IF(limits <= 0 || (limits & ~0xFFFFFL), INVALID_AXIS_SELECTION);
    CHECK(clear_axis_flags(b, axes, 2u));
done:
    END
}

long _stdcall ClrLimitFlags(HANDLE h, long limits) { return clear_limits(h, limits); }
long _stdcall ClrOmsLimitFlags(HANDLE h, long limits) { return clear_limits(h, limits); }

static long status_flags(HANDLE h, long *out)
{
    unsigned bits[OMS_AXES];
    unsigned long error = 0;
    BEGIN(h)
    REFUSE_IF(!out, INVALID_PARAMETER);
    CHECK(axis_flag_bits(b, bits, &error));
    *out = error ? COMMAND_ERROR : 0;
done:
    END
}

long _stdcall GetStatusFlags(HANDLE h, long *status) { return status_flags(h, status); }
long _stdcall GetOmsControllerFlags(HANDLE h, long *status) { return status_flags(h, status); }

static long clear_status(HANDLE h, long status)
{
    BEGIN(h)
    if (!(status & COMMAND_ERROR))
        goto done;
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        CHECK(map_mailbox_wait(b, MAP_ODBR_CLEAR, 0, b->command_ms));
        map_put(b, MAP_ODBR_CLEAR, ODBR_COMMAND_ERROR);
        CHECK(map_mailbox_wait(b, MAP_ODBR_CLEAR, 0, b->command_ms));
        CHECK(map_settle(b, b->command_ms));
        goto done;
    }
#endif
    /* TCP has no clear word: the library forgets the notification; the board's own
     * flag stays for the hosts that read it (decision recorded in docs/oms-library.md) */
    tcp_drain(b);
    b->notified &= ~(unsigned long)ODBR_COMMAND_ERROR;
done:
    END
}

long _stdcall ClrStatusFlags(HANDLE h, long status) { return clear_status(h, status); }
long _stdcall ClrOmsControllerFlags(HANDLE h, long status) { return clear_status(h, status); }

long _stdcall GetOmsAxisFlags(HANDLE h, long axis, long *flags)
{
    char line[OMS_LINE_MAX];
    unsigned bits[OMS_AXES];
    int i = single_axis(axis);
    BEGIN(h)
    REFUSE_IF(i < 0, INVALID_AXIS_SELECTION);
    REFUSE_IF(!flags, INVALID_PARAMETER);
    /* QA: direction P/M, done D/N, overtravel L/N, home H/N (leaves the flags set) */
    CHECK(query(b, line, sizeof line, "A%cQA;", AXIS_LETTERS[i]));
    CHECK(axis_flag_bits(b, bits, NULL));
    *flags = 0;
    if (line[0] == 'M')
        *flags |= AXIS_DIRECTION;
    if (line[1] == 'D' || (bits[i] & 1u))
        *flags |= AXIS_DONE;
    if (line[2] == 'L' || (bits[i] & 2u))
        *flags |= AXIS_OVERTRAVEL;
    if (line[3] == 'H')
        *flags |= AXIS_HOME_SWITCH;
done:
    END
}

long _stdcall GetOmsLimitSensors(HANDLE h, long *limits)
{
    BEGIN(h)
    REFUSE_IF(!limits, INVALID_PARAMETER);
    CHECK(limit_sensors(b, limits));
done:
    END
}

long _stdcall GetOmsHomeSensors(HANDLE h, long *axes)
{
    BEGIN(h)
    REFUSE_IF(!axes, INVALID_PARAMETER);
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        *axes = (long)(map_get(b, MAP_HOME_WORD) & OMS_ALL_AXES);
        goto done;
    }
#endif
    {
        char line[OMS_LINE_MAX];
        const char *p = line;
        int i;
        CHECK(query(b, line, sizeof line, "AM;QA;"));
        *axes = 0;
        for (i = 0; i < OMS_AXES && p && *p; i++) {
            if (strlen(p) >= 4 && p[3] == 'H')
                *axes |= 1L << i;
            p = strchr(p, ',');
            if (p)
                p++;
        }
    }
done:
    END
}

/* ---- moves ------------------------------------------------------------------------------- */
/* Wait for the done flags of `axes` (set by the move's ID), up to `ms` of real time.
 * Through the map: the board has taken the move once its process index passes it and a
 * later update has refreshed the registers (the tick counter moves); then the doorbell
 * image tells. Over TCP: QA tells the state after the move was queued, and the done
 * notifications that follow it tell the rest. */
static long wait_done(oms_board *b, long axes, long ms)
{
    double deadline = now_ms() + (double)(ms < 0 ? 0 : ms);
    unsigned bits[OMS_AXES];
    long pending = axes, rc;
    int i;
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        if (map_sync(b, ms < 0 ? 0 : ms) != SUCCESS)
            return MOVE_TIME_OUT;
        for (;;) {
            axis_flag_bits(b, bits, NULL);
            for (i = 0; i < OMS_AXES; i++)
                if (bits[i] & 1u)
                    pending &= ~(1L << i);
            if (!pending)
                return SUCCESS;
            if (now_ms() > deadline)
                return MOVE_TIME_OUT;
            pause_us(200);
        }
    }
#endif
    for (i = 0; i < OMS_AXES; i++) {
        char line[OMS_LINE_MAX];
        if (!(axes & (1L << i)))
            continue;
        if ((rc = query(b, line, sizeof line, "A%cQA;", AXIS_LETTERS[i])) != SUCCESS)
            return rc;
        /* QA tells the state now: a done notification taken in before its reply is an
         * earlier move's, still on its way when the flag was cleared */
        b->notified &= ~(i < 8 ? 1UL << i : 1UL << (17 + i));
        if (line[1] == 'D')
            pending &= ~(1L << i);
    }
    for (;;) {
        axis_flag_bits(b, bits, NULL);
        for (i = 0; i < OMS_AXES; i++)
            if (bits[i] & 1u)
                pending &= ~(1L << i);
        if (!pending)
            return SUCCESS;
        {
            double left = deadline - now_ms();
            if (left <= 0)
                return MOVE_TIME_OUT;
            if (tcp_pull(b, left > 20 ? 20 : (long)left + 1) < 0)
                return RESPONSE_TIME_OUT;
        }
    }
}

/* Clear the done flags of the axes about to move, send the move, wait if asked. */
static long move(HANDLE h, long axes, const char *text, int wait, long ms)
{
    BEGIN(h)
    CHECK(clear_axis_flags(b, axes, 1u));
    CHECK(write_text(b, text));
    if (wait)
        CHECK(wait_done(b, axes, ms));
done:
    END
}

static long single_move(HANDLE h, long axis, const char *op, long value, int wait, long ms)
{
    char text[128];
    int i = single_axis(axis);
    if (i < 0)
        return INVALID_AXIS_SELECTION;
    if (wait && ms < 0)
        return INVALID_PARAMETER;
    snprintf(text, sizeof text, "A%c%s%ld;GDID", AXIS_LETTERS[i], op, value);
    return move(h, axis, text, wait, ms);
}

long _stdcall MoveOmsAxisAbs(HANDLE h, long axis, long pos) { return single_move(h, axis, "MA", pos, 0, 0); }
long _stdcall MoveOmsAxisAbsWait(HANDLE h, long axis, long pos, long ms) { return single_move(h, axis, "MA", pos, 1, ms); }
long _stdcall MoveOmsAxisRel(HANDLE h, long axis, long dist) { return single_move(h, axis, "MR", dist, 0, 0); }
long _stdcall MoveOmsAxisRelWait(HANDLE h, long axis, long dist, long ms) { return single_move(h, axis, "MR", dist, 1, ms); }

static long simple(HANDLE h, const char *text)
{
    BEGIN(h)
    CHECK(write_text(b, text));
done:
    END
}

/* One-axis command from a template `A%c...`; checks the mask. */
static long axis_command(HANDLE h, long axis, const char *fmt, ...)
{
    char text[256], body[200];
    va_list args;
    int i = single_axis(axis);
    if (i < 0)
        return INVALID_AXIS_SELECTION;
    va_start(args, fmt);
    vsnprintf(body, sizeof body, fmt, args);
    va_end(args);
    snprintf(text, sizeof text, "A%c%s", AXIS_LETTERS[i], body);
    return simple(h, text);
}

long _stdcall MoveOmsAxisIndefinite(HANDLE h, long axis, long velocity)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (velocity < -MAX_VELOCITY || velocity > MAX_VELOCITY)
        return INVALID_PARAMETER;
    return axis_command(h, axis, "JG%ld;", velocity);
}

long _stdcall MoveOmsAxisFractional(HANDLE h, long axis, double velocity)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (!(velocity >= -MAX_VELOCITY && velocity <= MAX_VELOCITY))
        return INVALID_PARAMETER;
    return axis_command(h, axis, "JF%f;", velocity);
}

long _stdcall MoveOmsAxisOneStep(HANDLE h, long axis, long direction)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (direction != POSITIVE && direction != NEGATIVE)
        return INVALID_PARAMETER;
    return axis_command(h, axis, direction == POSITIVE ? "MPMO;" : "MMMO;");
}

/* Several axes: `AA` (or `AM` for the Mt variants), the operation, one comma field per
 * axis up to the last masked one (empty fields leave an axis alone), GD, ID. */
static long multi_move(HANDLE h, long axes, PAXES_DATA data, const char *mode, const char *op,
                       int wait, long ms)
{
    char text[512];
    size_t n;
    int i, last = -1;
    if (!valid_axes(axes))
        return INVALID_AXIS_SELECTION;
    if (!data || (wait && ms < 0))
        return INVALID_PARAMETER;
    for (i = 0; i < OMS_AXES; i++)
        if (axes & (1L << i))
            last = i;
    n = (size_t)snprintf(text, sizeof text, "%s%s", mode, op);
    for (i = 0; i <= last; i++) {
        if (i)
            text[n++] = ',';
        if (axes & (1L << i))
            n += (size_t)snprintf(text + n, sizeof text - n, "%ld", axes_value(data, i));
    }
    snprintf(text + n, sizeof text - n, ";GDID");
    return move(h, axes, text, wait, ms);
}

#define MULTI(name, mode, op)                                                              \
    long _stdcall name(HANDLE h, long axes, PAXES_DATA d) { return multi_move(h, axes, d, mode, op, 0, 0); } \
    long _stdcall name##Wait(HANDLE h, long axes, PAXES_DATA d, long ms) { return multi_move(h, axes, d, mode, op, 1, ms); }
MULTI(MoveOmsIndependentAbs, "AA", "MA")
MULTI(MoveOmsIndependentRel, "AA", "MR")
MULTI(MoveOmsLinearAbs, "AA", "MT")
MULTI(MoveOmsLinearRel, "AA", "ML")
MULTI(MoveOmsIndependentAbsMt, "AM", "MA")
MULTI(MoveOmsIndependentRelMt, "AM", "MR")
MULTI(MoveOmsLinearAbsMt, "AM", "MT")
MULTI(MoveOmsLinearRelMt, "AM", "ML")

long _stdcall StopOmsAxis(HANDLE h, long axis) { return axis_command(h, axis, "ST;"); }
long _stdcall StopAllOmsAxes(HANDLE h) { return simple(h, "AA;SA;"); }

long _stdcall KillAllOmsMotion(HANDLE h)
{
    BEGIN(h)
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        /* the manual's one direct command, through the mailbox, not the text ring */
        map_put(b, MAP_DIRECT_MAILBOX, DIRECT_KILL_ALL);
        CHECK(map_mailbox_wait(b, MAP_DIRECT_MAILBOX, DIRECT_KILL_ALL, b->command_ms));
        goto done;
    }
#endif
    CHECK(write_text(b, "AA;KL;"));
done:
    END
}

/* ---- positions --------------------------------------------------------------------------- */
enum { POS_MOTOR, POS_ENCODER, POS_ABSOLUTE };

/* Read the positions of `axes` into values[]: from the map's registers, or with one
 * comma-list report over TCP. */
static long read_positions(oms_board *b, long axes, int kind, long values[OMS_AXES])
{
    int i;
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        /* one read of the registers (the first 0xC0 bytes hold every motor and encoder
         * position, X..S and W K; the absolute positions are a block of their own) */
        unsigned char block[0xC0];
        unsigned base = kind == POS_ABSOLUTE ? MAP_ABSOLUTE_ENCODERS : 0u;
        if (!map_read(b, block, kind == POS_ABSOLUTE ? 4u * OMS_AXES : sizeof block, base))
            return COMMAND_TIME_OUT;
        for (i = 0; i < OMS_AXES; i++)
            if (axes & (1L << i)) {
                unsigned at = (kind == POS_MOTOR     ? motor_offset(i)
                               : kind == POS_ENCODER ? encoder_offset(i)
                                                     : base + 4u * (unsigned)i) - base;
                values[i] = (long)(int32_t)((uint32_t)block[at] << 24 |
                                            (uint32_t)block[at + 1] << 16 |
                                            (uint32_t)block[at + 2] << 8 | block[at + 3]);
            }
        return SUCCESS;
    }
#endif
    {
        char line[OMS_LINE_MAX];
        const char *p = line;
        long rc;
        int single = single_axis(axes);
        if (single >= 0) {
            rc = query(b, line, sizeof line, "A%c%s;", AXIS_LETTERS[single],
                       kind == POS_MOTOR ? "RP" : "RE");
            if (rc != SUCCESS)
                return rc;
            values[single] = strtol(line, NULL, 10);
            return SUCCESS;
        }
        rc = query(b, line, sizeof line, kind == POS_MOTOR ? "AM;PP;" : "AM;PE;");
        if (rc != SUCCESS)
            return rc;
        for (i = 0; i < OMS_AXES; i++) {
            long v = (p && *p && *p != ',') ? strtol(p, NULL, 10) : 0;
            if (axes & (1L << i))
                values[i] = v;
            p = p ? strchr(p, ',') : NULL;
            if (p)
                p++;
        }
        return SUCCESS;
    }
}

static long axis_position(HANDLE h, long axis, long *out, int kind)
{
    long values[OMS_AXES];
    int i = single_axis(axis);
    BEGIN(h)
    REFUSE_IF(i < 0, INVALID_AXIS_SELECTION);
    REFUSE_IF(!out, INVALID_PARAMETER);
    CHECK(read_positions(b, axis, kind, values));
    *out = values[i];
done:
    END
}

long _stdcall GetOmsAxisMotorPosition(HANDLE h, long axis, long *p) { return axis_position(h, axis, p, POS_MOTOR); }
long _stdcall GetOmsAxisEncoderPosition(HANDLE h, long axis, long *p) { return axis_position(h, axis, p, POS_ENCODER); }
long _stdcall GetOmsAxisAbsoluteEncoderPosition(HANDLE h, long axis, long *p) { return axis_position(h, axis, p, POS_ABSOLUTE); }

static long positions(HANDLE h, long axes, PAXES_DATA data, int kind)
{
    long values[OMS_AXES];
    int i;
    BEGIN(h)
    REFUSE_IF(!valid_axes(axes), INVALID_AXIS_SELECTION);
    REFUSE_IF(!data, INVALID_PARAMETER);
    CHECK(read_positions(b, axes, kind, values));
    for (i = 0; i < OMS_AXES; i++)
        if (axes & (1L << i))
            axes_set(data, i, values[i]);
done:
    END
}

long _stdcall GetSelectedOmsMotorPositions(HANDLE h, long axes, PAXES_DATA d) { return positions(h, axes, d, POS_MOTOR); }
long _stdcall GetSelectedOmsEncoderPositions(HANDLE h, long axes, PAXES_DATA d) { return positions(h, axes, d, POS_ENCODER); }
long _stdcall GetMotorPositions(HANDLE h, PAXES_DATA d) { return positions(h, OMS_ALL_AXES, d, POS_MOTOR); }
long _stdcall GetEncoderPositions(HANDLE h, PAXES_DATA d) { return positions(h, OMS_ALL_AXES, d, POS_ENCODER); }
long _stdcall GetAbsoluteEncoderPositions(HANDLE h, PAXES_DATA d) { return positions(h, OMS_ALL_AXES, d, POS_ABSOLUTE); }

/* Motor and encoder positions of one instant: the map's position request mailbox. */
long _stdcall GetPositionData(HANDLE h, PPOSITION_DATA data)
{
    AXIS_DATA *out = (AXIS_DATA *)data;
    long motor[OMS_AXES], encoder[OMS_AXES];
    int i;
    BEGIN(h)
    REFUSE_IF(!data, INVALID_PARAMETER);
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP) {
        map_put(b, MAP_POSITION_REQUEST, 1);
        CHECK(map_mailbox_wait(b, MAP_POSITION_REQUEST, 0, b->response_ms) == SUCCESS
                  ? SUCCESS : RESPONSE_TIME_OUT);
        for (i = 0; i < OMS_AXES; i++) {
            out[i].Motor = map_signed(b, snap_motor_offset(i));
            out[i].Encoder = map_signed(b, snap_encoder_offset(i));
        }
        goto done;
    }
#endif
    CHECK(read_positions(b, OMS_ALL_AXES, POS_MOTOR, motor));
    CHECK(read_positions(b, OMS_ALL_AXES, POS_ENCODER, encoder));
    for (i = 0; i < OMS_AXES; i++) {
        out[i].Motor = motor[i];
        out[i].Encoder = encoder[i];
    }
done:
    END
}

/* ---- position initialization --------------------------------------------------------------- */
long _stdcall DefineOmsHomeAsSwitchClosed(HANDLE h, long axis) { return axis_command(h, axis, "HH;"); }
long _stdcall DefineOmsHomeAsSwitchOpen(HANDLE h, long axis) { return axis_command(h, axis, "HL;"); }

/* Jog toward a limit with overtravel detection on; done when the limit stops the axis. */
static long find_limit(HANDLE h, long axis, long velocity, long ms, int sign)
{
    char text[128];
    int i = single_axis(axis);
    if (i < 0)
        return INVALID_AXIS_SELECTION;
    if (!valid_velocity(velocity) || ms < 0)
        return INVALID_PARAMETER;
    {
        double deadline;
        unsigned bits[OMS_AXES];
        BEGIN(h)
        CHECK(clear_axis_flags(b, axis, 2u));
        snprintf(text, sizeof text, "A%cLNJG%s%ld;", AXIS_LETTERS[i], sign < 0 ? "-" : "", velocity);
        CHECK(write_text(b, text));
        deadline = now_ms() + (double)ms;
        for (;;) {
            CHECK(axis_flag_bits(b, bits, NULL));
            if (bits[i] & 2u)
                break;
            REFUSE_IF(now_ms() > deadline, MOVE_TIME_OUT);
#ifdef OMS_HAVE_MAP
            if (b->transport == OMS_MAP) {
                pause_us(200);
                continue;
            }
#endif
            REFUSE_IF(tcp_pull(b, 20) < 0, RESPONSE_TIME_OUT);
        }
    done:
        END
    }
}

long _stdcall FindOmsAxisFwdLimit(HANDLE h, long axis, long v, long ms) { return find_limit(h, axis, v, ms, 1); }
long _stdcall FindOmsAxisRevLimit(HANDLE h, long axis, long v, long ms) { return find_limit(h, axis, v, ms, -1); }

/* Homing: HE (encoder index) or HS (switch), then HM (forward) or HR (reverse) with the
 * position loaded at home, then ID. The slew velocity is the axis's own (VL). */
static long home(HANDLE h, long axis, long position, const char *how, const char *dir, int wait, long ms)
{
    char text[128];
    int i = single_axis(axis);
    if (i < 0)
        return INVALID_AXIS_SELECTION;
    if (wait && ms < 0)
        return INVALID_PARAMETER;
    snprintf(text, sizeof text, "A%c%s%s%ld;ID", AXIS_LETTERS[i], how, dir, position);
    return move(h, axis, text, wait, ms);
}

long _stdcall HomeOmsAxisFwdUseEncoder(HANDLE h, long a, long p) { return home(h, a, p, "HE", "HM", 0, 0); }
long _stdcall HomeOmsAxisFwdUseEncoderWait(HANDLE h, long a, long p, long ms) { return home(h, a, p, "HE", "HM", 1, ms); }
long _stdcall HomeOmsAxisFwdUseSwitch(HANDLE h, long a, long p) { return home(h, a, p, "HS", "HM", 0, 0); }
long _stdcall HomeOmsAxisFwdUseSwitchWait(HANDLE h, long a, long p, long ms) { return home(h, a, p, "HS", "HM", 1, ms); }
long _stdcall HomeOmsAxisRevUseEncoder(HANDLE h, long a, long p) { return home(h, a, p, "HE", "HR", 0, 0); }
long _stdcall HomeOmsAxisRevUseEncoderWait(HANDLE h, long a, long p, long ms) { return home(h, a, p, "HE", "HR", 1, ms); }
long _stdcall HomeOmsAxisRevUseSwitch(HANDLE h, long a, long p) { return home(h, a, p, "HS", "HR", 0, 0); }
long _stdcall HomeOmsAxisRevUseSwitchWait(HANDLE h, long a, long p, long ms) { return home(h, a, p, "HS", "HR", 1, ms); }

long _stdcall SetOmsAxisPosition(HANDLE h, long axis, long pos) { return axis_command(h, axis, "LP%ld;", pos); }

/* ---- velocity and acceleration ------------------------------------------------------------- */
static long axis_report(HANDLE h, long axis, const char *what, long *out)
{
    char line[OMS_LINE_MAX];
    int i = single_axis(axis);
    BEGIN(h)
    REFUSE_IF(i < 0, INVALID_AXIS_SELECTION);
    REFUSE_IF(!out, INVALID_PARAMETER);
    CHECK(query(b, line, sizeof line, "A%c%s;", AXIS_LETTERS[i], what));
    *out = strtol(line, NULL, 10);
done:
    END
}

static long selected_report(HANDLE h, long axes, const char *what, PAXES_DATA data)
{
    char line[OMS_LINE_MAX];
    const char *p = line;
    int i;
    BEGIN(h)
    REFUSE_IF(!valid_axes(axes), INVALID_AXIS_SELECTION);
    REFUSE_IF(!data, INVALID_PARAMETER);
    CHECK(query(b, line, sizeof line, "AM%s;", what));
    for (i = 0; i < OMS_AXES; i++) {
        long v = (p && *p && *p != ',') ? strtol(p, NULL, 10) : 0;
        if (axes & (1L << i))
            axes_set(data, i, v);
        p = p ? strchr(p, ',') : NULL;
        if (p)
            p++;
    }
done:
    END
}

long _stdcall GetOmsAxisVelocity(HANDLE h, long axis, long *v) { return axis_report(h, axis, "RV", v); }
long _stdcall GetSelectedOmsVelocities(HANDLE h, long axes, PAXES_DATA d) { return selected_report(h, axes, "RV", d); }
long _stdcall GetOmsAxisAcceleration(HANDLE h, long axis, long *a) { return axis_report(h, axis, "RC", a); }
long _stdcall GetSelectedOmsAccelerations(HANDLE h, long axes, PAXES_DATA d) { return selected_report(h, axes, "RC", d); }

long _stdcall SetOmsAxisBaseVelocity(HANDLE h, long axis, long v)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (v < 0 || v > MAX_VELOCITY)
        return INVALID_PARAMETER;
    return axis_command(h, axis, "VB%ld;", v);
}

long _stdcall SetOmsAxisVelocity(HANDLE h, long axis, long v)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (!valid_velocity(v))
        return INVALID_PARAMETER;
    return axis_command(h, axis, "VL%ld;", v);
}

long _stdcall SetOmsAxisAcceleration(HANDLE h, long axis, long a)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (!valid_acceleration(a))
        return INVALID_PARAMETER;
    return axis_command(h, axis, "AC%ld;", a);
}

/* The DLL's ramp templates in the order of its ramp functions: CN, LA, PN#, SC + SS#. */
long _stdcall SelectOmsCosineRamp(HANDLE h, long axis) { return axis_command(h, axis, "CN;"); }
long _stdcall SelectOmsLinearRamp(HANDLE h, long axis) { return axis_command(h, axis, "LA;"); }

long _stdcall SelectOmsParabolicRamp(HANDLE h, long axis, long n)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (n < 0 || n > 8) /* the board's PN takes degrees 0..8 (docs/commands.md) */
        return INVALID_PARAMETER;
    return axis_command(h, axis, "PN%ld;", n);
}

long _stdcall SelectOmsSCurveRamp(HANDLE h, long axis, long n)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (n < 0 || n > 100)
        return INVALID_PARAMETER;
    return axis_command(h, axis, "SC;SS%ld;PR%ld;", n, n);
}

/* ---- encoders -------------------------------------------------------------------------- */
long _stdcall EnableOmsSlipDetection(HANDLE h, long axis) { return axis_command(h, axis, "IS;"); }

long _stdcall GetOmsEncoderFlags(HANDLE h, long axis, long *flags)
{
    char line[OMS_LINE_MAX];
    int i = single_axis(axis);
    BEGIN(h)
    REFUSE_IF(i < 0, INVALID_AXIS_SELECTION);
    REFUSE_IF(!flags, INVALID_PARAMETER);
    /* EA: slip detection E/D, position maintenance E/D, slipped S/N, dead band D/N,
     * index H/N; an axis without an encoder answers nothing but a command error */
    CHECK(query(b, line, sizeof line, "AM;EA;"));
    {
        const char *p = line;
        int k;
        for (k = 0; k < i && p; k++) {
            p = strchr(p, ',');
            if (p)
                p++;
        }
        *flags = 0;
        if (p && strlen(p) >= 5 && p[0] != ',') {
            if (p[0] == 'E')
                *flags |= SLIP_DETECT_ENABLED;
            if (p[1] == 'E')
                *flags |= POSITION_MAINTENANCE_ENABLED;
            if (p[2] == 'S')
                *flags |= AXIS_SLIPPED;
            if (p[3] == 'D')
                *flags |= AXIS_WITHIN_DEADBAND;
            if (p[4] == 'H')
                *flags |= ENCODER_AT_HOME;
        }
    }
done:
    END
}

static long mode_command(HANDLE h, long axis, long mode, const char *on, const char *off)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (mode != MODE_ON && mode != MODE_OFF)
        return INVALID_PARAMETER;
    return axis_command(h, axis, "%s", mode == MODE_ON ? on : off);
}

long _stdcall SetOmsAxisPidEnable(HANDLE h, long axis, long mode) { return mode_command(h, axis, mode, "HN;", "HF;"); }
long _stdcall SetOmsEncoderHoldMode(HANDLE h, long axis, long mode) { return mode_command(h, axis, mode, "HN;", "HF;"); }

long _stdcall SetOmsEncoderRatio(HANDLE h, long axis, long counts, long steps)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (counts <= 0 || steps <= 0)
        return INVALID_PARAMETER;
    return axis_command(h, axis, "ER%ld,%ld;", counts, steps);
}

static long nonnegative(HANDLE h, long axis, const char *op, long value)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (value < 0)
        return INVALID_PARAMETER;
    return axis_command(h, axis, "%s%ld;", op, value);
}

long _stdcall SetOmsHoldDeadBand(HANDLE h, long axis, long n) { return nonnegative(h, axis, "HD", n); }
long _stdcall SetOmsEncoderSlipTolerance(HANDLE h, long axis, long n) { return nonnegative(h, axis, "ES", n); }
long _stdcall SetOmsHoldGain(HANDLE h, long axis, long n) { return nonnegative(h, axis, "HG", n); }

long _stdcall SetOmsHoldVelocity(HANDLE h, long axis, long v)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (!valid_velocity(v))
        return INVALID_PARAMETER;
    return axis_command(h, axis, "HV%ld;", v);
}

/* ---- overtravel ------------------------------------------------------------------------ */
long _stdcall SetOmsAxisOvertravelDetect(HANDLE h, long axis, long mode) { return mode_command(h, axis, mode, "LN;", "LF;"); }

long _stdcall ConfigureOmsAxisLimitInput(HANDLE h, long axis, long level)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    if (level != HIGH && level != LOW)
        return INVALID_PARAMETER;
    return axis_command(h, axis, level == HIGH ? "LH;" : "LL;");
}

long _stdcall SetOmsSoftLimitsMode(HANDLE h, long axis, long mode) { return mode_command(h, axis, mode, "SL;", "SF;"); }

/* ---- general purpose I/O ------------------------------------------------------------------ */
static long hex_report(HANDLE h, const char *text, long *out)
{
    char line[OMS_LINE_MAX];
    BEGIN(h)
    REFUSE_IF(!out, INVALID_PARAMETER);
    CHECK(query(b, line, sizeof line, "%s", text));
    *out = (long)(parse_hex(line) & 0xFFFFu);
done:
    END
}

long _stdcall GetOmsIOBitConfig(HANDLE h, long *outputs) { return hex_report(h, "AXRB;", outputs); }

/* BX, as the vendor DLL reads the bits (the map's I/O word lags a command by an update) */
long _stdcall GetAllOmsIOBits(HANDLE h, long *bits) { return hex_report(h, "BX;", bits); }

static long io_word(HANDLE h, const char *op, long word)
{
    char text[32];
    if (word < 0 || word > 0xFFFF)
        return INVALID_PARAMETER;
    snprintf(text, sizeof text, "AA;%s%04lX;", op, word);
    return simple(h, text);
}

long _stdcall ConfigureAllOmsIOBits(HANDLE h, long outputs) { return io_word(h, "BD", outputs); }
long _stdcall SetAllOmsIOBits(HANDLE h, long bits) { return io_word(h, "BS", bits); }

long _stdcall GetOmsIOBit(HANDLE h, long bit, long *state)
{
    long word = 0, rc;
    if (bit < 0 || bit > 15)
        return INVALID_BIT_NUMBER;
    if (!state)
        return INVALID_PARAMETER;
    rc = GetAllOmsIOBits(h, &word);
    if (rc == SUCCESS)
        *state = (word >> bit) & 1L;
    return rc;
}

long _stdcall SetOmsIOBit(HANDLE h, long bit, long state)
{
    char text[32];
    if (bit < 0 || bit > 15)
        return INVALID_BIT_NUMBER;
    /* AA mode: the bit switches at once, not queued behind the last addressed axis */
    snprintf(text, sizeof text, "AA;%s%ld;", state ? "BH" : "BL", bit);
    return simple(h, text);
}

/* ---- auxiliary outputs --------------------------------------------------------------------- */
long _stdcall EnableOmsAxisAuxOutAutoMode(HANDLE h, long axis, long mode) { return mode_command(h, axis, mode, "PA1;", "PA0;"); }
long _stdcall SetOmsAxisAuxOutSettleTime(HANDLE h, long axis, long ms) { return nonnegative(h, axis, "SE", ms); }
long _stdcall SetOmsAxisAuxOutBit(HANDLE h, long axis, long state)
{
    if (single_axis(axis) < 0)
        return INVALID_AXIS_SELECTION;
    return axis_command(h, axis, state ? "AN;" : "AF;");
}

long _stdcall SetSelectedOmsAuxOutBits(HANDLE h, long axes, long state)
{
    char text[256];
    size_t n;
    int i;
    if (!valid_axes(axes))
        return INVALID_AXIS_SELECTION;
    n = (size_t)snprintf(text, sizeof text, "AM");
    for (i = 0; i < OMS_AXES; i++)
        if (axes & (1L << i))
            n += (size_t)snprintf(text + n, sizeof text - n, ";A%c%s", AXIS_LETTERS[i], state ? "AN" : "AF");
    snprintf(text + n, sizeof text - n, ";");
    return simple(h, text + 3); /* one A?AN/AF per axis: AM's AN would switch them all */
}

/* ---- not in the vendor's library ------------------------------------------------------------ */
/* How many reply lines too long for the library's inbox (4 KiB) were dropped on this
 * handle's board; 0 for a handle that is not open. */
unsigned long _stdcall MaxkOmsDroppedLines(HANDLE h)
{
    oms_board *b = board_of(h);
    unsigned long n;
    if (!b)
        return 0;
    oms_mutex_lock(&b->lock);
    n = b->dropped_lines;
    oms_mutex_unlock(&b->lock);
    return n;
}

/* ---- the big command buffer ---------------------------------------------------------------- */
long _stdcall OMS_SetCommandBuffer(HANDLE h, eOMSBuffMode mode, long size)
{
    char text[64];
    long rc;
    oms_board *b;
    if (mode != OMS_BIG_CMD_BUFFER_MODE && mode != OMS_NORMAL_CMD_BUFFER_MODE)
        return INVALID_PARAMETER;
    if (mode == OMS_BIG_CMD_BUFFER_MODE && size < 0)
        return INVALID_PARAMETER;
    if (mode == OMS_BIG_CMD_BUFFER_MODE)
        snprintf(text, sizeof text, size ? ";#BB%ld;" : ";#BB;", size);
    else
        snprintf(text, sizeof text, ";#BN;");
    rc = simple(h, text);
    if (rc == SUCCESS && (b = board_of(h)) != NULL) {
        oms_mutex_lock(&b->lock);
        b->buffer_mode = mode;
        oms_mutex_unlock(&b->lock);
    }
    return rc;
}

long _stdcall OMS_GetCommandBufferSelection(HANDLE h, eOMSBuffMode *mode)
{
    BEGIN(h)
    REFUSE_IF(!mode, INVALID_PARAMETER);
    *mode = b->buffer_mode;
done:
    END
}

long _stdcall OMS_BigBufferSendBlock(HANDLE h, LPSTR block, long size, long *sent)
{
    BEGIN(h)
    REFUSE_IF(!block || size < 0, INVALID_PARAMETER);
    if (sent)
        *sent = 0;
#ifdef OMS_HAVE_MAP
    if (b->transport == OMS_MAP)
        rc = map_write_text(b, block, (size_t)size);
    else
#endif
        rc = tcp_write_text(b, block, (size_t)size);
    if (rc == SUCCESS && sent)
        *sent = size;
done:
    END
}

long _stdcall OMS_GetBigBufferFreeSpace(HANDLE h, long *free_space)
{
    if (!free_space)
        return INVALID_PARAMETER;
    if (!board_of(h))
        return COMMAND_TIME_OUT;
    *free_space = GetCmdBufferFree(h);
    return SUCCESS;
}

long _stdcall OMS_FlushBigBuffer(HANDLE h) { return simple(h, ";#BF;"); }
