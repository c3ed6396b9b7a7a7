/*
 * The C firmwares: the kernel's C interface (libcurvicast.a) on an emulated Cortex-M4F, measured as
 * kernel/m4f-bench measures the Rust firmwares, on the same workloads, so that the cost of the C boundary is
 * a difference of two measurements:
 *   c-march-f32 (BENCH_MARCH): march-f32's benchmark (two full-sphere grids of 16^3 and 32^3 non-uniform cells,
 *     48 rays each, the same rays) through curvicast_march_f32_fill, in batches of 32 crossings;
 *   c-march-next-f32 (BENCH_MARCH and MARCH_NEXT): the same through curvicast_march_f32_next, one call per
 *     crossing;
 *   c-pick-f32 (BENCH_PICK): pick-f32's benchmark (a 9 x 9 DEM near 45 N 7 E, one leaf of 8 x 8 cells, 32 rays
 *     from 5 km up) through curvicast_terrain_f32_build, curvicast_picker_f32_init and curvicast_picker_f32_pick;
 *   c-empty (neither): the harness alone, the size the other two are measured against.
 * Each checks its answers (the marches agree between next and fill; the picks hit within the DEM's heights)
 * and ends with "status ok" (QEMU exit 0) or "status FAILED".
 */
#include "curvicast.h"
#include "harness.h"

#if defined(BENCH_MARCH)

#define MAX 33
static const size_t breakpoint_counts[2] = {17, 33};
#define RAYS_PER_GRID 48u

/* n non-uniform breakpoints from lo to hi (both exact), as m4f-bench's `grid_breakpoints`. */
static void breakpoints(float lo, float hi, float *out, size_t n) {
    size_t i, last = n - 1;
    float d = (float)(int32_t)last;
    for (i = 0; i < n; i++) {
        float u = (float)(int32_t)i / d;
        out[i] = i == last ? hi : lo + (hi - lo) * u * (1.0f + u) * 0.5f;
    }
}

/* A point at distance s from the center in a direction drawn from r (m4f-bench's `ray_ends`). */
static void unit(rng *r, float s, float p[3]) {
    const float scale = (float)(1 << 23);
    float l2, l;
    int k;
    for (k = 0; k < 3; k++) p[k] = (float)rng_next24(r) / scale - 1.0f;
    l2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    __asm__("vsqrt.f32 %0, %1" : "=t"(l) : "t"(l2));
    if (l > 0.0f) {
        for (k = 0; k < 3; k++) p[k] *= s / l;
    } else {
        p[0] = s;
        p[1] = p[2] = 0.0f;
    }
}

typedef struct {
    curvicast_grid_f32 *grid;
    curvicast_ray_f32 ray;
} march_ctx;

#define BATCH 32

/* One march folded as m4f-bench's `march_once` (length, cells, count); returns the crossings, or UINT32_MAX on
   an error. */
static uint32_t march_once(void *p) {
    march_ctx *c = p;
    curvicast_march_f32 march;
    float length = 0.0f;
    uint32_t cells = 0, count = 0;
    curvicast_status s = curvicast_march_f32_begin(&march, c->grid, &c->ray);
    if (s != CURVICAST_OK) return UINT32_MAX;
#if defined(MARCH_NEXT)
    {
        curvicast_crossing_f32 x;
        while ((s = curvicast_march_f32_next(&march, &x)) == CURVICAST_OK) {
            length += x.t_exit - x.t_enter;
            cells += x.cell[0] ^ ((x.cell[1] << 8) | (x.cell[1] >> 24)) ^ ((x.cell[2] << 16) | (x.cell[2] >> 16));
            count++;
        }
    }
#else
    {
        curvicast_crossing_f32 batch[BATCH];
        size_t n, i;
        do {
            s = curvicast_march_f32_fill(&march, batch, BATCH, &n);
            for (i = 0; i < n; i++) {
                const curvicast_crossing_f32 *x = &batch[i];
                length += x->t_exit - x->t_enter;
                cells += x->cell[0] ^ ((x->cell[1] << 8) | (x->cell[1] >> 24)) ^
                         ((x->cell[2] << 16) | (x->cell[2] >> 16));
                count++;
            }
        } while (s == CURVICAST_OK);
    }
#endif
    __asm__ volatile("" : : "r"(length), "r"(cells) : "memory");
    return s == CURVICAST_DONE ? count : UINT32_MAX;
}

int main(void) {
    static float r[MAX], th[MAX], ph[MAX], ws[5 * MAX];
    static curvicast_grid_f32 grid;
    fit all = {0, 0, 0, 0, 0};
    uint32_t stack = 0, ray_i;
    rng random = {0x5EED0017u | 1u};
    int ok, g;
#if defined(MARCH_NEXT)
    out_begin("c-march-next-f32");
#else
    out_begin("c-march-f32");
#endif
    calibrate();
    ok = loop_check();
    for (g = 0; g < 2; g++) {
        size_t n = breakpoint_counts[g];
        fit one = {0, 0, 0, 0, 0};
        fit *fits[2];
        fits[0] = &one;
        fits[1] = &all;
        breakpoints(0.0f, 1.0f, r, n);
        breakpoints(0.0f, 3.14159274f, th, n);
        breakpoints(0.0f, 3.14159274f + 3.14159274f, ph, n);
        if (curvicast_spherical_grid_f32_init(&grid, r, n, th, n, ph, n, 0, ws,
                                              curvicast_spherical_workspace_len(n, n, n)) != CURVICAST_OK)
            return 1;
        for (ray_i = 0; ray_i < RAYS_PER_GRID; ray_i++) {
            march_ctx c;
            float from[3], to[3];
            int k;
            unit(&random, 2.5f, from);
            unit(&random, 0.9f, to);
            for (k = 0; k < 3; k++) {
                c.ray.origin[k] = from[k];
                c.ray.dir[k] = to[k] - from[k];
            }
            c.ray.t_min = 0.0f;
            c.ray.t_max = __builtin_inff();
            c.grid = &grid;
            if (measure(fits, 2, &stack, march_once, &c) == UINT32_MAX) ok = 0;
        }
        out_str("grid ");
        out_num(n - 1);
        out_str("^3");
        print_fit(&one, " rays ", " crossings ", " per_crossing ");
    }
    out_str("grid both");
    print_fit(&all, " rays ", " crossings ", " per_crossing ");
    out_str("march_stack_bytes ");
    out_num(stack);
    out_flush();
    return ok ? 0 : 1;
}

#elif defined(BENCH_PICK)

#define N 9u
#define BLOCK 8u
#define PICKS 32u

typedef struct {
    const curvicast_picker_f32 *picker;
    curvicast_ray_f32 ray;
} pick_ctx;

/* 1: a hit within the DEM's heights; 0: no such hit; 2: an error. */
static uint32_t pick_once(void *p) {
    pick_ctx *c = p;
    curvicast_hit_f32 hit;
    curvicast_status s = curvicast_picker_f32_pick(c->picker, &c->ray, &hit, 0);
    if (s == CURVICAST_OK) return hit.h >= 0.0f && hit.h <= 300.5f ? 1 : 0;
    return s == CURVICAST_NO_HIT ? 0 : 2;
}

static float coord(rng *r, float lo) { return lo + 0.005f + 0.07f * ((float)rng_next24(r) / 16777216.0f); }

int main(void) {
    static float heights[N * N];
    static curvicast_node_record nodes[4];
    static curvicast_terrain_f32 terrain;
    static curvicast_picker_f32 picker;
    curvicast_dem_grid_f32 grid = {45.0f, 7.0f, 0.01f, 0.01f, N, N};
    rng random = {0x000091CCu | 1u};
    uint64_t total = 0;
    uint32_t hits = 0, stack = 0, i, k;
    int ok;
    out_begin("c-pick-f32");
    calibrate();
    ok = loop_check();
    for (i = 0; i < N * N; i++) heights[i] = 50.0f * (float)((3 * (i / N) + 5 * (i % N)) % 7);
    if (curvicast_node_slots(N, N, BLOCK) > sizeof nodes / sizeof nodes[0]) return 1;
    if (curvicast_terrain_f32_build(&terrain, &grid, heights, N * N, BLOCK, nodes,
                                    curvicast_node_slots(N, N, BLOCK)) != CURVICAST_OK)
        return 1;
    if (curvicast_picker_f32_init(&picker, &terrain, 0) != CURVICAST_OK) return 1;
    for (i = 0; i < PICKS; i++) {
        pick_ctx c;
        float from[3], to[3];
        uint32_t hit = 0, bytes;
        float lat = coord(&random, 45.0f), lon = coord(&random, 7.0f);
        curvicast_wgs84_to_ecef_f32(lat, lon, 5000.0f, from);
        lat = coord(&random, 45.0f);
        lon = coord(&random, 7.0f);
        curvicast_wgs84_to_ecef_f32(lat, lon, 0.0f, to);
        for (k = 0; k < 3; k++) {
            c.ray.origin[k] = from[k];
            c.ray.dir[k] = to[k] - from[k];
        }
        c.ray.t_min = 0.0f;
        c.ray.t_max = __builtin_inff();
        c.picker = &picker;
        total += instructions(1, pick_once, &c, &hit);
        if (hit == 1) hits++;
        else if (hit == 2) ok = 0;
        bytes = stack_high_water(pick_once, &c, 0);
        if (bytes > stack) stack = bytes;
    }
    out_str("picks ");
    out_num(PICKS);
    out_str(" hits ");
    out_num(hits);
    out_str(" per_pick ");
    out_num(total / PICKS);
    out_str(" stack_bytes ");
    out_num(stack);
    out_flush();
    return ok && hits > 0 ? 0 : 1;
}

#else

int main(void) {
    bool ok;
    out_begin("c-empty");
    calibrate();
    ok = loop_check();
    return ok ? 0 : 1;
}

#endif
