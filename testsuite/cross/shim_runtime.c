/*
 * Test shim, not a runtime: the scan-boundary calls of the ladderc runtime
 * (runtime/src/scan.rs) for programs that use no runtime helper, so that
 * cross-compiled program code can run under qemu-user where the Rust runtime
 * cannot be built. Forces are not supported (the driver uses none). Offsets
 * come from layout.h, generated from the runtime's layout by the test.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "ladder_runtime.h"
#include "layout.h"

#define AT(mem, offset) ((uint8_t *)(mem) + (offset))
#define U32(mem, offset) (*(uint32_t *)AT(mem, offset))

static void set(LadderMemory *mem, unsigned long area, unsigned n, int on) { *AT(mem, area + n) = (uint8_t)on; }

void LADDER_TAGGED_BEGIN_SCAN(LadderMemory *mem, uint32_t elapsed_ms);
void LADDER_TAGGED_BEGIN_SCAN(LadderMemory *mem, uint32_t elapsed_ms) {
    U32(mem, OFFSET_ELAPSED_MS) = elapsed_ms;
    memcpy(AT(mem, OFFSET_X), AT(mem, OFFSET_INPUT_IMAGE), 256);
    if (U32(mem, OFFSET_STL_PENDING_ANY) != 0) {
        for (unsigned s = 0; s < 4096; s++) {
            if (*AT(mem, OFFSET_STL_PENDING_OFF + s)) {
                *AT(mem, OFFSET_S + s) = 0;
                *AT(mem, OFFSET_STL_PENDING_OFF + s) = 0;
            }
        }
        U32(mem, OFFSET_STL_PENDING_ANY) = 0;
    }
    int first = U32(mem, OFFSET_SCAN_COUNT) == 0;
    set(mem, OFFSET_SM, 0, 1);
    set(mem, OFFSET_SM, 1, 0);
    set(mem, OFFSET_SM, 2, first);
    set(mem, OFFSET_SM, 3, !first);
    set(mem, OFFSET_M, 8000, 1);
    set(mem, OFFSET_M, 8151, 1);
    set(mem, OFFSET_M, 8160, 1);
    set(mem, OFFSET_M, 8001, 0);
    set(mem, OFFSET_M, 8002, first);
    set(mem, OFFSET_M, 8150, first);
    set(mem, OFFSET_M, 8003, !first);
}

void ladder_end_scan(LadderMemory *mem) {
    memcpy(AT(mem, OFFSET_OUTPUT_IMAGE), AT(mem, OFFSET_Y), 256);
    if (U32(mem, OFFSET_SCAN_COUNT) != UINT32_MAX) U32(mem, OFFSET_SCAN_COUNT) += 1;
}

/* The C API calls examples/host/main.c makes. */

LadderMemory *ladder_init(void *storage, size_t size) {
    if (storage == NULL || size < MEMORY_SIZE || (uintptr_t)storage % 4 != 0) return NULL;
    memset(storage, 0, MEMORY_SIZE);
    return storage;
}

LadderStatus ladder_set_input(LadderMemory *mem, uint32_t x, bool on) {
    if (mem == NULL || x >= 256) return LADDER_STATUS_OUT_OF_RANGE;
    *AT(mem, OFFSET_INPUT_IMAGE + x) = on;
    *AT(mem, OFFSET_X + x) = on;
    return LADDER_STATUS_OK;
}

int32_t ladder_get_output(const LadderMemory *mem, uint32_t y) {
    return mem != NULL && y < 256 ? *AT(mem, OFFSET_OUTPUT_IMAGE + y) : -1;
}

static int16_t d(const LadderMemory *mem, unsigned n) { return *(int16_t *)AT(mem, OFFSET_D + 2 * n); }

uint16_t ladder_operation_error(const LadderMemory *mem) {
    return *AT(mem, OFFSET_M + 8067) ? (uint16_t)d(mem, 8067) : 0;
}

uint16_t ladder_operation_error_line(const LadderMemory *mem) {
    return *AT(mem, OFFSET_M + 8067) ? (uint16_t)d(mem, 8069) : 0;
}

static void unsupported(const char *name) {
    fprintf(stderr, "shim: the program called %s, which the shim does not provide\n", name);
    abort();
}

void ladder_rt_timer_coil(void) { unsupported("ladder_rt_timer_coil"); }
void ladder_rt_counter_coil(void) { unsupported("ladder_rt_counter_coil"); }
void ladder_rt_reset_timer(void) { unsupported("ladder_rt_reset_timer"); }
void ladder_rt_reset_counter(void) { unsupported("ladder_rt_reset_counter"); }
void ladder_rt_schedule_state_off(void) { unsupported("ladder_rt_schedule_state_off"); }
void ladder_rt_block_move(void) { unsupported("ladder_rt_block_move"); }
