/* tdm_identify() against a register bank in memory (no core): the bank answers every
 * ID register with this header's value and ID_OPTIONS with argv[1] (hex); the program
 * prints tdm_identify's code and the options it read: "IDENTIFY <rc> <options>"; then
 * the same through tdm_open_mmio32() on a 32-bit image of the bank whose bits 31..16
 * hold junk (a Wishbone or AXI4-Lite core's region): "IDENTIFY32 <rc> <options>". */
#include <stdio.h>
#include <stdlib.h>
#include "tdm_driver.h"

static uint16_t options;

static uint16_t bank_read(void *ctx, uint32_t byte_offset)
{
    (void)ctx;
    switch (byte_offset) {
    case TDM_ID_MAGIC: return (uint16_t)TDM_MAGIC;
    case TDM_ID_VERSION: return (uint16_t)TDM_VERSION;
    case TDM_ID_AXES: return (uint16_t)TDM_AXES;
    case TDM_ID_QUEUE_DEPTH: return (uint16_t)TDM_QUEUE_DEPTH;
    case TDM_ID_FIFO_DEPTH: return (uint16_t)TDM_FIFO_DEPTH;
    case TDM_ID_T_CALC: return (uint16_t)TDM_T_CALC;
    case TDM_ID_CLOCK_HZ_LO: return (uint16_t)(TDM_CLOCK_HZ & 0xFFFFu);
    case TDM_ID_CLOCK_HZ_HI: return (uint16_t)(TDM_CLOCK_HZ >> 16);
    case TDM_ID_MIN_PERIOD: return (uint16_t)TDM_MIN_PERIOD;
    case TDM_ID_MAX_RATE_LO: return (uint16_t)(TDM_MAX_RATE & 0xFFFFu);
    case TDM_ID_MAX_RATE_HI: return (uint16_t)(TDM_MAX_RATE >> 16);
    case TDM_ID_OPTIONS: return options;
    default: return 0u;
    }
}

static void bank_write(void *ctx, uint32_t byte_offset, uint16_t value)
{
    (void)ctx;
    (void)byte_offset;
    (void)value;
}

int main(int argc, char **argv)
{
    tdm_dev dev;
    int rc;
    if (argc < 2) {
        fprintf(stderr, "usage: %s OPTIONS\n", argv[0]);
        return 2;
    }
    options = (uint16_t)strtoul(argv[1], 0, 16);
    tdm_open_hooks(&dev, bank_read, bank_write, 0);
    rc = tdm_identify(&dev);
    printf("IDENTIFY %d %x\n", rc, (unsigned)dev.options);
    {
        static uint32_t bank32[512];
        unsigned w;
        for (w = 0; w < 512u; w++) {
            bank32[w] = 0xA5A50000ul | bank_read(0, 2u * w);
        }
        tdm_open_mmio32(&dev, bank32);
        rc = tdm_identify(&dev);
        printf("IDENTIFY32 %d %x\n", rc, (unsigned)dev.options);
    }
    return 0;
}
