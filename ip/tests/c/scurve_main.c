/* Runs the README's S-curve worked example (scurve_move, extracted from README.md by
 * ip/tests/c_driver.rs) through exmc_shim.cpp on an S-curve export, then the
 * driver's polynomial push errors. Each result is one line on stdout. */
#include <stdio.h>
#include "tdm_driver.h"

unsigned long shim_accesses(void);
void shim_write16(void *ctx, uint32_t byte_offset, uint16_t value);
uint16_t shim_read16(void *ctx, uint32_t byte_offset);
int scurve_move(tdm_dev *dev);
int driver_check_main(int argc, char **argv);

int driver_check_main(int argc, char **argv)
{
    tdm_dev dev;
    tdm_poly_segment bad;
    unsigned long before;
    unsigned taken = 7u;
    int rc, rc2;
    (void)argc;
    (void)argv;
    tdm_open_hooks(&dev, shim_read16, shim_write16, 0);
    rc = scurve_move(&dev);
    printf("RC %d\n", rc);
    /* A segment whose speed would reverse inside it (A far below -v0.T): code 2 on the
     * host, no bus access; on a bad axis: TDM_E_AXIS; a null segment: TDM_E_ARG. */
    bad.v0_rate = 0u;
    bad.v1_rate = 0u;
    bad.a_q32 = -((int64_t)40 << 32);
    bad.t_ticks = 30000u;
    bad.steps = 5;
    before = shim_accesses();
    printf("BADPOLY %d %lu\n", tdm_push_poly(&dev, 0u, &bad), shim_accesses() - before);
    rc2 = tdm_push_poly_some(&dev, 1u, &bad, 1u, &taken);
    printf("BADSOME %d %u\n", rc2, taken);
    printf("AXISPOLY %d\n", tdm_push_poly(&dev, dev.axes, &bad));
    printf("NULLPOLY %d\n", tdm_push_poly(&dev, 0u, 0));
    /* The arm is clear: the last push took it. */
    printf("ARM %u\n", (unsigned)tdm_read(&dev, TDM_POLY_ARM));
    printf("LEVEL %u %u\n", tdm_queue_room(&dev, 0u), tdm_queue_room(&dev, 1u));
    return rc == 0 ? 0 : 1;
}
