/*
 * The host `ladderc test --engine aot` links with a compiled program and the
 * runtime library, exactly as a firmware host would. It drives the program
 * through the C API on commands from stdin, one per line, and answers each
 * with one line:
 *
 *   r KIND N        read a device        -> value, or "E status"
 *   w KIND N V      write a device       -> status
 *   f KIND N ON     force                -> status
 *   u KIND N        unforce              -> status
 *   s COUNT MS      run COUNT scans      -> 0, or "M misses" when the
 *                   program wrote devices its compact image lacks
 *   p X COUNT       add pulses to X      -> status
 *   c Y M D H MI S  set the clock        -> status
 *   q               quit
 *
 * KIND is a LadderDevice, status a LadderStatus.
 */
#include <stdio.h>
#include <stdlib.h>
#include "ladder_runtime.h"

LADDER_DECLARE_PROGRAM(ladder_program_);

static uint32_t storage[LADDER_MEMORY_SIZE / sizeof(uint32_t) + 1];

int main(void) {
    LadderMemory *mem = ladder_program_init(storage, sizeof storage);
    if (mem == NULL) {
        fprintf(stderr, "ladder_program_init refused the storage\n");
        return 2;
    }
    char line[128];
    while (fgets(line, sizeof line, stdin) != NULL) {
        unsigned kind = 0, number = 0, count = 0, ms = 0;
        uint32_t misses = 0;
        long value = 0;
        int32_t read = 0;
        switch (line[0]) {
        case 'r':
            if (sscanf(line + 1, "%u %u", &kind, &number) != 2) return 3;
            LadderStatus status = ladder_read(mem, kind, number, &read);
            if (status == LADDER_STATUS_OK) printf("%ld\n", (long)read);
            else printf("E %d\n", (int)status);
            break;
        case 'w':
            if (sscanf(line + 1, "%u %u %ld", &kind, &number, &value) != 3) return 3;
            printf("%d\n", (int)ladder_write(mem, kind, number, (int32_t)value));
            break;
        case 'f':
            if (sscanf(line + 1, "%u %u %ld", &kind, &number, &value) != 3) return 3;
            printf("%d\n", (int)ladder_force(mem, kind, number, value != 0));
            break;
        case 'u':
            if (sscanf(line + 1, "%u %u", &kind, &number) != 2) return 3;
            printf("%d\n", (int)ladder_unforce(mem, kind, number));
            break;
        case 's':
            if (sscanf(line + 1, "%u %u", &count, &ms) != 2) return 3;
            for (unsigned i = 0; i < count; i++) ladder_program_scan(mem, ms);
            /* A write by the program to a device its compact image lacks
               is the compiler's fault: the scan fails. */
            misses = ladder_layout_misses(mem);
            if (misses == 0) printf("0\n");
            else printf("M %u\n", (unsigned)misses);
            break;
        case 'p':
            if (sscanf(line + 1, "%u %u", &number, &count) != 2) return 3;
            printf("%d\n", (int)ladder_add_pulses(mem, number, count));
            break;
        case 'c': {
            unsigned y = 0, mo = 0, d = 0, h = 0, mi = 0, sec = 0;
            if (sscanf(line + 1, "%u %u %u %u %u %u", &y, &mo, &d, &h, &mi, &sec) != 6) return 3;
            printf("%d\n", (int)ladder_set_clock(mem, y, mo, d, h, mi, sec));
            break;
        }
        case 'q':
            return 0;
        default:
            return 3;
        }
        fflush(stdout);
    }
    return 0;
}
