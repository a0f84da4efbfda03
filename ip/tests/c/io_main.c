/* Runs the README's homing worked example (home_axis0, extracted from README.md by
 * ip/tests/c_driver.rs) through exmc_shim.cpp built with SHIM_IO, on an `--io all`
 * export, with a home switch at position -1234 of axis 0; then a controlled stop of a
 * move on axis 1 through the driver, its events, and the calls that must refuse. */
#include <stdio.h>
#include "tdm_driver.h"
#include "tdm_planner.h"

void shim_write16(void *ctx, uint32_t byte_offset, uint16_t value);
uint16_t shim_read16(void *ctx, uint32_t byte_offset);
void shim_home_switch(unsigned axis, int32_t at, int dir);
void shim_idle_ns(unsigned long ns);
unsigned long long shim_clk_cycles(void);
int home_axis0(tdm_dev *dev, int32_t *zero);
int driver_check_main(int argc, char **argv);

int driver_check_main(int argc, char **argv)
{
    tdm_dev dev;
    tdm_io_config bad = {0};
    tdm_io_events ev;
    tdm_segment segs[3];
    unsigned count;
    unsigned phase;
    unsigned taken;
    int32_t zero = 0;
    int rc;
    (void)argc;
    (void)argv;
    tdm_open_hooks(&dev, shim_read16, shim_write16, 0);
    shim_home_switch(0, -1234, -1);
    rc = home_axis0(&dev, &zero);
    printf("HOME %d %ld %ld\n", rc, (long)zero, (long)tdm_position(&dev, 0));
    ev = tdm_io_service(&dev);
    printf("EVENTS %u %u %u %u %u\n", ev.estop, ev.watchdog, ev.probe, ev.home, ev.stopped);
    ev = tdm_io_service(&dev);
    printf("EVENTS %u %u %u %u %u\n", ev.estop, ev.watchdog, ev.probe, ev.home, ev.stopped);

    /* A controlled stop of a move of axis 1, 5 ms after its start. */
    rc = tdm_plan_rates(3000, 50000u, 5000000u, 5000000u, dev.clock_hz, dev.max_rate, segs, &count, &phase);
    if (rc == 0) {
        rc = tdm_push_some(&dev, 1, segs, count, &taken);
    }
    if (rc == 0) {
        rc = tdm_start(&dev, 2u);
    }
    shim_idle_ns(5000000ul);
    printf("STOPAT %llu\n", shim_clk_cycles());
    if (rc == 0) {
        rc = tdm_stop(&dev, 2u);
    }
    if (rc == 0) {
        rc = tdm_wait_idle(&dev, 2u, 10000000ul);
    }
    printf("STOP %d %ld\n", rc, (long)tdm_position(&dev, 1));

    /* Refused on the host, or by the core. */
    bad.filter[TDM_GROUP_HOME] = 16;
    printf("BADFILTER %d\n", tdm_io_configure(&dev, &bad));
    bad.filter[TDM_GROUP_HOME] = 0;
    bad.stop_decel = TDM_STOP_DECEL_MIN - 1u;
    printf("BADDECEL %d\n", tdm_io_configure(&dev, &bad));
    bad.stop_decel = 0u;
    bad.stop_mode = 16u;
    printf("BADMODE %d\n", tdm_io_configure(&dev, &bad));
    bad.stop_mode = 0u;
    printf("ENABLED %d\n", tdm_io_configure(&dev, &bad));
    printf("SOFTBAD %d\n", tdm_soft_limits(&dev, 0, 10, -10, 1));
    printf("STOPAXIS %d %d\n", tdm_stop(&dev, (uint16_t)(1u << TDM_AXES)), tdm_stop_on_home(&dev, (uint16_t)(1u << TDM_AXES)));
    printf("RC %d\n", rc);
    return rc == 0 ? 0 : 1;
}
