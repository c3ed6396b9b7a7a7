/*
 * The precision-generic half of cases.c, included once per precision with T (float or double), SUFFIX (_f32
 * or _f64), HEX (the bits printer) and READ (the bits reader) defined.
 */
#define PASTE3(a, b, c) a##b##c
#define XPASTE3(a, b, c) PASTE3(a, b, c)
/* curvicast_<x>_f32 / _f64 */
#define CC(x) XPASTE3(curvicast_, x, SUFFIX)
/* curvicast_<x>_f32<rest> */
#define CCR(x, rest) XPASTE3(CC(x), rest, )
/* this file's own function <x>_f32 */
#define OWN(x) XPASTE3(x, SUFFIX, )

/* Reads a count and that many numbers (into a new array). */
static T *OWN(read_list)(size_t *len) {
    size_t i;
    T *v;
    *len = (size_t)int_tok();
    v = alloc(*len, sizeof(T));
    for (i = 0; i < *len; i++) v[i] = READ();
    return v;
}

static CC(ray) OWN(read_ray)(void) {
    CC(ray) r;
    int k;
    for (k = 0; k < 3; k++) r.origin[k] = READ();
    for (k = 0; k < 3; k++) r.dir[k] = READ();
    r.t_min = READ();
    r.t_max = READ();
    return r;
}

static void OWN(march)(char kind) {
    size_t len[3] = {0, 0, 0}, need, shortfall, i, written = 0, got = 0;
    T *axis[3] = {NULL, NULL, NULL}, center[3] = {0, 0, 0}, *ws;
    int n_axes = kind == 'P' ? 2 : 3, k, has_center, agree = 1;
    CC(grid) grid;
    CC(march) march;
    CC(ray) ray;
    CC(crossing) c, batch[3];
    char a[24], b[24];
    curvicast_status s, end;
    for (k = 0; k < n_axes; k++) axis[k] = OWN(read_list)(&len[k]);
    has_center = int_tok() != 0;
    if (has_center) {
        for (k = 0; k < (kind == 'P' ? 2 : 3); k++) center[k] = READ();
    }
    ray = OWN(read_ray)();
    shortfall = (size_t)int_tok();
    need = kind == 'S'   ? curvicast_spherical_workspace_len(len[0], len[1], len[2])
           : kind == 'C' ? curvicast_cylindrical_workspace_len(len[0], len[1])
                         : curvicast_polar_workspace_len(len[0], len[1]);
    need = need > shortfall ? need - shortfall : 0;
    ws = alloc(need, sizeof(T));
    if (kind == 'S')
        s = CCR(spherical_grid, _init)(&grid, axis[0], len[0], axis[1], len[1], axis[2], len[2],
                                       has_center ? center : NULL, ws, need);
    else if (kind == 'C')
        s = CCR(cylindrical_grid, _init)(&grid, axis[0], len[0], axis[1], len[1], axis[2], len[2],
                                         has_center ? center : NULL, ws, need);
    else
        s = CCR(polar_grid, _init)(&grid, axis[0], len[0], axis[1], len[1], has_center ? center : NULL, ws,
                                   need);
    if (s != CURVICAST_OK) {
        printf("M %u -\n", (unsigned)s);
    } else if ((s = CCR(march, _begin)(&march, &grid, &ray)) != CURVICAST_OK) {
        printf("M 0 %u\n", (unsigned)s);
    } else {
        /* One crossing per call, then the same march in batches of 3, which must agree. */
        printf("M 0 0\n");
        while ((s = CCR(march, _next)(&march, &c)) == CURVICAST_OK) {
            HEX(a, c.t_enter);
            HEX(b, c.t_exit);
            printf("  %" PRIu32 " %" PRIu32 " %" PRIu32 " %s %s\n", c.cell[0], c.cell[1], c.cell[2], a, b);
            got++;
        }
        printf("  end %u\n", (unsigned)s);
        end = s;
        CCR(march, _begin)(&march, &grid, &ray);
        i = 0;
        do {
            s = CCR(march, _fill)(&march, batch, 3, &written);
            i += written;
        } while (s == CURVICAST_OK && written == 3);
        agree = i == got && s == end;
        printf("  fill %s\n", agree ? "agrees" : "differs");
    }
    for (k = 0; k < 3; k++) free(axis[k]);
    free(ws);
}

/* The terrain of the last `terrain` line of this precision, its buffers and its picker. */
static CC(terrain) OWN(the_terrain);
static CC(picker) OWN(the_picker);
static float *OWN(heights);
static curvicast_node_record *OWN(nodes);
static bool *OWN(resident);
static size_t OWN(resident_len);

static void OWN(terrain)(void) {
    CC(dem_grid) g;
    CC(multires) shape;
    uint32_t block;
    size_t n_heights, i, slots;
    int multires = int_tok() != 0;
    curvicast_status s;
    g.rows = (uint32_t)int_tok();
    g.cols = (uint32_t)int_tok();
    g.lat0_deg = READ();
    g.lon0_deg = READ();
    g.dlat_deg = READ();
    g.dlon_deg = READ();
    block = (uint32_t)int_tok();
    if (multires) {
        shape.has_fine_region = int_tok() != 0;
        for (i = 0; i < 4; i++) shape.fine_region[i] = shape.has_fine_region ? READ() : 0;
        shape.coarse_level = (uint32_t)int_tok();
    }
    free(OWN(heights));
    free(OWN(nodes));
    free(OWN(resident));
    n_heights = (size_t)int_tok();
    OWN(heights) = alloc(n_heights, sizeof(float));
    for (i = 0; i < n_heights; i++) OWN(heights)[i] = f32_tok();
    slots = curvicast_node_slots(g.rows, g.cols, block);
    OWN(nodes) = alloc(slots, sizeof(curvicast_node_record));
    /* Multi-resolution: every block paged out; the picks page them in one by one. */
    OWN(resident_len) = multires ? slots : 0;
    OWN(resident) = alloc(slots, sizeof(bool));
    if (multires)
        s = CCR(terrain, _build_multires)(&OWN(the_terrain), &g, OWN(heights), n_heights, block, &shape,
                                          OWN(nodes), slots, OWN(resident), OWN(resident_len));
    else
        s = CCR(terrain, _build)(&OWN(the_terrain), &g, OWN(heights), n_heights, block, OWN(nodes), slots);
    if (s != CURVICAST_OK) {
        printf("T %u -\n", (unsigned)s);
        return;
    }
    s = CCR(picker, _init)(&OWN(the_picker), &OWN(the_terrain), 0);
    printf("T 0 %u\n", (unsigned)s);
}

/* Pages in the block of every NEEDS_BLOCK answer (printing the node) until the answer is another. */
#define PAGING(call)                                                                                        \
    do {                                                                                                    \
        s = (call);                                                                                         \
        if (s != CURVICAST_TERRAIN_NEEDS_BLOCK || node >= OWN(resident_len)) break;                         \
        printf("  needs %" PRIu32 "\n", node);                                                              \
        OWN(resident)[node] = true;                                                                         \
    } while (1)

static void OWN(pick)(void) {
    CC(ray) ray = OWN(read_ray)();
    CC(hit) h;
    T t;
    uint32_t cell[2], node = UINT32_MAX;
    char x[6][24];
    curvicast_status s;
    printf("P\n");
    PAGING(CCR(picker, _pick)(&OWN(the_picker), &ray, &h, &node));
    if (s == CURVICAST_OK) {
        HEX(x[0], h.t);
        HEX(x[1], h.ecef[0]);
        HEX(x[2], h.ecef[1]);
        HEX(x[3], h.ecef[2]);
        HEX(x[4], h.lat_deg);
        HEX(x[5], h.lon_deg);
        printf("  hit %s %s %s %s %s %s ", x[0], x[1], x[2], x[3], x[4], x[5]);
        HEX(x[0], h.h);
        printf("%s %" PRIu32 " %" PRIu32 " %" PRIu32 " %u\n", x[0], h.cell[0], h.cell[1], h.stride,
               (unsigned)h.level);
    } else if (s == CURVICAST_NO_HIT) {
        printf("  no hit\n");
    } else {
        printf("  error %u\n", (unsigned)s);
    }
    PAGING(CCR(picker, _pick_t)(&OWN(the_picker), &ray, &t, cell, &node));
    if (s == CURVICAST_OK) {
        HEX(x[0], t);
        printf("  t %s %" PRIu32 " %" PRIu32 "\n", x[0], cell[0], cell[1]);
    } else if (s == CURVICAST_NO_HIT) {
        printf("  t none\n");
    } else {
        printf("  t error %u\n", (unsigned)s);
    }
}

static void OWN(los)(void) {
    T a[3], b[3];
    bool clear = false;
    uint32_t node = UINT32_MAX;
    int k;
    curvicast_status s;
    for (k = 0; k < 3; k++) a[k] = READ();
    for (k = 0; k < 3; k++) b[k] = READ();
    printf("L\n");
    PAGING(CCR(picker, _line_of_sight)(&OWN(the_picker), a, b, &clear, &node));
    if (s == CURVICAST_OK) printf("  clear %d\n", clear ? 1 : 0);
    else printf("  error %u\n", (unsigned)s);
}

static void OWN(level)(void) {
    const char *kind = tok();
    T axes[3], a, b;
    uint32_t level = 0;
    int k;
    curvicast_status s;
    for (k = 0; k < 3; k++) axes[k] = READ();
    a = READ();
    b = READ();
    if (kind[0] == 'D') s = CC(level_for_deviation)(axes, a, &level);
    else if (kind[0] == 'A') s = CC(level_for_dihedral)(axes, a, &level);
    else s = CC(level_for_screen)(axes, a, b, &level);
    if (s == CURVICAST_OK) printf("V 0 %" PRIu32 "\n", level);
    else printf("V %u -\n", (unsigned)s);
}

static void OWN(bevel)(void) {
    uint32_t level = (uint32_t)int_tok();
    T axes[3];
    size_t nv, nf, i;
    int k;
    CC(vec3) * v;
    CC(face) * f;
    curvicast_status s;
    for (k = 0; k < 3; k++) axes[k] = READ();
    nv = (size_t)int_tok();
    nf = (size_t)int_tok();
    v = alloc(nv, sizeof *v);
    f = alloc(nf, sizeof *f);
    s = CC(bevel_ellipsoid)(level, axes, v, nv, f, nf);
    if (s == CURVICAST_OK) {
        uint64_t h = UINT64_C(0xcbf29ce484222325);
        char x[24];
        for (i = 0; i < nv; i++) {
            HEX(x, v[i].x);
            fnv(&h, x);
            HEX(x, v[i].y);
            fnv(&h, x);
            HEX(x, v[i].z);
            fnv(&h, x);
        }
        for (i = 0; i < nf; i++) {
            const CC(vec3) *p[2];
            p[0] = &f[i].center;
            p[1] = &f[i].normal;
            for (k = 0; k < 2; k++) {
                HEX(x, p[k]->x);
                fnv(&h, x);
                HEX(x, p[k]->y);
                fnv(&h, x);
                HEX(x, p[k]->z);
                fnv(&h, x);
            }
            for (k = 0; k < CURVICAST_FACE_MAX_VERTICES; k++) {
                sprintf(x, "%" PRIu32, f[i].vertices[k]);
                fnv(&h, x);
            }
            sprintf(x, "%u", (unsigned)f[i].len);
            fnv(&h, x);
        }
        printf("B 0 %016" PRIx64 "\n", h);
    } else {
        printf("B %u -\n", (unsigned)s);
    }
    free(v);
    free(f);
}

#undef PAGING
#undef OWN
#undef CCR
#undef CC
#undef XPASTE3
#undef PASTE3
