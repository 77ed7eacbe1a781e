/*
 * A firmware-style host for a program compiled by `ladderc build`: the device
 * image lives in static storage (no heap), the program scans at a fixed
 * period, and outputs are printed after every scan.
 *
 *   ./host [SCANS [SCAN_MS [Xn=0|1 ...]]]
 *
 * Prints `scan,Y0,...,Y7` as CSV, the format of
 * `ladderc run --format csv --watch Y0,Y1,Y2,Y3,Y4,Y5,Y6,Y7` (an output
 * the program's compact image does not hold is OFF), and reports
 * operation errors on stderr. Build it (see README.md):
 *
 *   cargo build -p ladder-runtime --profile firmware --no-default-features
 *   cc -std=c99 -Os -I runtime/include examples/host/main.c prog.o \
 *      target/firmware/libladder_runtime.a -nodefaultlibs -lc -o host
 *
 * For a program built with `--image compact`, add
 * -DPROGRAM_HEADER='"prog.h"' (the header `ladderc build` wrote beside it):
 * the static image then has the program's size instead of the full one.
 */
#ifdef LADDER_HOST_GUARDED
#define _DEFAULT_SOURCE
#include <sys/mman.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "ladder_runtime.h"

#ifdef PROGRAM_HEADER
#include PROGRAM_HEADER
#define IMAGE_SIZE LADDER_PROGRAM_IMAGE_SIZE
#else
LADDER_DECLARE_PROGRAM(ladder_program_);
#define IMAGE_SIZE LADDER_MEMORY_SIZE
#endif

#if defined(LADDER_HOST_GUARDED)
/* The image ends flush against an inaccessible region larger than any offset
   can reach, with another one below it: a stray access faults at once (tests
   build the host this way). */
static void *guarded_storage(void) {
    const size_t guard = (size_t)1 << 21, page = 4096;
    const size_t body = (IMAGE_SIZE + page - 1) / page * page;
    unsigned char *base = mmap(NULL, body + 2 * guard, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (base == MAP_FAILED || mprotect(base + guard, body, PROT_READ | PROT_WRITE) != 0) return NULL;
    return base + guard + (body - IMAGE_SIZE);
}
#elif !defined(LADDER_HOST_HEAP)
static uint32_t storage[IMAGE_SIZE / sizeof(uint32_t) + 1];
#endif

/* "X17=1": input X17 (octal) ON. */
static int set_input(LadderMemory *mem, const char *arg) {
    if (arg[0] != 'X' && arg[0] != 'x') return -1;
    char *end = NULL;
    unsigned long number = strtoul(arg + 1, &end, 8);
    if (end == arg + 1 || *end != '=' || (end[1] != '0' && end[1] != '1')) return -1;
    return ladder_set_input(mem, (uint32_t)number, end[1] == '1') == LADDER_STATUS_OK ? 0 : -1;
}

int main(int argc, char **argv) {
    unsigned long scans = argc > 1 ? strtoul(argv[1], NULL, 10) : 40;
    unsigned long scan_ms = argc > 2 ? strtoul(argv[2], NULL, 10) : 100;
#if defined(LADDER_HOST_GUARDED)
    LadderMemory *mem = ladder_program_init(guarded_storage(), IMAGE_SIZE);
#elif defined(LADDER_HOST_HEAP)
    /* Exactly the image, on the heap: a memory checker sees accesses just
       outside it (tests build the host this way under valgrind). */
    LadderMemory *mem = ladder_program_init(malloc(IMAGE_SIZE), IMAGE_SIZE);
#else
    LadderMemory *mem = ladder_program_init(storage, sizeof storage);
#endif
    if (mem == NULL) {
        fprintf(stderr, "ladder_program_init: storage too small or misaligned\n");
        return 1;
    }
    for (int i = 3; i < argc; i++) {
        if (set_input(mem, argv[i]) != 0) {
            fprintf(stderr, "bad input `%s` (expected Xn=0 or Xn=1, n octal)\n", argv[i]);
            return 1;
        }
    }
    printf("scan,Y0,Y1,Y2,Y3,Y4,Y5,Y6,Y7\n");
    uint16_t reported = 0;
    for (unsigned long scan = 1; scan <= scans; scan++) {
        ladder_program_scan(mem, (uint32_t)scan_ms);
        printf("%lu", scan);
        for (uint32_t y = 0; y < 8; y++) printf(",%d", ladder_get_output(mem, y) == 1);
        printf("\n");
        uint16_t error = ladder_operation_error(mem);
        if (error != 0 && error != reported) {
            fprintf(stderr, "scan %lu: operation error %04XH at line %u\n", scan, error,
                    (unsigned)ladder_operation_error_line(mem));
        }
        reported = error;
    }
    return 0;
}
