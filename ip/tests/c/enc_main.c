/* Runs the README's encoder worked example (setup_encoders, check_and_correct,
 * extracted from README.md by ip/tests/c_driver.rs) through exmc_shim.cpp built with
 * SHIM_ENC, on an `--encoder` export (K = 2): a 2,000-step move of axis 0 whose motor
 * loses 40 steps (the shim stalls it), then the correction; and the calls that must
 * refuse. Prints tagged lines for the Rust test. */
#include <stdio.h>
#include "tdm_driver.h"
#include "tdm_planner.h"

void shim_write16(void *ctx, uint32_t byte_offset, uint16_t value);
uint16_t shim_read16(void *ctx, uint32_t byte_offset);
void shim_enc_stall(uint32_t mask);
long long shim_enc_count(unsigned axis);
long long shim_motor(unsigned axis);
int setup_encoders(tdm_dev *dev);
int check_and_correct(tdm_dev *dev, int32_t *moved);
int driver_check_main(int argc, char **argv);

int driver_check_main(int argc, char **argv)
{
    tdm_dev dev;
    tdm_enc_config bad = {0};
    tdm_enc_status st;
    tdm_segment segs[3];
    unsigned count, phase, taken;
    uint16_t failed = 0;
    uint16_t irq;
    int32_t moved = 0;
    int rc;
    (void)argc;
    (void)argv;
    tdm_open_hooks(&dev, shim_read16, shim_write16, 0);
    rc = tdm_identify(&dev);
    printf("IDENTIFY %d\n", rc);
    /* Refused without a bus access. */
    bad.ratio[0] = 0x14000u;
    bad.ratio[1] = 0u;
    printf("BADRATIO %d\n", tdm_enc_configure(&dev, &bad));
    bad.ratio[1] = TDM_ENC_RATIO_MAX + 1u;
    printf("BIGRATIO %d\n", tdm_enc_configure(&dev, &bad));
    bad.ratio[1] = TDM_ENC_RATIO_ONE;
    bad.filter = 16u;
    printf("BADFILTER %d\n", tdm_enc_configure(&dev, &bad));
    bad.filter = 0u;
    bad.stop = 0x4u;
    printf("BADSTOP %d\n", tdm_enc_configure(&dev, &bad));
    printf("SETUP %d\n", setup_encoders(&dev));
    rc = tdm_enable(&dev, 1u, 1u, 1u, 1u);
    printf("ENABLE %d\n", rc);
    printf("ENABLED %d\n", setup_encoders(&dev));
    printf("ALIGN %d %d\n", tdm_enc_align(&dev, 0x3u), tdm_enc_align(&dev, 0x4u));
    /* 2,000 steps at up to 20,000 steps/s; the motor stalls from step 600 to step 640. */
    rc = tdm_plan_rates(2000, 20000u, 2000000u, 2000000u, dev.clock_hz, dev.max_rate, segs, &count, &phase);
    if (rc == 0) rc = tdm_push_some(&dev, 0, segs, count, &taken);
    if (rc == 0) rc = tdm_start(&dev, 0x1u);
    while (rc == 0 && tdm_position(&dev, 0) < 600) {
    }
    shim_enc_stall(0x1u);
    while (rc == 0 && tdm_position(&dev, 0) < 640) {
    }
    shim_enc_stall(0x0u);
    if (rc == 0) rc = tdm_wait_idle(&dev, 0x1u, 4000000ul);
    printf("STALL %lld\n", 2000 - shim_motor(0));
    printf("MOVE %d %ld\n", rc, (long)tdm_position(&dev, 0));
    rc = tdm_enc_read(&dev, 0, &st, 1000ul);
    printf("READ %d %ld %ld %u %u\n", rc, (long)st.count, (long)st.deviation, (unsigned)(st.state >> 13 & 1u), (unsigned)(st.state & 0xFFu));
    printf("INDEX %ld %ld\n", (long)st.index, (long)st.index_pos);
    irq = tdm_enc_service(&dev, &failed);
    printf("SERVICE %u %u\n", (unsigned)irq, (unsigned)failed);
    rc = check_and_correct(&dev, &moved);
    printf("CORRECT %d %ld %lld %lld %ld\n", rc, (long)moved, shim_enc_count(0), shim_motor(0), (long)tdm_position(&dev, 0));
    rc = tdm_enc_read(&dev, 0, &st, 1000ul);
    printf("AFTER %d %ld %ld %u\n", rc, (long)st.count, (long)st.deviation, (unsigned)(st.state >> 13 & 1u));
    rc = check_and_correct(&dev, &moved);
    printf("NOTHING %d %ld\n", rc, (long)moved);
    printf("BADAXIS %d %d\n", tdm_enc_read(&dev, 2, &st, 10ul), tdm_enc_correct(&dev, 2, 1000u, 1000u, 10ul, &moved));
    printf("RC 0\n");
    return 0;
}
