/* Runs the README's MCU worked example (two_axis_move, extracted from README.md by
 * ip/tests/c_driver.rs) through exmc_shim.cpp. */
#include <stdio.h>
#include "tdm_driver.h"

void shim_write16(void *ctx, uint32_t byte_offset, uint16_t value);
uint16_t shim_read16(void *ctx, uint32_t byte_offset);
int two_axis_move(tdm_dev *dev);
int driver_check_main(int argc, char **argv);

int driver_check_main(int argc, char **argv)
{
    tdm_dev dev;
    int rc;
    (void)argc;
    (void)argv;
    tdm_open_hooks(&dev, shim_read16, shim_write16, 0);
    rc = two_axis_move(&dev);
    printf("RC %d\n", rc);
    return rc == 0 ? 0 : 1;
}
