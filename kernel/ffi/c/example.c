/* curvicast from C: march a ray through a spherical grid, pick a small DEM, choose a tessellation level. */
#include <math.h>
#include <stdio.h>

#include "curvicast.h"

#define PI 3.14159265358979323846

static int check(curvicast_status s, const char *what) {
    if (s != CURVICAST_OK) fprintf(stderr, "%s: %s\n", what, curvicast_status_message(s));
    return s == CURVICAST_OK;
}

int main(void) {
    /* 1. March: a ball of radius 1 split at r = 0.5, the equator and the xz plane (Hannasch, ch. 5). */
    static const double r[] = {0.0, 0.5, 1.0}, theta[] = {0.0, PI / 2, PI}, phi[] = {0.0, PI, 2 * PI};
    static double workspace[15]; /* curvicast_spherical_workspace_len(3, 3, 3) */
    static curvicast_grid_f64 grid;
    static curvicast_march_f64 march;
    curvicast_ray_f64 ray = {{-2.0, 0.25, 0.25}, {1.0, 0.0, 0.0}, 0.0, INFINITY};
    curvicast_crossing_f64 c;
    curvicast_status s;
    if (!check(curvicast_spherical_grid_f64_init(&grid, r, 3, theta, 3, phi, 3, NULL, workspace, 15), "grid") ||
        !check(curvicast_march_f64_begin(&march, &grid, &ray), "march"))
        return 1;
    while ((s = curvicast_march_f64_next(&march, &c)) == CURVICAST_OK)
        printf("cell [%u %u %u] t %.6f .. %.6f\n", (unsigned)c.cell[0], (unsigned)c.cell[1], (unsigned)c.cell[2],
               c.t_enter, c.t_exit);
    if (s != CURVICAST_DONE) return !check(s, "march");

    /* 2. Pick: 9 x 9 heights at 0.01 degree near 45 N 7 E on WGS84 (Wartell et al.), seen from 5 km up. */
    static float heights[81];
    static curvicast_node_record nodes[16]; /* at least curvicast_node_slots(9, 9, 4) */
    static curvicast_terrain_f64 terrain;
    static curvicast_picker_f64 picker;
    curvicast_dem_grid_f64 dem = {45.0, 7.0, 0.01, 0.01, 9, 9};
    curvicast_hit_f64 hit;
    double from[3], to[3];
    int i;
    for (i = 0; i < 81; i++) heights[i] = 100.0f + 10.0f * (float)(i % 9);
    if (curvicast_node_slots(9, 9, 4) > 16 ||
        !check(curvicast_terrain_f64_build(&terrain, &dem, heights, 81, 4, nodes, 16), "terrain") ||
        !check(curvicast_picker_f64_init(&picker, &terrain, 0), "picker"))
        return 1;
    curvicast_wgs84_to_ecef_f64(45.04, 7.04, 5000.0, from);
    curvicast_wgs84_to_ecef_f64(45.04, 7.04, 0.0, to);
    curvicast_ray_f64 down = {{from[0], from[1], from[2]}, {to[0] - from[0], to[1] - from[1], to[2] - from[2]},
                              0.0, INFINITY};
    if (!check(curvicast_picker_f64_pick(&picker, &down, &hit, NULL), "pick")) return 1;
    printf("hit at %.6f N %.6f E, %.3f m, t = %.9f\n", hit.lat_deg, hit.lon_deg, hit.h, hit.t);

    /* 3. Tessellate: the level whose beveled WGS84 ellipsoid stays within 100 m of it. */
    const double wgs84[3] = {6378137.0, 6378137.0, 6356752.314245};
    uint32_t level;
    if (!check(curvicast_level_for_deviation_f64(wgs84, 100.0, &level), "level")) return 1;
    printf("level %u: %zu vertices, %zu faces\n", (unsigned)level, curvicast_bevel_vertex_count(level),
           curvicast_bevel_face_count(level));
    return 0;
}
