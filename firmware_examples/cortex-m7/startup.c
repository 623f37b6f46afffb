/*
 * Minimal Cortex-M7 start-up for programs that use libsfm: vector table,
 * FPU enable, .data/.bss initialisation, then main(). Faults end the program
 * with a non-zero status through Arm semihosting (so an emulator run fails
 * loudly); on a board without a debugger, replace sfm_semihost_exit with the
 * board's own fault handling.
 */
#include <stdint.h>

/* main is called with a valid argv (argc 1): a main that reads its arguments
 * (the test runner's name filter) must not see stale registers. */
extern int main(int argc, char **argv);
extern void initialise_monitor_handles(void);
extern void __libc_init_array(void);
extern void exit(int status);

extern uint32_t __data_load, __data_start, __data_end, __bss_start__, __bss_end__, __stack_top;

#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)

/* Semihosting SYS_EXIT with ADP_Stopped_ApplicationExit (0x20026) or
 * ADP_Stopped_RunTimeError (0x20023). */
static void sfm_semihost_exit(int ok)
{
    register uint32_t r0 __asm__("r0") = 0x18u;
    register uint32_t r1 __asm__("r1") = ok ? 0x20026u : 0x20023u;
    __asm__ volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
    for (;;) {
    }
}

static void sfm_semihost_write0(const char *s)
{
    register uint32_t r0 __asm__("r0") = 0x04u; /* SYS_WRITE0 */
    register const char *r1 __asm__("r1") = s;
    __asm__ volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
}

void sfm_fault_handler(void)
{
    sfm_semihost_write0("FATAL: processor fault\n");
    sfm_semihost_exit(0);
}

void sfm_reset_handler(void)
{
    /* Full access to CP10 and CP11 (the FPU) before any floating point. */
    SCB_CPACR |= (0xFu << 20);
    __asm__ volatile("dsb\n\tisb" ::: "memory");

    uint32_t *src = &__data_load, *dst = &__data_start;
    while (dst < &__data_end)
        *dst++ = *src++;
    for (dst = &__bss_start__; dst < &__bss_end__;)
        *dst++ = 0;

    initialise_monitor_handles();
    __libc_init_array();
    static char prog[] = "sfm";
    static char *argv[] = {prog, 0};
    exit(main(1, argv));
}

/* -nostartfiles drops crti/crtn; newlib's init/fini arrays still call these. */
void _init(void);
void _fini(void);
void _init(void)
{
}
void _fini(void)
{
}

static void sfm_default_handler(void)
{
    sfm_fault_handler();
}

__attribute__((section(".vectors"), used)) static void (*const sfm_vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&__stack_top,
    sfm_reset_handler,
    sfm_default_handler, /* NMI */
    sfm_fault_handler,   /* HardFault */
    sfm_fault_handler,   /* MemManage */
    sfm_fault_handler,   /* BusFault */
    sfm_fault_handler,   /* UsageFault */
    0, 0, 0, 0,
    sfm_default_handler, /* SVC */
    sfm_default_handler, /* DebugMon */
    0,
    sfm_default_handler, /* PendSV */
    sfm_default_handler, /* SysTick */
};
