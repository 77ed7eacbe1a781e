/*
 * Test shim, not a runtime: the scan-boundary calls of the ladderc runtime
 * (runtime/src/scan.rs) and the loop watchdog's helper, for programs that
 * use no other runtime helper (nor high-speed counters), so that
 * cross-compiled program code can run under qemu-user where the Rust runtime
 * cannot be built. Forces are not supported (the driver uses none). Offsets
 * and the parts of the machine (runtime/src/machine.rs) come from layout.h,
 * generated from the runtime by the test.
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

static int16_t *dw(LadderMemory *mem, unsigned n) { return (int16_t *)AT(mem, OFFSET_D + 2 * n); }

/* The calendar clock and the scan-time registers, as runtime/src/calendar.rs
   keeps them: seconds since 1980-01-01, D8013-D8019, D8010-D8012, M8015-M8018. */
static int leap(unsigned y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }
static unsigned month_days(unsigned y, unsigned m) {
    static const unsigned days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    return m == 2 && leap(y) ? 29 : days[m - 1];
}
static int to_seconds(unsigned y, unsigned mo, unsigned d, unsigned h, unsigned mi, unsigned s, uint32_t *out) {
    if (y < 1980 || y > 2079 || mo < 1 || mo > 12 || d < 1 || d > month_days(y, mo) || h > 23 || mi > 59 || s > 59)
        return 0;
    uint32_t days = 0;
    for (unsigned year = 1980; year < y; year++) days += leap(year) ? 366 : 365;
    for (unsigned month = 1; month < mo; month++) days += month_days(y, month);
    *out = (days + d - 1) * 86400u + h * 3600u + mi * 60u + s;
    return 1;
}
static void write_clock(LadderMemory *mem) {
    uint32_t seconds = U32(mem, OFFSET_CALENDAR_SECONDS), days = seconds / 86400u, in_day = seconds % 86400u;
    unsigned weekday = (days + 2) % 7, year = 1980, month = 1;
    while (days >= (leap(year) ? 366u : 365u)) days -= leap(year++) ? 366u : 365u;
    while (days >= month_days(year, month)) days -= month_days(year, month++);
    unsigned shown = (U32(mem, OFFSET_CALENDAR_FLAGS) & 1) ? year : year % 100;
    unsigned fields[7] = {in_day % 60, in_day % 3600 / 60, in_day / 3600, days + 1, month, shown, weekday};
    for (unsigned k = 0; k < 7; k++) *dw(mem, 8013 + k) = (int16_t)fields[k];
    /* The runtime keeps the time it showed, worked out once per second. */
    U32(mem, OFFSET_CALENDAR_CACHE_AT) = seconds + 1;
    U32(mem, OFFSET_CALENDAR_CACHE_TIME) = fields[0] | fields[1] << 6 | fields[2] << 12 | fields[3] << 17 |
                                           fields[4] << 22 | fields[6] << 26;
    U32(mem, OFFSET_CALENDAR_CACHE_YEAR) = year;
}
static unsigned full_year(int y) {
    if (y >= 0 && y <= 79) return 2000u + (unsigned)y;
    if (y >= 80 && y <= 99) return 1900u + (unsigned)y;
    return (unsigned)y;
}
static void record_scan_time(LadderMemory *mem, uint32_t elapsed_ms) {
    uint64_t tenths = (uint64_t)elapsed_ms * 10u;
    int16_t now = (int16_t)(tenths > 32767u ? 32767u : tenths);
    int first = U32(mem, OFFSET_SCAN_COUNT) == 0;
    *dw(mem, 8010) = now;
    if (first || now < *dw(mem, 8011)) *dw(mem, 8011) = now;
    if (first || now > *dw(mem, 8012)) *dw(mem, 8012) = now;
}
static void tick_calendar(LadderMemory *mem, uint32_t elapsed_ms) {
    uint32_t last = 0;
    to_seconds(2079, 12, 31, 23, 59, 59, &last);
    uint64_t ms = (uint64_t)U32(mem, OFFSET_CALENDAR_MS) + elapsed_ms;
    uint64_t seconds = (uint64_t)U32(mem, OFFSET_CALENDAR_SECONDS) + ms / 1000u;
    U32(mem, OFFSET_CALENDAR_SECONDS) = (uint32_t)(seconds < last ? seconds : last);
    U32(mem, OFFSET_CALENDAR_MS) = (uint32_t)(ms % 1000u);
}
static void advance_calendar(LadderMemory *mem, uint32_t elapsed_ms, uint32_t machine) {
    if (!(machine & MACHINE_CALENDAR)) {
        tick_calendar(mem, elapsed_ms);
        return;
    }
    set(mem, OFFSET_M, 8018, 1);
    int stopped = *AT(mem, OFFSET_M + 8015) != 0, was_stopped = (U32(mem, OFFSET_CALENDAR_FLAGS) & 2) != 0;
    U32(mem, OFFSET_CALENDAR_FLAGS) = (U32(mem, OFFSET_CALENDAR_FLAGS) & ~2u) | (stopped ? 2u : 0u);
    if (stopped) return;
    if (was_stopped) {
        uint32_t seconds = 0;
        int valid = 1;
        for (unsigned k = 0; k < 6; k++) valid = valid && *dw(mem, 8013 + k) >= 0;
        valid = valid && to_seconds(full_year(*dw(mem, 8018)), (unsigned)*dw(mem, 8017), (unsigned)*dw(mem, 8016),
                                    (unsigned)*dw(mem, 8015), (unsigned)*dw(mem, 8014), (unsigned)*dw(mem, 8013), &seconds);
        if (valid) {
            U32(mem, OFFSET_CALENDAR_SECONDS) = seconds;
            U32(mem, OFFSET_CALENDAR_MS) = 0;
        }
        write_clock(mem);
        set(mem, OFFSET_M, 8019, !valid);
        return;
    }
    int rounding = *AT(mem, OFFSET_M + 8017) != 0, was_rounding = (U32(mem, OFFSET_CALENDAR_FLAGS) & 4) != 0;
    U32(mem, OFFSET_CALENDAR_FLAGS) = (U32(mem, OFFSET_CALENDAR_FLAGS) & ~4u) | (rounding ? 4u : 0u);
    tick_calendar(mem, elapsed_ms);
    uint32_t last = 0;
    to_seconds(2079, 12, 31, 23, 59, 59, &last);
    if (rounding && !was_rounding) {
        uint32_t now = U32(mem, OFFSET_CALENDAR_SECONDS), minute = now - now % 60;
        U32(mem, OFFSET_CALENDAR_SECONDS) = now % 60 >= 30 ? (minute + 60 < last ? minute + 60 : last) : minute;
        U32(mem, OFFSET_CALENDAR_MS) = 0;
    }
    if (*dw(mem, 8018) == 2000) U32(mem, OFFSET_CALENDAR_FLAGS) |= 1;
    if (!*AT(mem, OFFSET_M + 8016)) write_clock(mem);
}

uint32_t LADDER_TAGGED_BEGIN_SCAN(LadderMemory *mem, uint32_t elapsed_ms, const uint32_t *layout, uint32_t machine);
uint32_t LADDER_TAGGED_BEGIN_SCAN(LadderMemory *mem, uint32_t elapsed_ms, const uint32_t *layout, uint32_t machine) {
    /* The full layout only, as the runtime: an image ladder_init made. */
    if (mem == NULL || layout != NULL || U32(mem, OFFSET_HEADER) != FULL_MAGIC) return 0;
    U32(mem, OFFSET_ELAPSED_MS) = elapsed_ms;
    uint8_t previous[8];
    memcpy(previous, AT(mem, OFFSET_X), 8);
    memcpy(AT(mem, OFFSET_X), AT(mem, OFFSET_INPUT_IMAGE), 256);
    /* The edges the input refresh saw (the high-speed counters' inputs). */
    for (unsigned x = 0; x < 8 && (machine & MACHINE_HIGH_SPEED); x++) {
        uint32_t rose = *AT(mem, OFFSET_X + x) && !previous[x];
        uint32_t *pending = (uint32_t *)AT(mem, OFFSET_PULSES_PENDING + 4 * x);
        uint64_t edges = (uint64_t)rose + *pending;
        *(uint32_t *)AT(mem, OFFSET_INPUT_EDGES + 4 * x) = edges > UINT32_MAX ? UINT32_MAX : (uint32_t)edges;
        *pending = 0;
    }
    if (machine & MACHINE_SCAN_TIME) record_scan_time(mem, elapsed_ms);
    advance_calendar(mem, elapsed_ms, machine);
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
    if (machine & MACHINE_SYSTEM_RELAYS) {
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
    /* Clock relays M8011-M8014 from the accumulated time, and the loop
       watchdog's count, as runtime/src/scan.rs does. */
    U32(mem, OFFSET_CLOCK_MS) = (uint32_t)(((uint64_t)U32(mem, OFFSET_CLOCK_MS) + elapsed_ms) % 60000u);
    static const uint32_t periods[4] = {10, 100, 1000, 60000};
    for (unsigned k = 0; k < 4 && (machine & MACHINE_CLOCK_RELAYS); k++) {
        set(mem, OFFSET_M, 8011 + k, U32(mem, OFFSET_CLOCK_MS) % periods[k] >= periods[k] / 2);
    }
    U32(mem, OFFSET_LOOP_REPETITIONS) = 0;
    return 1;
}

int32_t ladder_rt_loop_repeat(LadderMemory *mem, uint32_t line) {
    if (U32(mem, OFFSET_LOOP_REPETITIONS) >= LOOP_REPETITION_LIMIT) {
        set(mem, OFFSET_M, 8067, 1);
        *(int16_t *)AT(mem, OFFSET_D + 2 * 8067) = (int16_t)0x6509;
        *(int16_t *)AT(mem, OFFSET_D + 2 * 8069) = (int16_t)line;
        return 0;
    }
    U32(mem, OFFSET_LOOP_REPETITIONS) += 1;
    return 1;
}

void LADDER_TAGGED_END_SCAN(LadderMemory *mem, uint32_t machine);
void LADDER_TAGGED_END_SCAN(LadderMemory *mem, uint32_t machine) {
    if ((machine & MACHINE_ALARMS) && *AT(mem, OFFSET_SM + 249)) {
        unsigned lowest = 0;
        for (unsigned s = 900; s <= 999 && !lowest; s++) lowest = *AT(mem, OFFSET_S + s) ? s : 0;
        set(mem, OFFSET_SM, 248, lowest != 0);
        *(int16_t *)AT(mem, OFFSET_SD + 2 * 249) = (int16_t)lowest;
    }
    memcpy(AT(mem, OFFSET_OUTPUT_IMAGE), AT(mem, OFFSET_Y), 256);
    if (U32(mem, OFFSET_SCAN_COUNT) != UINT32_MAX) U32(mem, OFFSET_SCAN_COUNT) += 1;
}

/* The C API calls examples/host/main.c makes. */

LadderMemory *ladder_init(void *storage, size_t size) {
    if (storage == NULL || size < MEMORY_SIZE || (uintptr_t)storage % 4 != 0) return NULL;
    memset(storage, 0, MEMORY_SIZE);
    U32(storage, OFFSET_HEADER) = FULL_MAGIC;
    U32(storage, OFFSET_HEADER + 4) = MEMORY_SIZE;
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

/* The one runtime helper the shim implements: cross_check.il has offsets
   out of range. The other helpers abort (helper_stubs.c, generated by the
   test from the runtime's helper declarations, which also checks that this
   definition matches its declaration). */
void ladder_rt_record_error(LadderMemory *mem, uint32_t code, uint32_t line) {
    *AT(mem, OFFSET_M + 8067) = 1;
    *(int16_t *)AT(mem, OFFSET_D + 2 * 8067) = (int16_t)code;
    *(int16_t *)AT(mem, OFFSET_D + 2 * 8069) = (int16_t)(uint16_t)line;
}
