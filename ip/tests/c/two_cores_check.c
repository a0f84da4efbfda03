/* Two cores of different K in one firmware build: tdm_driver.h includes the header of
 * export B (K = 4, --io all, --name motion_b) as tdm_stepper_regs.h, and this file
 * includes export A's (K = 2, --name motion_a) after it as motion_a_regs.h; the
 * driver is compiled with B's header. Two register banks in memory answer A's and
 * B's ID values; each core's identity is checked against each bank:
 * "AS <bank> <identity> <rc> <axes read>". */
#include <stdio.h>
#include "tdm_driver.h"
#include "motion_a_regs.h"

static const tdm_identity ids[2] = {MOTION_A_IDENTITY, MOTION_B_IDENTITY};

static uint16_t bank_read(void *ctx, uint32_t byte_offset)
{
    const tdm_identity *id = (const tdm_identity *)ctx;
    switch (byte_offset) {
    case TDM_ID_MAGIC: return (uint16_t)TDM_MAGIC;
    case TDM_ID_VERSION: return id->version;
    case TDM_ID_AXES: return id->axes;
    case TDM_ID_QUEUE_DEPTH: return id->queue_depth;
    case TDM_ID_FIFO_DEPTH: return id->fifo_depth;
    case TDM_ID_CLOCK_HZ_LO: return (uint16_t)(id->clock_hz & 0xFFFFu);
    case TDM_ID_CLOCK_HZ_HI: return (uint16_t)(id->clock_hz >> 16);
    case TDM_ID_MIN_PERIOD: return id->min_period;
    case TDM_ID_MAX_RATE_LO: return (uint16_t)(id->max_rate & 0xFFFFu);
    case TDM_ID_MAX_RATE_HI: return (uint16_t)(id->max_rate >> 16);
    case TDM_ID_OPTIONS: return id->options;
    default: return 0u;
    }
}

static void bank_write(void *ctx, uint32_t byte_offset, uint16_t value)
{
    (void)ctx;
    (void)byte_offset;
    (void)value;
}

int main(void)
{
    unsigned b;
    unsigned i;
    for (b = 0; b < 2u; b++) {
        for (i = 0; i < 2u; i++) {
            tdm_dev dev;
            int rc;
            tdm_open_hooks(&dev, bank_read, bank_write, (void *)&ids[b]);
            rc = tdm_identify_as(&dev, &ids[i]);
            printf("AS %u %u %d %u\n", b, i, rc, (unsigned)dev.axes);
        }
    }
    printf("HEADER_AXES %u\n", (unsigned)TDM_AXES);
    return 0;
}
