/*
 * The C side of the C interface's host test: reads the cases of `c_cases emit` (kernel/ffi/examples/c_cases.rs)
 * on stdin, answers them through libcurvicast.a, and prints the answers in the format `c_cases run` prints
 * them with the kernel's Rust API. check-host.sh compares the two outputs byte for byte.
 *
 * Numbers travel as the hex bits of their float or double. The precision-generic part is cases_impl.h,
 * included once per precision.
 */
#include "curvicast.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The longest case line (a DEM of 3072 heights is about 34 000 characters). */
static char line[1 << 20];

/* The next token of the current line, or "" at its end. */
static const char *tok(void) {
    const char *t = strtok(NULL, " \t\r\n");
    return t ? t : "";
}

static long int_tok(void) { return strtol(tok(), NULL, 10); }

static float f32_tok(void) {
    uint32_t bits = (uint32_t)strtoul(tok(), NULL, 16);
    float x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

static double f64_tok(void) {
    uint64_t bits = (uint64_t)strtoull(tok(), NULL, 16);
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

static void hex_f32(char *out, float x) {
    uint32_t bits;
    memcpy(&bits, &x, sizeof bits);
    sprintf(out, "0x%08" PRIx32, bits);
}

static void hex_f64(char *out, double x) {
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    sprintf(out, "0x%016" PRIx64, bits);
}

/* FNV-1a over a number's text and a space (the bevel's checksum, as the Rust side forms it). */
static void fnv(uint64_t *h, const char *s) {
    for (; *s; s++) *h = (*h ^ (uint8_t)*s) * UINT64_C(0x100000001b3);
    *h = (*h ^ (uint8_t)' ') * UINT64_C(0x100000001b3);
}

static void *alloc(size_t n, size_t size) {
    void *p = calloc(n ? n : 1, size);
    if (!p) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    return p;
}

#define T float
#define SUFFIX _f32
#define HEX hex_f32
#define READ f32_tok
#include "cases_impl.h"
#undef T
#undef SUFFIX
#undef HEX
#undef READ

#define T double
#define SUFFIX _f64
#define HEX hex_f64
#define READ f64_tok
#include "cases_impl.h"
#undef T
#undef SUFFIX
#undef HEX
#undef READ

/* Every function of the header, referenced so that the link-time panic-path proof covers all of them. */
#include "all_functions.h"

int main(void) {
    int current = 0; /* the precision of the current terrain: 32 or 64 */
    size_t n;
    for (n = 0; n < sizeof curvicast_all_functions / sizeof curvicast_all_functions[0]; n++) {
        if (!curvicast_all_functions[n]) return 3;
    }
    n = 0;
    while (fgets(line, sizeof line, stdin)) {
        const char *word = strtok(line, " \t\r\n");
        const char *bits;
        n++;
        if (!word) continue;
        if (!strcmp(word, "march")) {
            const char *kind = tok();
            bits = tok();
            if (!strcmp(bits, "32")) march_f32(kind[0]);
            else march_f64(kind[0]);
        } else if (!strcmp(word, "terrain")) {
            bits = tok();
            current = !strcmp(bits, "32") ? 32 : 64;
            if (current == 32) terrain_f32();
            else terrain_f64();
        } else if (!strcmp(word, "pick")) {
            if (current == 32) pick_f32();
            else pick_f64();
        } else if (!strcmp(word, "los")) {
            if (current == 32) los_f32();
            else los_f64();
        } else if (!strcmp(word, "level")) {
            bits = tok();
            if (!strcmp(bits, "32")) level_f32();
            else level_f64();
        } else if (!strcmp(word, "bevel")) {
            bits = tok();
            if (!strcmp(bits, "32")) bevel_f32();
            else bevel_f64();
        } else {
            fprintf(stderr, "line %lu: malformed case\n", (unsigned long)n);
            return 2;
        }
    }
    return 0;
}
