/*
 * A firmware host for a Cortex-M3 (the Arm MPS2 AN385 board, as QEMU
 * emulates it): the device image in static RAM, SysTick as the scan
 * period, the program built by `ladderc build --target thumbv7m-none-eabi`
 * (through the C back end), the runtime built for the same target. After
 * each scan it prints `scan,Y0,...,Y7` (the CSV of `ladderc run --format
 * csv --watch Y0,...,Y7`) through semihosting; after SCANS scans it ends
 * the emulation. Build and run: see README.md in this folder.
 */
#include <stdint.h>
#include "ladder_runtime.h"
/* The program's header (`ladderc build` writes it beside the object, e.g.
   traffic_light_m3.h for traffic_light_m3.o): its entry points and the size
   of its image. Name it with -DPROGRAM_HEADER='"traffic_light_m3.h"'. */
#ifndef PROGRAM_HEADER
#define PROGRAM_HEADER "program.h"
#endif
#include PROGRAM_HEADER

#ifndef SCANS
#define SCANS 40
#endif
#ifndef SCAN_MS
#define SCAN_MS 100
#endif
/* The MPS2 boards run the core at 25 MHz. */
#define CORE_HZ 25000000u


/* ---- semihosting: output and exit through the debugger (QEMU) ---- */
static int semihost(int operation, const void *argument) {
    register int r0 __asm__("r0") = operation;
    register const void *r1 __asm__("r1") = argument;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

static void put(const char *text) { semihost(0x04, text); /* SYS_WRITE0 */ }

static void put_number(unsigned long n) {
    char digits[12];
    int i = sizeof digits - 1;
    digits[i] = '\0';
    do { digits[--i] = (char)('0' + n % 10); n /= 10; } while (n && i > 0);
    put(&digits[i]);
}

static void exit_emulation(void) {
    /* SYS_EXIT with ADP_Stopped_ApplicationExit. */
    semihost(0x18, (const void *)0x20026);
    for (;;) {}
}

/* ---- SysTick: one interrupt per scan period ---- */
#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)

static volatile uint32_t ticks;

void SysTick_Handler(void) { ticks++; }

/* The image: static storage of the program's size, aligned as
   ladder_program_init requires. */
static uint32_t storage[(LADDER_PROGRAM_IMAGE_SIZE + 3) / 4];

int main(void) {
    LadderMemory *mem = ladder_program_init(storage, sizeof storage);
    if (mem == 0) {
        put("ladder_program_init: storage too small or misaligned\n");
        exit_emulation();
    }
    SYST_RVR = CORE_HZ / 1000u * SCAN_MS - 1u;
    SYST_CVR = 0;
    SYST_CSR = 7; /* processor clock, interrupt, enabled */
    put("scan,Y0,Y1,Y2,Y3,Y4,Y5,Y6,Y7\n");
    uint32_t seen = ticks;
    for (unsigned long scan = 1; scan <= SCANS; scan++) {
        while (ticks == seen) __asm__ volatile("wfi");
        seen = ticks;
        ladder_program_scan(mem, SCAN_MS);
        put_number(scan);
        /* An output the compact image does not hold is -1: OFF. */
        for (uint32_t y = 0; y < 8; y++) put(ladder_get_output(mem, y) == 1 ? ",1" : ",0");
        put("\n");
    }
    exit_emulation();
    return 0;
}
