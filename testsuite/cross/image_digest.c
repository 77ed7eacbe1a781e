/*
 * Drives a compiled program through SCANS scans of 10 ms with a fixed input
 * pattern and prints an FNV-1a hash of the whole device image after each
 * scan. compiler/tests/cross_targets.rs computes the same on the interpreter.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "layout.h"

void ladder_program_scan(void *mem, uint32_t elapsed_ms);
void *ladder_program_init(void *storage, size_t size);

static uint32_t image[MEMORY_SIZE / 4];

int main(int argc, char **argv) {
    unsigned long scans = argc > 1 ? strtoul(argv[1], NULL, 10) : 100;
    if (ladder_program_init(image, sizeof image) == NULL) return 2;
    uint8_t *bytes = (uint8_t *)image;
    for (uint32_t scan = 1; scan <= scans; scan++) {
        uint32_t pattern = (scan * 2654435761u) >> 13;
        for (unsigned x = 0; x < 8; x++) bytes[OFFSET_INPUT_IMAGE + x] = (pattern >> x) & 1;
        ladder_program_scan(image, 10);
        uint64_t hash = 0xcbf29ce484222325ull;
        for (unsigned long i = 0; i < MEMORY_SIZE; i++) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
        printf("%u %016llx\n", scan, (unsigned long long)hash);
    }
    return 0;
}
