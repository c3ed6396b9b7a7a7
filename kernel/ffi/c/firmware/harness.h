/*
 * The measuring harness of the C firmwares, the C twin of kernel/m4f-bench/src/lib.rs: semihosting output
 * (integers and strings only), SysTick as an instruction counter under QEMU's -icount shift=0, a least-squares
 * fit in integers, a painted-stack high-water mark, and the exit. Output lines start with
 * "m4f-bench <firmware>:" so that m4f-bench/run.sh reads them as it reads the Rust firmwares'.
 */
#ifndef HARNESS_H
#define HARNESS_H

#include <stdbool.h>
#include <stdint.h>

/* One output line. */
void out_str(const char *s);
void out_num(uint64_t n);
void out_int(int64_t n);
void out_tenths(int64_t n);
void out_flush(void);
void out_begin(const char *firmware);

/* Instructions per run of f(ctx) over `repeat` runs, and the last run's result in *last. */
typedef uint32_t (*run_fn)(void *ctx);
uint64_t instructions(uint32_t repeat, run_fn f, void *ctx, uint32_t *last);
void calibrate(void);

/* Least-squares line y = a + b x over (x, y) points, in exact integer sums. */
typedef struct {
    int64_t n, sx, sy, sxx, sxy;
} fit;
void fit_add(fit *f, uint64_t x, uint64_t y);
void print_fit(const fit *f, const char *points, const char *x, const char *slope);
/* 10 × slope, rounded; false with fewer than two distinct x. */
bool fit_slope_tenths(const fit *f, int64_t *slope10, int64_t *intercept);

/* Runs timed together per point, as the Rust harness's REPEAT. */
#define REPEAT 8u
/* One point of a series (the Rust harness's `measure`): returns run's x. */
uint32_t measure(fit *fits[], int nfits, uint32_t *stack, run_fn f, void *ctx);
uint32_t stack_high_water(run_fn f, void *ctx, uint32_t *result);
bool loop_check(void);

/* xorshift32, as the Rust harness's Rng. */
typedef struct {
    uint32_t x;
} rng;
int32_t rng_next24(rng *r);

void finish(bool ok);

#endif
