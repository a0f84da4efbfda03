/* The C planner on many inputs, for the property test against the Rust planner
 * (ip/tests/c_driver.rs). Reads lines from stdin:
 *   rates <steps> <speed> <accel> <decel> <clock_hz> <max_rate>
 *   ticks <steps> <t_acc> <t_cruise> <t_dec> <max_rate>
 * and prints, per line: <rc> <bad_phase> <count> then v0 T steps per segment. */
#include <stdio.h>
#include <string.h>
#include "tdm_planner.h"

int main(void)
{
    char kind[16];
    while (scanf("%15s", kind) == 1) {
        tdm_segment out[3];
        unsigned count = 0, bad = 0, k;
        long steps;
        unsigned long a, b, c, d, e;
        int rc;
        if (strcmp(kind, "rates") == 0) {
            if (scanf("%ld %lu %lu %lu %lu %lu", &steps, &a, &b, &c, &d, &e) != 6) return 2;
            rc = tdm_plan_rates((int32_t)steps, (uint32_t)a, (uint32_t)b, (uint32_t)c, (uint32_t)d, (uint32_t)e, out,
                                &count, &bad);
        } else {
            uint32_t t[3];
            if (scanf("%ld %lu %lu %lu %lu", &steps, &a, &b, &c, &e) != 5) return 2;
            t[0] = (uint32_t)a;
            t[1] = (uint32_t)b;
            t[2] = (uint32_t)c;
            rc = tdm_plan_ticks((int32_t)steps, t, (uint32_t)e, out, &count, &bad);
        }
        printf("%d %u %u", rc, bad, count);
        for (k = 0; k < count; k++) {
            printf(" %lu %lu %ld", (unsigned long)out[k].v0_rate, (unsigned long)out[k].t_ticks, (long)out[k].steps);
        }
        printf("\n");
    }
    return 0;
}
