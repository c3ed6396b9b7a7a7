/* The measuring harness of the C firmwares (harness.h). */
#include "harness.h"

#include <stddef.h>

/* ---- semihosting ---- */

static int semihost(int op, const void *arg) {
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

static const char *firmware_name = "";
static char line[201];
static size_t len;

void out_str(const char *s) {
    while (*s && len + 1 < sizeof line) line[len++] = *s++;
}

void out_num(uint64_t n) {
    char digits[20];
    int i = 0;
    do {
        digits[i++] = (char)('0' + n % 10);
        n /= 10;
    } while (n && i < 20);
    while (i > 0 && len + 1 < sizeof line) line[len++] = digits[--i];
}

void out_int(int64_t n) {
    if (n < 0) out_str("-");
    out_num(n < 0 ? (uint64_t)0 - (uint64_t)n : (uint64_t)n);
}

void out_tenths(int64_t n) {
    uint64_t m;
    if (n < 0) out_str("-");
    m = n < 0 ? (uint64_t)0 - (uint64_t)n : (uint64_t)n;
    out_num(m / 10);
    out_str(".");
    out_num(m % 10);
}

static void prefix(void) {
    len = 0;
    out_str("m4f-bench ");
    out_str(firmware_name);
    out_str(": ");
}

/* The host's stdout: SYS_OPEN of ":tt" for writing (what cortex-m-semihosting's hstdout opens). */
static int stdout_handle = -1;

void out_begin(const char *firmware) {
    static const char tt[] = ":tt";
    uint32_t args[3];
    args[0] = (uint32_t)(uintptr_t)tt;
    args[1] = 4; /* "w" */
    args[2] = 3;
    stdout_handle = semihost(0x01 /* SYS_OPEN */, args);
    firmware_name = firmware;
    prefix();
}

void out_flush(void) {
    uint32_t args[3];
    line[len++] = '\n';
    args[0] = (uint32_t)stdout_handle;
    args[1] = (uint32_t)(uintptr_t)line;
    args[2] = (uint32_t)len;
    if (stdout_handle >= 0) semihost(0x05 /* SYS_WRITE */, args);
    prefix();
}

void finish(bool ok) {
    /* SYS_EXIT with ADP_Stopped_ApplicationExit (QEMU exits 0) or ADP_Stopped_RunTimeErrorUnknown (exits 1). */
    out_str("status ");
    out_str(ok ? "ok" : "FAILED");
    out_flush();
    semihost(0x18, (const void *)(uintptr_t)(ok ? 0x20026 : 0x20023));
    for (;;) __asm__ volatile("wfi");
}

/* ---- SysTick ---- */

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define RELOAD 0x00FFFFFFu

static uint64_t per_tick;

static void systick_start(void) {
    SYST_RVR = RELOAD;
    SYST_CVR = 0;
    SYST_CSR = 5; /* core clock, no interrupt, enabled */
}

/* Ticks while f runs `repeat` times. */
__attribute__((noinline)) static uint64_t ticks(uint32_t repeat, run_fn f, void *ctx, uint32_t *last) {
    uint32_t a = SYST_CVR, b, i, r = 0;
    for (i = 0; i < repeat; i++) {
        r = f(ctx);
        __asm__ volatile("" : : "r"(r) : "memory");
    }
    b = SYST_CVR;
    if (last) *last = r;
    return (uint64_t)((a - b) & RELOAD);
}

/* cortex_m::asm::delay's loop: n + 1 iterations of two instructions. */
__attribute__((noinline)) static void delay(uint32_t n) {
    __asm__ volatile("1: subs %0, #1\n bne 1b" : "+r"(n) : : "cc");
}

static uint32_t delay_run(void *n) {
    delay(*(uint32_t *)n);
    return *(uint32_t *)n;
}

void calibrate(void) {
    uint32_t s = 100000, l = 300000;
    uint64_t t_short, t_long, ins = 2u * (uint64_t)(l - s), tk;
    systick_start();
    t_short = ticks(1, delay_run, &s, NULL);
    t_long = ticks(1, delay_run, &l, NULL);
    tk = t_long > t_short ? t_long - t_short : 0;
    per_tick = tk ? ins / tk : 0;
    out_str("calibration_instructions ");
    out_num(ins);
    out_str(" calibration_ticks ");
    out_num(tk);
    out_str(" instructions_per_tick ");
    out_num(per_tick);
    out_flush();
}

uint64_t instructions(uint32_t repeat, run_fn f, void *ctx, uint32_t *last) {
    return ticks(repeat, f, ctx, last) * per_tick / repeat;
}

/* ---- the fit ---- */

void fit_add(fit *f, uint64_t x, uint64_t y) {
    f->n += 1;
    f->sx += (int64_t)x;
    f->sy += (int64_t)y;
    f->sxx += (int64_t)(x * x);
    f->sxy += (int64_t)(x * y);
}

static int64_t div_round(int64_t a, int64_t b) { return a >= 0 ? (a + b / 2) / b : (a - b / 2) / b; }

bool fit_slope_tenths(const fit *f, int64_t *slope10, int64_t *intercept) {
    int64_t den = f->n * f->sxx - f->sx * f->sx, num = f->n * f->sxy - f->sx * f->sy;
    if (den <= 0) return false;
    *slope10 = div_round(num * 10, den);
    *intercept = div_round(f->sy * den - num * f->sx, f->n * den);
    return true;
}

void print_fit(const fit *f, const char *points, const char *x, const char *slope) {
    int64_t b, a;
    out_str(points);
    out_num((uint64_t)f->n);
    out_str(x);
    out_num((uint64_t)f->sx);
    out_str(slope);
    if (fit_slope_tenths(f, &b, &a)) {
        out_tenths(b);
        out_str(" setup ");
        out_int(a);
    } else {
        out_str("none");
    }
    out_flush();
}

/* ---- the stack ---- */

#define PAINT 0xC5ACCE55u
#define DEPTH (16u * 1024u)

__attribute__((noinline)) static void paint(uint32_t bottom, uint32_t top) {
    for (; bottom < top; bottom += 4) *(volatile uint32_t *)bottom = PAINT;
}

__attribute__((noinline)) static uint32_t lowest_touched(uint32_t bottom, uint32_t top) {
    for (; bottom < top; bottom += 4)
        if (*(volatile uint32_t *)bottom != PAINT) return bottom;
    return top;
}

__attribute__((noinline)) uint32_t stack_high_water(run_fn f, void *ctx, uint32_t *result) {
    uint32_t sp, top, bottom, r;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    top = (sp - 64) & ~3u;
    bottom = sp - DEPTH;
    paint(bottom, top);
    r = f(ctx);
    __asm__ volatile("" : : "r"(r) : "memory");
    if (result) *result = r;
    return sp - lowest_touched(bottom, top);
}

uint32_t measure(fit *fits[], int nfits, uint32_t *stack, run_fn f, void *ctx) {
    uint32_t x = 0;
    uint64_t ins = instructions(REPEAT, f, ctx, &x);
    int i;
    if (x > 0 && x < UINT32_MAX) {
        uint32_t bytes;
        for (i = 0; i < nfits; i++) fit_add(fits[i], x, ins);
        bytes = stack_high_water(f, ctx, NULL);
        if (bytes > *stack) *stack = bytes;
    }
    return x;
}

bool loop_check(void) {
    fit f = {0, 0, 0, 0, 0};
    fit *fits[1];
    uint32_t stack = 0, k, n;
    int64_t b, a;
    fits[0] = &f;
    for (k = 1; k <= 16; k++) {
        n = 50 * k;
        measure(fits, 1, &stack, delay_run, &n);
    }
    out_str("delay_loop");
    print_fit(&f, " runs ", " iterations ", " loop_per_iteration ");
    return fit_slope_tenths(&f, &b, &a) && b == 20;
}

int32_t rng_next24(rng *r) {
    uint32_t x = r->x;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    r->x = x;
    return (int32_t)(x >> 8);
}

/* ---- reset ---- */

extern uint32_t __bss_start, __bss_end, __stack_top;
int main(void);

void reset(void) {
    uint32_t *p;
    /* Full access to the FPU (CP10, CP11) before any floating-point instruction. */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n isb" ::: "memory");
    for (p = &__bss_start; p < &__bss_end; p++) *p = 0;
    finish(main() == 0);
}

static void hang(void) {
    finish(false);
}

__attribute__((section(".vectors"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))&__stack_top, reset, hang, hang, hang, hang, hang, 0, 0, 0, 0, hang, hang, 0, hang, hang,
};
