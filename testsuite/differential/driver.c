/*
 * Differential-test driver: several compiled programs (each built with its
 * own --prefix, listed in programs.h as X(prefix) entries) linked with the
 * runtime library into one host. Commands on stdin, one per line:
 *
 *   P i          start program i on a freshly initialised image (its
 *                <prefix>init: the program's layout, full or compact)
 *   I x on       ladder_set_input(x, on)
 *   W k n v      ladder_write(kind k, number n, value v)
 *   B k n b v    ladder_write_word_bit(kind k, number n, bit b, value v)
 *   H x n        ladder_add_pulses(input x, count n)
 *   F k n on     ladder_force(kind k, number n, on)
 *   U k n        ladder_unforce(kind k, number n)
 *   S ms         one scan reporting ms; prints a hash of the whole image
 *                after its header
 *   D            prints the whole image in hex on one line
 *
 * compiler/tests/common/differential.rs does the same on the interpreter
 * and the JIT and compares the hashes after every scan.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "ladder_runtime.h"
#include "programs.h"

#define X(prefix) LADDER_DECLARE_PROGRAM(prefix);
PROGRAMS
#undef X

typedef void (*scan_fn)(LadderMemory *mem, uint32_t elapsed_ms);
typedef LadderMemory *(*init_fn)(void *storage, size_t size);

#define X(prefix) prefix##scan,
static const scan_fn programs[] = {PROGRAMS};
#undef X
#define X(prefix) prefix##init,
static const init_fn inits[] = {PROGRAMS};
#undef X

/* The full image's size: a compact one (--image compact) is smaller. */
static uint32_t storage[LADDER_MEMORY_SIZE / 4];

/* The image's size, from its header (magic, size, ...). */
static size_t image_size(void) { return storage[1]; }

int main(void) {
    char line[256];
    LadderMemory *mem = NULL;
    scan_fn scan = NULL;
    const uint8_t *bytes = (const uint8_t *)storage;
    while (fgets(line, sizeof line, stdin)) {
        unsigned long a = 0, b = 0;
        long v = 0;
        switch (line[0]) {
        case 'P':
            a = strtoul(line + 1, NULL, 10);
            if (a >= sizeof programs / sizeof programs[0]) return 2;
            mem = inits[a](storage, sizeof storage);
            if (mem == NULL) return 3;
            scan = programs[a];
            break;
        case 'I':
            if (sscanf(line + 1, "%lu %lu", &a, &b) != 2) return 2;
            ladder_set_input(mem, (uint32_t)a, b != 0);
            break;
        case 'W':
            if (sscanf(line + 1, "%lu %lu %ld", &a, &b, &v) != 3) return 2;
            ladder_write(mem, (uint32_t)a, (uint32_t)b, (int32_t)v);
            break;
        case 'B': {
            unsigned long bit = 0;
            if (sscanf(line + 1, "%lu %lu %lu %ld", &a, &b, &bit, &v) != 4) return 2;
            ladder_write_word_bit(mem, (uint32_t)a, (uint32_t)b, (uint32_t)bit, (int32_t)v);
            break;
        }
        case 'H':
            if (sscanf(line + 1, "%lu %lu", &a, &b) != 2) return 2;
            ladder_add_pulses(mem, (uint32_t)a, (uint32_t)b);
            break;
        case 'F':
            if (sscanf(line + 1, "%lu %lu %ld", &a, &b, &v) != 3) return 2;
            ladder_force(mem, (uint32_t)a, (uint32_t)b, v != 0);
            break;
        case 'U':
            if (sscanf(line + 1, "%lu %lu", &a, &b) != 2) return 2;
            ladder_unforce(mem, (uint32_t)a, (uint32_t)b);
            break;
        case 'S': {
            if (scan == NULL) return 2;
            scan(mem, (uint32_t)strtoul(line + 1, NULL, 10));
            /* FNV-1a over the image's 64-bit little-endian words after its
               16-byte header, the last one padded with zeros. */
            uint64_t hash = 0xcbf29ce484222325ull;
            size_t size = image_size();
            for (size_t i = 16; i < size; i += 8) {
                uint64_t word = 0;
                for (int b = 7; b >= 0; b--) word = (word << 8) | (i + (size_t)b < size ? bytes[i + b] : 0u);
                hash = (hash ^ word) * 0x100000001b3ull;
            }
            printf("%016llx\n", (unsigned long long)hash);
            break;
        }
        case 'D':
            for (size_t i = 0; i < image_size(); i++) printf("%02x", bytes[i]);
            putchar('\n');
            break;
        default:
            return 2;
        }
    }
    return 0;
}
