/* Startup for the Cortex-M example host: the vector table, and a reset
   handler that copies .data, clears .bss and calls main. */
#include <stdint.h>

extern uint32_t __data_load, __data_start, __data_end, __bss_start, __bss_end, __stack_top;
int main(void);

static void halt(void) { for (;;) {} }

/* Handlers a host may define; until it does, they halt. */
void Default_Handler(void) { halt(); }
void SysTick_Handler(void) __attribute__((weak, alias("Default_Handler")));

void Reset_Handler(void) {
    uint32_t *from = &__data_load, *to = &__data_start;
    while (to < &__data_end) *to++ = *from++;
    for (to = &__bss_start; to < &__bss_end;) *to++ = 0;
    main();
    halt();
}

__attribute__((section(".vectors"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))&__stack_top, /* initial stack pointer */
    Reset_Handler,
    halt, /* NMI */
    halt, /* HardFault */
    halt, halt, halt, 0, 0, 0, 0,
    halt, /* SVCall */
    halt, 0,
    halt, /* PendSV */
    SysTick_Handler,
};
