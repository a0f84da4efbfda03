/* The C S-curve planner on many inputs, for the test against the Rust planner
 * (ip/tests/c_driver.rs). Reads lines from stdin (doubles printed with 17 digits):
 *   jerk <steps> <v_start> <v_end> <v_max> <a> <j> <d> <jd> <clock_hz> <max_rate>
 *   fourth <steps> <v_max> <a> <j> <s> <clock_hz> <max_rate>
 * and prints, per line: <rc> <count> then v0 v1 a T steps per segment. */
#include <stdio.h>
#include <string.h>
#include "tdm_scurve.h"

int main(void)
{
    char kind[16];
    static tdm_poly_segment out[TDM_SCURVE_MAX_SEGMENTS];
    while (scanf("%15s", kind) == 1) {
        unsigned count = 0, k;
        long steps;
        unsigned long clock, max_rate;
        double v[7];
        int rc;
        if (strcmp(kind, "jerk") == 0) {
            if (scanf("%ld %lf %lf %lf %lf %lf %lf %lf %lu %lu", &steps, &v[0], &v[1], &v[2], &v[3], &v[4], &v[5],
                      &v[6], &clock, &max_rate) != 10)
                return 2;
            rc = tdm_plan_jerk((int32_t)steps, v[0], v[1], v[2], v[3], v[4], v[5], v[6], (uint32_t)clock,
                               (uint32_t)max_rate, out, &count);
        } else {
            if (scanf("%ld %lf %lf %lf %lf %lu %lu", &steps, &v[0], &v[1], &v[2], &v[3], &clock, &max_rate) != 7)
                return 2;
            rc = tdm_plan_fourth((int32_t)steps, v[0], v[1], v[2], v[3], (uint32_t)clock, (uint32_t)max_rate, out,
                                 &count);
        }
        printf("%d %u", rc, rc > 0 ? count : (rc == 0 ? count : 0));
        if (rc == 0) {
            for (k = 0; k < count; k++) {
                printf(" %lu %lu %lld %lu %ld", (unsigned long)out[k].v0_rate, (unsigned long)out[k].v1_rate,
                       (long long)out[k].a_q32, (unsigned long)out[k].t_ticks, (long)out[k].steps);
            }
        }
        printf("\n");
    }
    return 0;
}
