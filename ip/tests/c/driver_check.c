/* The C driver and planner against the exported IP, through exmc_shim.cpp (on the
 * EXMC pins, or with SHIM_SPI on the SPI pins: shim_open() picks the transport).
 *
 * argv[1] is a moves file, one move per line:
 *   rates <axis> <steps> <speed> <accel> <decel>   (tdm_plan_rates)
 *   ticks <axis> <steps> <t_acc> <t_cruise> <t_dec> (tdm_plan_ticks)
 * Every move is planned (PLAN lines); the planned moves of each axis run back to back
 * from one START, pushed as the queues have room; then the errors, a full queue, an
 * abort in motion and a failed START are exercised. Each result is one line on
 * stdout, which the Rust test (ip/tests/c_driver.rs) checks. */
#include <stdio.h>
#include <string.h>
#include "tdm_driver.h"
#include "tdm_planner.h"

unsigned long shim_accesses(void);
unsigned long long shim_clk_cycles(void);
void shim_idle_ns(unsigned long ns);
void shim_open(tdm_dev *dev);
int shim_spi_glitch(void);
int driver_check_main(int argc, char **argv);

#define MAX_SEGS 400

static tdm_segment segs[TDM_AXES][MAX_SEGS];
static unsigned nsegs[TDM_AXES];

static void print_positions(tdm_dev *dev)
{
    unsigned a;
    for (a = 0; a < dev->axes; a++) {
        tdm_axis_status s = tdm_status(dev, a);
        long pos = (long)tdm_position(dev, a);
        printf("POS %u %llu %ld %u %u %u %u\n", a, shim_clk_cycles(), pos, s.underrun, s.overflow, s.error, s.level);
    }
}

static void wait_idle(tdm_dev *dev, uint16_t mask)
{
    while (tdm_busy(dev) & mask) {
        shim_idle_ns(20000ul);
    }
}

int driver_check_main(int argc, char **argv)
{
    tdm_dev dev;
    FILE *f;
    char kind[16];
    unsigned axis;
    long steps;
    unsigned long p1, p2, p3;
    unsigned line = 0;
    unsigned a;
    unsigned idx[TDM_AXES];
    uint16_t mask = 0;
    int rc;
    if (argc < 2) {
        fprintf(stderr, "usage: %s MOVES\n", argv[0]);
        return 2;
    }
    shim_open(&dev);
    rc = tdm_identify(&dev);
    printf("IDENTIFY %d %u %lu %u %u %u %lu\n", rc, dev.axes, (unsigned long)dev.clock_hz, dev.queue_depth,
           dev.fifo_depth, dev.min_period, (unsigned long)dev.max_rate);
    if (rc != 0) {
        return 1;
    }
    printf("ENABLE_BAD %d\n", tdm_enable(&dev, (uint16_t)dev.min_period, 1u, 1u, 1u));
    rc = tdm_enable(&dev, 1u, 1u, 1u, 1u);
    printf("ENABLE %d\n", rc);
    if (rc != 0) {
        return 1;
    }

    /* Plan every move. */
    f = fopen(argv[1], "r");
    if (!f) {
        perror(argv[1]);
        return 2;
    }
    while (fscanf(f, "%15s %u %ld %lu %lu %lu", kind, &axis, &steps, &p1, &p2, &p3) == 6) {
        tdm_segment out[3];
        unsigned count = 0, bad = 0, k;
        if (strcmp(kind, "rates") == 0) {
            rc = tdm_plan_rates((int32_t)steps, (uint32_t)p1, (uint32_t)p2, (uint32_t)p3, dev.clock_hz, dev.max_rate,
                                out, &count, &bad);
        } else {
            uint32_t t[3];
            t[0] = (uint32_t)p1;
            t[1] = (uint32_t)p2;
            t[2] = (uint32_t)p3;
            rc = tdm_plan_ticks((int32_t)steps, t, dev.max_rate, out, &count, &bad);
        }
        printf("PLAN %u %d %u %u", line, rc, bad, count);
        for (k = 0; k < count; k++) {
            printf(" %lu %lu %ld", (unsigned long)out[k].v0_rate, (unsigned long)out[k].t_ticks, (long)out[k].steps);
        }
        printf("\n");
        if (rc == 0 && axis < dev.axes) {
            for (k = 0; k < count && nsegs[axis] < MAX_SEGS; k++) {
                segs[axis][nsegs[axis]++] = out[k];
            }
        }
        line++;
    }
    fclose(f);

    /* Run them: fill the queues, one START, keep them fed, wait for the end. */
    for (a = 0; a < dev.axes; a++) {
        unsigned taken = 0;
        idx[a] = 0;
        if (nsegs[a] == 0u) {
            continue;
        }
        rc = tdm_push_some(&dev, a, segs[a], nsegs[a], &taken);
        if (rc != 0) {
            printf("PUSHERR %u %d\n", a, rc);
        }
        idx[a] = taken;
        mask |= (uint16_t)(1u << a);
    }
    printf("START %d %u\n", tdm_start(&dev, mask), mask);
    for (;;) {
        unsigned pushed = 0, left = 0;
        for (a = 0; a < dev.axes; a++) {
            unsigned taken = 0;
            if (idx[a] >= nsegs[a]) {
                continue;
            }
            rc = tdm_push_some(&dev, a, &segs[a][idx[a]], nsegs[a] - idx[a], &taken);
            if (rc != 0) {
                printf("PUSHERR %u %d\n", a, rc);
                idx[a] = nsegs[a];
            }
            idx[a] += taken;
            pushed += taken;
            left += nsegs[a] - idx[a];
        }
        if (left == 0u) {
            break;
        }
        if (pushed == 0u) {
            shim_idle_ns(20000ul);
        }
    }
    wait_idle(&dev, mask);
    print_positions(&dev);
    {
        tdm_events ev = tdm_irq_service(&dev);
        printf("IRQ %u %u %u %u\n", ev.done, ev.queue_low, ev.error, ev.start_failed);
    }

    /* Errors found on the host, with no bus access. */
    {
        tdm_segment bad[4] = {{0u, 0u, 1}, {0u, 1000u, 1 << 25}, {0x7FFFFFFFul, 1000u, 10}, {0u, 1000u, 0}};
        unsigned k;
        bad[2].v0_rate = dev.max_rate + 1u;
        bad[2].steps = 1000; /* starts above RMAX: period too short */
        bad[3].v0_rate = 100000000u; /* decelerates past rest: reverses */
        for (k = 0; k < 4u; k++) {
            unsigned long before = shim_accesses();
            rc = tdm_push(&dev, 0, &bad[k]);
            printf("BADPUSH %u %d %lu\n", k, rc, shim_accesses() - before);
        }
        printf("AXISPUSH %d\n", tdm_push(&dev, dev.axes, &bad[0]));
        printf("AXISSTART %d\n", tdm_start(&dev, (uint16_t)(1u << dev.axes)));
    }

    /* A full queue: axis 0, 20 ms segments of 400 steps, pushed before any START. */
    printf("MARK %llu\n", shim_clk_cycles());
    {
        tdm_segment slow;
        unsigned accepted = 0;
        tdm_axis_status s;
        slow.t_ticks = 1000000u;
        slow.steps = -400;
        slow.v0_rate = (uint32_t)(((uint64_t)400u << 32) / slow.t_ticks);
        for (;;) {
            rc = tdm_push(&dev, 0, &slow);
            if (rc != 0) {
                break;
            }
            accepted++;
        }
        s = tdm_status(&dev, 0);
        printf("FULL %d %u %u %u\n", rc, accepted, s.level, s.overflow);
        /* Abort in motion: start, let it run 3 ms, stop everything. */
        printf("START2 %d\n", tdm_start(&dev, 1u));
        shim_idle_ns(3000000ul);
        tdm_abort(&dev);
        printf("ABORT %llu\n", shim_clk_cycles());
        wait_idle(&dev, 1u);
        print_positions(&dev);
    }

    /* A START whose axis has nothing to run fails, and the irq helper says so. */
    {
        tdm_events ev = tdm_irq_service(&dev);
        printf("IRQ %u %u %u %u\n", ev.done, ev.queue_low, ev.error, ev.start_failed);
        printf("START3 %d\n", tdm_start(&dev, 1u << (dev.axes - 1u)));
        shim_idle_ns(20000ul);
        ev = tdm_irq_service(&dev);
        printf("IRQ %u %u %u %u\n", ev.done, ev.queue_low, ev.error, ev.start_failed);
        ev = tdm_irq_service(&dev);
        printf("IRQ %u %u %u %u\n", ev.done, ev.queue_low, ev.error, ev.start_failed);
    }
    /* No frame was refused; then a frame cut mid-word is (SPI only): the register
     * keeps its value and the next frame's status byte counts one bus error. */
    printf("BUSERR %lu\n", dev.bus_errors);
    {
        uint16_t before = tdm_read(&dev, TDM_QLOW_LEVEL);
        int glitched = shim_spi_glitch();
        uint16_t after = tdm_read(&dev, TDM_QLOW_LEVEL);
        printf("GLITCH %d %u %u %lu\n", glitched, before, after, dev.bus_errors);
    }
    printf("END %llu\n", shim_clk_cycles());
    return 0;
}
