/*
 * A legacy-style host program for the maxk shared-memory door: it maps the MAXk
 * shared memory (Table 3-1) from a file and drives a move using only the ASCII command
 * ring, the response ring and the doorbell, as a PCI host would.
 *
 *   cc -O2 -o maxk_shm_move maxk_shm_move.c
 *   maxk serve --shm /dev/shm/maxk &          (prints where the map is)
 *   ./maxk_shm_move /dev/shm/maxk "AX;VL5000;AC50000;MR1000;GO;ID;"
 *
 * Everything in the map is big-endian (the board is a PowerPC). Offsets 0x0F0..0x900
 * are the manual's; the doorbell image and its clear register at 0xD000/0xD004 are
 * maxk's choice (docs/shared-memory.md): on the real board they are PCI registers.
 */
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define MAP_SIZE 0xE010
#define MOTOR_X 0x000
#define FIRMWARE_FLAGS 0x048
#define CMD_INSERT 0x0F0
#define CMD_PROCESS 0x0F4
#define RESP_INSERT 0x0F8
#define RESP_PROCESS 0x0FC
#define CMD_RING 0x100
#define RESP_RING 0x500
#define RING_SIZE 1024
#define ODBR 0xD000
#define ODBR_CLEAR 0xD004
#define DONE_X 0x1u
#define FW_RUNNING 0x4u

static volatile uint8_t *mem;

static uint32_t get32(unsigned off) {
    return (uint32_t)mem[off] << 24 | (uint32_t)mem[off + 1] << 16 |
           (uint32_t)mem[off + 2] << 8 | (uint32_t)mem[off + 3];
}

static void put32(unsigned off, uint32_t v) {
    mem[off] = v >> 24; mem[off + 1] = v >> 16; mem[off + 2] = v >> 8; mem[off + 3] = v;
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Write a command string at the insert index, then advance the index. */
static int send_text(const char *text) {
    size_t n = strlen(text);
    uint32_t insert = get32(CMD_INSERT) % RING_SIZE;
    uint32_t process = get32(CMD_PROCESS) % RING_SIZE;
    if (n > (process - insert - 1 + RING_SIZE) % RING_SIZE) return -1;
    for (size_t i = 0; i < n; i++) mem[CMD_RING + (insert + i) % RING_SIZE] = text[i];
    put32(CMD_INSERT, (insert + n) % RING_SIZE);
    return 0;
}

/* Read one LF-terminated reply from the response ring, advancing the process index. */
static int read_reply(char *out, size_t size, double timeout) {
    size_t len = 0;
    double end = now() + timeout;
    while (now() < end) {
        uint32_t insert = get32(RESP_INSERT) % RING_SIZE;
        uint32_t process = get32(RESP_PROCESS) % RING_SIZE;
        while (process != insert) {
            char c = mem[RESP_RING + process];
            process = (process + 1) % RING_SIZE;
            put32(RESP_PROCESS, process);
            if (c == '\n') { out[len] = 0; return 0; }
            if (len + 1 < size) out[len++] = c;
        }
        usleep(100);
    }
    return -1;
}

int main(int argc, char **argv) {
    const char *path = argc > 1 ? argv[1] : "/dev/shm/maxk";
    const char *move = argc > 2 ? argv[2] : "AX;VL5000;AC50000;MR1000;GO;ID;";
    struct stat st;
    int fd = open(path, O_RDWR);
    if (fd < 0) { perror(path); return 1; }
    /* a file shorter than the map would fault (SIGBUS) where the mapping passes its end */
    if (fstat(fd, &st) != 0 || st.st_size < (off_t)MAP_SIZE) {
        fprintf(stderr, "%s: not a whole map\n", path);
        return 1;
    }
    mem = mmap(NULL, MAP_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    close(fd);
    if (mem == MAP_FAILED) { perror("mmap"); return 1; }

    double end = now() + 5.0;  /* power-up: the flags read all ones until initialized */
    while ((get32(FIRMWARE_FLAGS) == 0xFFFFFFFFu || !(get32(FIRMWARE_FLAGS) & FW_RUNNING))
           && now() < end) usleep(100);
    if (!(get32(FIRMWARE_FLAGS) & FW_RUNNING)) { fprintf(stderr, "board not running\n"); return 1; }

    put32(ODBR_CLEAR, DONE_X);               /* forget an old done flag */
    while (get32(ODBR_CLEAR) != 0 && now() < end) usleep(100);
    if (send_text(move) != 0) { fprintf(stderr, "command ring full\n"); return 1; }

    end = now() + 10.0;                      /* wait for the done doorbell bit of X */
    while (!(get32(ODBR) & DONE_X) && now() < end) usleep(100);
    if (!(get32(ODBR) & DONE_X)) { fprintf(stderr, "no done flag\n"); return 1; }
    put32(ODBR_CLEAR, DONE_X);               /* write-one-to-clear */

    char reply[128];
    send_text("AX RP;");
    if (read_reply(reply, sizeof reply, 5.0) != 0) { fprintf(stderr, "no reply\n"); return 1; }
    printf("done X, RP %s, map X %d\n", reply, (int32_t)get32(MOTOR_X));
    return 0;
}
