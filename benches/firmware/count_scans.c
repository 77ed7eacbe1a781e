/*
 * Runs SCANS scans of a program on a Cortex-M3 (QEMU's mps2-an385) without
 * printing, then ends the emulation: the benchmark `firmware_scan` runs it
 * for two scan counts under QEMU with one instruction per translation block
 * and an execution log, and divides the difference in executed
 * instructions by the difference in scans. Inputs change as the example
 * host's might: X0 every scan, X1 every other.
 */
#include <stdint.h>
#include "ladder_runtime.h"
#include PROGRAM_HEADER

#ifndef SCANS
#define SCANS 10
#endif

static uint32_t storage[LADDER_PROGRAM_IMAGE_SIZE / sizeof(uint32_t) + 1];

static void exit_emulation(void) {
    /* Semihosting SYS_EXIT with ADP_Stopped_ApplicationExit. */
    register int r0 __asm__("r0") = 0x18;
    register int r1 __asm__("r1") = 0x20026;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
}

int main(void) {
    LadderMemory *mem = ladder_program_init(storage, sizeof storage);
    for (unsigned long scan = 0; mem != 0 && scan < SCANS; scan++) {
        ladder_set_input(mem, 0, scan & 1);
        ladder_set_input(mem, 1, (scan >> 1) & 1);
        ladder_program_scan(mem, 100);
    }
    exit_emulation();
    return 0;
}
