/* tdm_driver.c: the MCU driver of the tdm-stepper IP core. See tdm_driver.h. */
#include <stddef.h>
#include "tdm_driver.h"

void tdm_open_mmio(tdm_dev *dev, volatile void *bank_base)
{
    tdm_dev zero = {0};
    *dev = zero;
    dev->base = (volatile uint16_t *)bank_base;
}

void tdm_open_hooks(tdm_dev *dev, tdm_read16_fn read16, tdm_write16_fn write16, void *ctx)
{
    tdm_dev zero = {0};
    *dev = zero;
    dev->read16 = read16;
    dev->write16 = write16;
    dev->ctx = ctx;
}

void tdm_open_mmio32(tdm_dev *dev, volatile void *base)
{
    tdm_dev zero = {0};
    *dev = zero;
    dev->base32 = (volatile uint32_t *)base;
}

void tdm_open_spi(tdm_dev *dev, tdm_spi_xfer_fn xfer, void *ctx)
{
    tdm_dev zero = {0};
    *dev = zero;
    dev->spi_xfer = xfer;
    dev->ctx = ctx;
}

/* Words per SPI frame the driver sends (the core takes up to TDM_SPI_MAX_BURST). */
#define SPI_BURST 8u

/* One SPI frame of n (1..SPI_BURST) words from word address addr, with INC: a write
 * of w, or a read into r. Counts the status byte's errors. */
static void spi_frame(tdm_dev *dev, uint32_t addr, const uint16_t *w, uint16_t *r, unsigned n)
{
    uint8_t tx[3u + 2u * SPI_BURST];
    uint8_t rx[3u + 2u * SPI_BURST];
    unsigned len;
    unsigned k;
    uint8_t st;
    tx[0] = (uint8_t)((w ? TDM_SPI_CMD_WRITE : 0u) | TDM_SPI_CMD_INC | ((n - 1u) << TDM_SPI_CMD_LEN_SHIFT) | ((addr >> 8) & 1u));
    tx[1] = (uint8_t)(addr & 0xFFu);
    len = w ? 2u + 2u * n : 3u + 2u * n;
    for (k = 2; k < len; k++) {
        tx[k] = 0u;
    }
    if (w) {
        for (k = 0; k < n; k++) {
            tx[2u + 2u * k] = (uint8_t)(w[k] >> 8);
            tx[3u + 2u * k] = (uint8_t)(w[k] & 0xFFu);
        }
    }
    dev->spi_xfer(dev->ctx, tx, rx, len);
    st = rx[0];
    dev->spi_status = st;
    if ((st & TDM_SPI_STATUS_FRAME_ERR) != 0u || (st & TDM_SPI_STATUS_PATTERN_MASK) != TDM_SPI_STATUS_PATTERN) {
        dev->bus_errors++;
    }
    if (r) {
        for (k = 0; k < n; k++) {
            r[k] = (uint16_t)(((uint16_t)rx[3u + 2u * k] << 8) | rx[4u + 2u * k]);
        }
    }
}

void tdm_read_burst(tdm_dev *dev, uint32_t byte_offset, uint16_t *values, unsigned count)
{
    unsigned k;
    if (dev->spi_xfer) {
        for (k = 0; k < count; k += SPI_BURST) {
            unsigned n = count - k < SPI_BURST ? count - k : SPI_BURST;
            spi_frame(dev, byte_offset / 2u + k, 0, values + k, n);
        }
        return;
    }
    for (k = 0; k < count; k++) {
        if (dev->read16) {
            values[k] = dev->read16(dev->ctx, byte_offset + 2u * k);
        } else if (dev->base32) {
            values[k] = (uint16_t)(dev->base32[byte_offset / 2u + k] & 0xFFFFu);
        } else {
            values[k] = dev->base[byte_offset / 2u + k];
        }
    }
}

void tdm_write_burst(tdm_dev *dev, uint32_t byte_offset, const uint16_t *values, unsigned count)
{
    unsigned k;
    if (dev->spi_xfer) {
        for (k = 0; k < count; k += SPI_BURST) {
            unsigned n = count - k < SPI_BURST ? count - k : SPI_BURST;
            spi_frame(dev, byte_offset / 2u + k, values + k, 0, n);
        }
        return;
    }
    for (k = 0; k < count; k++) {
        if (dev->write16) {
            dev->write16(dev->ctx, byte_offset + 2u * k, values[k]);
        } else if (dev->base32) {
            dev->base32[byte_offset / 2u + k] = values[k];
        } else {
            dev->base[byte_offset / 2u + k] = values[k];
        }
    }
}

uint16_t tdm_read(tdm_dev *dev, uint32_t byte_offset)
{
    uint16_t v;
    tdm_read_burst(dev, byte_offset, &v, 1u);
    return v;
}

void tdm_write(tdm_dev *dev, uint32_t byte_offset, uint16_t value)
{
    tdm_write_burst(dev, byte_offset, &value, 1u);
}

/* A 32-bit value from two consecutive registers, low half first, in one burst (a
 * read of the low half latches the high half where the map says so). */
static uint32_t read32(tdm_dev *dev, uint32_t lo)
{
    uint16_t v[2];
    tdm_read_burst(dev, lo, v, 2u);
    return v[0] | ((uint32_t)v[1] << 16);
}

int tdm_identify_as(tdm_dev *dev, const tdm_identity *want)
{
    if (want == 0) {
        return TDM_E_ARG;
    }
    if (tdm_read(dev, TDM_ID_MAGIC) != TDM_MAGIC) {
        return TDM_E_MAGIC;
    }
    dev->version = tdm_read(dev, TDM_ID_VERSION);
    dev->axes = tdm_read(dev, TDM_ID_AXES);
    dev->queue_depth = tdm_read(dev, TDM_ID_QUEUE_DEPTH);
    dev->fifo_depth = tdm_read(dev, TDM_ID_FIFO_DEPTH);
    dev->t_calc = tdm_read(dev, TDM_ID_T_CALC);
    dev->min_period = tdm_read(dev, TDM_ID_MIN_PERIOD);
    dev->clock_hz = read32(dev, TDM_ID_CLOCK_HZ_LO);
    dev->max_rate = read32(dev, TDM_ID_MAX_RATE_LO);
    dev->options = tdm_read(dev, TDM_ID_OPTIONS);
    dev->stop_decel_min = want->stop_decel_min;
    if ((dev->version >> 8) != (want->version >> 8) || (dev->version & 0xFFu) < (want->version & 0xFFu)
        || (want->version >> 8) != (TDM_VERSION >> 8)) {
        return TDM_E_VERSION;
    }
    if (dev->axes != want->axes || dev->clock_hz != want->clock_hz || dev->queue_depth != want->queue_depth
        || dev->fifo_depth != want->fifo_depth || dev->min_period != want->min_period
        || dev->max_rate != want->max_rate || dev->options != want->options || dev->axes == 0u || dev->axes > 16u) {
        return TDM_E_CONFIG;
    }
    return 0;
}

int tdm_identify(tdm_dev *dev)
{
#if defined(TDM_STOP_DECEL_MIN)
    const tdm_identity want = {TDM_VERSION, TDM_AXES, TDM_CLOCK_HZ, TDM_QUEUE_DEPTH, TDM_FIFO_DEPTH, TDM_MIN_PERIOD,
                               TDM_MAX_RATE, TDM_OPTIONS, TDM_STOP_DECEL_MIN};
#else
    const tdm_identity want = {TDM_VERSION, TDM_AXES, TDM_CLOCK_HZ, TDM_QUEUE_DEPTH, TDM_FIFO_DEPTH, TDM_MIN_PERIOD,
                               TDM_MAX_RATE, TDM_OPTIONS, 0u};
#endif
    return tdm_identify_as(dev, &want);
}

static int poll_gstatus(tdm_dev *dev, uint16_t mask, uint16_t want)
{
    unsigned long i;
    for (i = 0; i < TDM_POLL_LIMIT; i++) {
        if ((tdm_read(dev, TDM_GSTATUS) & mask) == want) {
            return 0;
        }
    }
    return TDM_E_TIMEOUT;
}

int tdm_enable(tdm_dev *dev, uint16_t step_high, uint16_t step_low, uint16_t dir_setup, uint16_t dir_hold)
{
    uint32_t high = step_high > dir_hold ? step_high : dir_hold;
    uint32_t low = step_low > dir_setup ? step_low : dir_setup;
    int rc;
    if (step_high == 0u || step_low == 0u || dir_setup == 0u || dir_hold == 0u || high + low > dev->min_period) {
        return TDM_E_ARG;
    }
    tdm_write(dev, TDM_CTRL, 0u);
    rc = poll_gstatus(dev, TDM_GSTATUS_ENABLED_MASK, 0u);
    if (rc != 0) {
        return rc;
    }
    tdm_write(dev, TDM_GSTATUS, TDM_GSTATUS_REFUSED_MASK);
    tdm_write(dev, TDM_STEP_HIGH, step_high);
    tdm_write(dev, TDM_STEP_LOW, step_low);
    tdm_write(dev, TDM_DIR_SETUP, dir_setup);
    tdm_write(dev, TDM_DIR_HOLD, dir_hold);
    tdm_write(dev, TDM_CTRL, TDM_CTRL_ENABLE_MASK);
    if (tdm_read(dev, TDM_GSTATUS) & TDM_GSTATUS_REFUSED_MASK) {
        return TDM_E_REFUSED;
    }
    return poll_gstatus(dev, TDM_GSTATUS_ENABLED_MASK, TDM_GSTATUS_ENABLED_MASK);
}

void tdm_disable(tdm_dev *dev)
{
    tdm_write(dev, TDM_CTRL, 0u);
}

uint32_t tdm_rate_from_sps(uint32_t clock_hz, uint32_t steps_per_s)
{
    uint64_t num;
    if (clock_hz == 0u || (uint64_t)steps_per_s * 2u >= clock_hz) {
        return 0u;
    }
    num = ((uint64_t)steps_per_s << 32) + clock_hz / 2u;
    return (uint32_t)(num / clock_hz);
}

int tdm_segment_check(const tdm_segment *seg, uint32_t max_rate)
{
    uint32_t n;
    uint32_t v0 = seg->v0_rate;
    int64_t v_end_t;
    if (seg->t_ticks == 0u) {
        return TDM_ERR_TICKS_ZERO;
    }
    if (seg->t_ticks > TDM_MAX_T_TICKS) {
        return TDM_ERR_TICKS_RANGE;
    }
    n = seg->steps < 0 ? (uint32_t)0 - (uint32_t)seg->steps : (uint32_t)seg->steps;
    if (n > TDM_MAX_STEPS) {
        return TDM_ERR_STEPS_RANGE;
    }
    if (v0 > TDM_MAX_V0_RATE) {
        return TDM_ERR_RATE_RANGE;
    }
    /* v_end·T·2^32 = 2n·2^32 − v0·T: |each| < 2^62, exact in 64 bits. */
    v_end_t = (int64_t)((uint64_t)n << 33) - (int64_t)((uint64_t)v0 * seg->t_ticks);
    if (v_end_t < 0 && v_end_t + (int64_t)seg->t_ticks > 0) {
        /* A deceleration to rest whose v0 was rounded up: runs as v0 − 1. */
        v0 -= 1u;
        v_end_t += (int64_t)seg->t_ticks;
    }
    if (v_end_t < 0) {
        return TDM_ERR_REVERSES;
    }
    if (v0 > max_rate || v_end_t > (int64_t)((uint64_t)seg->t_ticks * max_rate)) {
        return TDM_ERR_PERIOD_TOO_SHORT;
    }
    return 0;
}

unsigned tdm_queue_room(tdm_dev *dev, unsigned axis)
{
    unsigned level;
    if (axis >= dev->axes) {
        return 0u;
    }
    level = (unsigned)(tdm_read(dev, TDM_STATUS(axis)) & TDM_STATUS_LEVEL_MASK) >> TDM_STATUS_LEVEL_SHIFT;
    return level >= dev->queue_depth ? 0u : dev->queue_depth - level;
}

static void write_segment(tdm_dev *dev, unsigned axis, const tdm_segment *seg)
{
    uint32_t steps = (uint32_t)seg->steps;
    uint16_t w[6];
    w[0] = (uint16_t)(seg->v0_rate & 0xFFFFu);
    w[1] = (uint16_t)(seg->v0_rate >> 16);
    w[2] = (uint16_t)(seg->t_ticks & 0xFFFFu);
    w[3] = (uint16_t)(seg->t_ticks >> 16);
    w[4] = (uint16_t)(steps & 0xFFFFu);
    w[5] = (uint16_t)(steps >> 16); /* STEPS_HI: pushes */
    tdm_write_burst(dev, TDM_V0_LO(axis), w, 6u);
}

/* A kind of segment for the push functions: its host-side check (0 or the core's
 * code) and its write (0, or TDM_E_REFUSED when the core refused it). */
typedef int (*check_fn)(const void *seg, uint32_t max_rate);
typedef int (*write_fn)(tdm_dev *dev, unsigned axis, const void *seg);

/* One segment: the axis, the check (no bus access), the room, the write. */
static int push_one(tdm_dev *dev, unsigned axis, const void *seg, check_fn check, write_fn write)
{
    int rc;
    if (axis >= dev->axes) {
        return TDM_E_AXIS;
    }
    if (seg == 0) {
        return TDM_E_ARG;
    }
    rc = check(seg, dev->max_rate);
    if (rc != 0) {
        return rc;
    }
    if (tdm_queue_room(dev, axis) == 0u) {
        return TDM_E_FULL;
    }
    return write(dev, axis, seg);
}

/* As many of count segments of size bytes each as the queue has room for (LEVEL read
 * once), in order, stopping at the first that fails its check or its write. */
static int push_run(tdm_dev *dev, unsigned axis, const void *segs, size_t size, unsigned count, unsigned *taken,
                    check_fn check, write_fn write)
{
    unsigned room;
    unsigned i;
    if (taken == 0 || (segs == 0 && count != 0u)) {
        return TDM_E_ARG;
    }
    *taken = 0u;
    if (axis >= dev->axes) {
        return TDM_E_AXIS;
    }
    if (count == 0u) {
        return 0;
    }
    room = tdm_queue_room(dev, axis);
    for (i = 0; i < count && i < room; i++) {
        const void *seg = (const unsigned char *)segs + i * size;
        int rc = check(seg, dev->max_rate);
        if (rc == 0) {
            rc = write(dev, axis, seg);
        }
        if (rc != 0) {
            return rc;
        }
        *taken = i + 1u;
    }
    return 0;
}

static int check_trapezoid(const void *seg, uint32_t max_rate)
{
    return tdm_segment_check((const tdm_segment *)seg, max_rate);
}

static int write_trapezoid(tdm_dev *dev, unsigned axis, const void *seg)
{
    write_segment(dev, axis, (const tdm_segment *)seg);
    return 0;
}

int tdm_push(tdm_dev *dev, unsigned axis, const tdm_segment *seg)
{
    return push_one(dev, axis, seg, check_trapezoid, write_trapezoid);
}

int tdm_push_some(tdm_dev *dev, unsigned axis, const tdm_segment *segs, unsigned count, unsigned *taken)
{
    return push_run(dev, axis, segs, sizeof *segs, count, taken, check_trapezoid, write_trapezoid);
}

#if defined(TDM_POLY_ARM)
static int check_poly(const void *seg, uint32_t max_rate)
{
    return tdm_poly_check((const tdm_poly_segment *)seg, max_rate);
}

/* The staging, the arm, the segment (its STEPS_HI write pushes it), then the arm read
 * back: 0 if the core took the push, TDM_E_REFUSED (arm cleared) if not. */
static int write_poly(tdm_dev *dev, unsigned axis, const void *p)
{
    const tdm_poly_segment *seg = (const tdm_poly_segment *)p;
    tdm_segment head;
    uint64_t a = (uint64_t)seg->a_q32;
    head.v0_rate = seg->v0_rate;
    head.t_ticks = seg->t_ticks;
    head.steps = seg->steps;
    uint16_t w[7];
    w[0] = (uint16_t)(seg->v1_rate & 0xFFFFu); /* POLY_V1_LO .. POLY_A_3, then POLY_ARM */
    w[1] = (uint16_t)(seg->v1_rate >> 16);
    w[2] = (uint16_t)(a & 0xFFFFu);
    w[3] = (uint16_t)((a >> 16) & 0xFFFFu);
    w[4] = (uint16_t)((a >> 32) & 0xFFFFu);
    w[5] = (uint16_t)(a >> 48);
    w[6] = TDM_POLY_ARM_ARM_MASK;
    tdm_write_burst(dev, TDM_POLY_V1_LO, w, 7u);
    write_segment(dev, axis, &head);
    if ((tdm_read(dev, TDM_POLY_ARM) & TDM_POLY_ARM_ARM_MASK) != 0u) {
        tdm_write(dev, TDM_POLY_ARM, 0u);
        return TDM_E_REFUSED;
    }
    return 0;
}

int tdm_push_poly(tdm_dev *dev, unsigned axis, const tdm_poly_segment *seg)
{
    return push_one(dev, axis, seg, check_poly, write_poly);
}

int tdm_push_poly_some(tdm_dev *dev, unsigned axis, const tdm_poly_segment *segs, unsigned count, unsigned *taken)
{
    return push_run(dev, axis, segs, sizeof *segs, count, taken, check_poly, write_poly);
}
#endif /* TDM_POLY_ARM */

int tdm_start(tdm_dev *dev, uint16_t mask)
{
    uint32_t all = (1ul << dev->axes) - 1u;
    if (mask == 0u || (mask & ~all) != 0u) {
        return TDM_E_AXIS;
    }
    tdm_write(dev, TDM_START, mask);
    return 0;
}

void tdm_abort(tdm_dev *dev)
{
    tdm_write(dev, TDM_ABORT, TDM_ABORT_ALL_MASK);
}

uint16_t tdm_busy(tdm_dev *dev)
{
    return tdm_read(dev, TDM_BUSY);
}

int tdm_wait_idle(tdm_dev *dev, uint16_t mask, unsigned long poll_limit)
{
    unsigned long i;
    for (i = 0; i < poll_limit; i++) {
        if ((tdm_busy(dev) & mask) == 0u) {
            return 0;
        }
    }
    return TDM_E_TIMEOUT;
}

int32_t tdm_position(tdm_dev *dev, unsigned axis)
{
    if (axis >= dev->axes) {
        return 0;
    }
    return (int32_t)read32(dev, TDM_POS_LO(axis)); /* POS_LO latches POS_HI */
}

tdm_axis_status tdm_status(tdm_dev *dev, unsigned axis)
{
    tdm_axis_status s = {0, 0, 0, 0, 0, 0};
    uint16_t v;
    if (axis >= dev->axes) {
        return s;
    }
    v = tdm_read(dev, TDM_STATUS(axis));
    s.level = (uint8_t)((v & TDM_STATUS_LEVEL_MASK) >> TDM_STATUS_LEVEL_SHIFT);
    s.busy = (uint8_t)((v & TDM_STATUS_BUSY_MASK) != 0u);
    s.underrun = (uint8_t)((v & TDM_STATUS_UNDERRUN_MASK) != 0u);
    s.overflow = (uint8_t)((v & TDM_STATUS_OVERFLOW_MASK) != 0u);
    s.error = (uint8_t)((v & TDM_STATUS_ERROR_MASK) != 0u);
    s.error_code = (uint8_t)((v & TDM_STATUS_ERROR_CODE_MASK) >> TDM_STATUS_ERROR_CODE_SHIFT);
    return s;
}

void tdm_clear_status(tdm_dev *dev, unsigned axis)
{
    if (axis < dev->axes) {
        tdm_write(dev, TDM_STATUS(axis),
                  (uint16_t)(TDM_STATUS_UNDERRUN_MASK | TDM_STATUS_OVERFLOW_MASK | TDM_STATUS_ERROR_MASK));
    }
}

tdm_events tdm_irq_service(tdm_dev *dev)
{
    tdm_events ev;
    uint16_t g;
    ev.done = tdm_read(dev, TDM_IRQ_DONE);
    ev.queue_low = tdm_read(dev, TDM_IRQ_QLOW);
    ev.error = tdm_read(dev, TDM_IRQ_ERROR);
    g = tdm_read(dev, TDM_GSTATUS);
    ev.start_failed = (uint16_t)((g & TDM_GSTATUS_START_FAILED_MASK) != 0u);
    if (ev.done) {
        tdm_write(dev, TDM_IRQ_DONE, ev.done);
    }
    if (ev.queue_low) {
        tdm_write(dev, TDM_IRQ_QLOW, ev.queue_low);
    }
    if (ev.error) {
        tdm_write(dev, TDM_IRQ_ERROR, ev.error);
    }
    if (ev.start_failed) {
        tdm_write(dev, TDM_GSTATUS, TDM_GSTATUS_START_FAILED_MASK);
    }
    return ev;
}

#if defined(TDM_STOP) || defined(TDM_ENC_AXIS)
static int axis_mask_ok(const tdm_dev *dev, uint16_t mask)
{
    return (mask & ~(uint16_t)((1ul << dev->axes) - 1u)) == 0u;
}
#endif

#if defined(TDM_STOP_HOME) || defined(TDM_PROBE_POS_LO) || defined(TDM_ENC_AXIS)
/* A 32-bit register read tear-free: reading the low half latches the high half. */
static int32_t read_latched(tdm_dev *dev, uint32_t lo, uint32_t hi)
{
    uint32_t l;
    uint32_t h;
    if (hi == lo + 2u) {
        return (int32_t)read32(dev, lo); /* one frame on SPI */
    }
    l = tdm_read(dev, lo); /* latches the high half */
    h = tdm_read(dev, hi);
    return (int32_t)((h << 16) | l);
}
#endif

#if defined(TDM_STOP) || defined(TDM_ENC_AXIS)
#include "tdm_planner.h"
#endif

#if defined(TDM_STOP_HOME) || defined(TDM_ENC_AXIS)
/* A rest-to-rest move of `steps` at speed and accel (steps/s, steps/s^2), planned,
 * pushed, started and waited for (tdm_home, tdm_enc_correct). */
static int rest_move(tdm_dev *dev, unsigned axis, int32_t steps, uint32_t speed, uint32_t accel, unsigned long poll_limit)
{
    tdm_segment segs[3];
    unsigned count;
    unsigned bad;
    unsigned taken;
    tdm_axis_status st;
    int rc;
    if (steps == 0) {
        return 0;
    }
    rc = tdm_plan_rates(steps, speed, accel, accel, dev->clock_hz, dev->max_rate, segs, &count, &bad);
    if (rc != 0) {
        return rc;
    }
    tdm_clear_status(dev, axis);
    rc = tdm_push_some(dev, axis, segs, count, &taken);
    if (rc != 0) {
        return rc;
    }
    if (taken != count) {
        return TDM_E_FULL;
    }
    st = tdm_status(dev, axis);
    if (st.error) {
        return st.error_code;
    }
    rc = tdm_start(dev, (uint16_t)(1u << axis));
    if (rc != 0) {
        return rc;
    }
    return tdm_wait_idle(dev, (uint16_t)(1u << axis), poll_limit);
}
#endif

#if defined(TDM_STOP)

/* Fields of groups the export lacks read as 0 here (the header leaves them out). */
#ifndef TDM_IO_STATUS_ESTOP_MASK
#define TDM_IO_STATUS_ESTOP_MASK 0u
#endif
#ifndef TDM_IO_STATUS_WATCHDOG_MASK
#define TDM_IO_STATUS_WATCHDOG_MASK 0u
#endif
#ifndef TDM_IO_CMD_ESTOP_REARM_MASK
#define TDM_IO_CMD_ESTOP_REARM_MASK 0u
#endif
#ifndef TDM_IO_CMD_WD_REARM_MASK
#define TDM_IO_CMD_WD_REARM_MASK 0u
#endif
#ifndef TDM_IRQ_IO_ESTOP_MASK
#define TDM_IRQ_IO_ESTOP_MASK 0u
#endif
#ifndef TDM_IRQ_IO_WATCHDOG_MASK
#define TDM_IRQ_IO_WATCHDOG_MASK 0u
#endif
#ifndef TDM_IRQ_IO_PROBE_MASK
#define TDM_IRQ_IO_PROBE_MASK 0u
#endif
#ifndef TDM_IRQ_IO_HOME_MASK
#define TDM_IRQ_IO_HOME_MASK 0u
#endif
#ifndef TDM_IO_AXIS_HOME_LATCHED_MASK
#define TDM_IO_AXIS_HOME_LATCHED_MASK 0u
#endif

int tdm_io_configure(tdm_dev *dev, const tdm_io_config *cfg)
{
    unsigned g;
    uint16_t refused;
    if (cfg == 0 || cfg->stop_mode > 15u || (cfg->stop_decel != 0u && cfg->stop_decel < dev->stop_decel_min)) {
        return TDM_E_ARG;
    }
    for (g = 0; g < 6u; g++) {
        if (cfg->filter[g] > 15u) {
            return TDM_E_ARG;
        }
    }
#if !defined(TDM_IO_PRESCALE)
    if (cfg->prescale != 0u) {
        return TDM_E_ARG;
    }
#endif
#if !defined(TDM_IO_EDGES)
    if (cfg->edges != 0u) {
        return TDM_E_ARG;
    }
#endif
#if !defined(TDM_WD_TIMEOUT)
    if (cfg->wd_timeout != 0u) {
        return TDM_E_ARG;
    }
#endif
    if (tdm_read(dev, TDM_GSTATUS) & TDM_GSTATUS_ENABLED_MASK) {
        return TDM_E_REFUSED;
    }
    tdm_write(dev, TDM_IO_STATUS, TDM_IO_STATUS_REFUSED_MASK);
    tdm_write(dev, TDM_STOP_STATUS, TDM_STOP_STATUS_REFUSED_MASK);
#if defined(TDM_IO_POLARITY)
    tdm_write(dev, TDM_IO_POLARITY, cfg->polarity);
#endif
#if defined(TDM_IO_FILTER_LO)
    tdm_write(dev, TDM_IO_FILTER_LO, (uint16_t)(cfg->filter[0] | cfg->filter[1] << 4 | cfg->filter[2] << 8 | cfg->filter[3] << 12));
#endif
#if defined(TDM_IO_FILTER_HI)
    tdm_write(dev, TDM_IO_FILTER_HI, (uint16_t)(cfg->filter[4] | cfg->filter[5] << 4));
#endif
#if defined(TDM_IO_PRESCALE)
    tdm_write(dev, TDM_IO_PRESCALE, cfg->prescale);
#endif
#if defined(TDM_IO_EDGES)
    tdm_write(dev, TDM_IO_EDGES, cfg->edges);
#endif
#if defined(TDM_WD_TIMEOUT)
    tdm_write(dev, TDM_WD_TIMEOUT, cfg->wd_timeout);
#endif
    if (cfg->stop_decel != 0u) {
        tdm_write(dev, TDM_STOP_DECEL_LO, (uint16_t)(cfg->stop_decel & 0xFFFFu));
        tdm_write(dev, TDM_STOP_DECEL_HI, (uint16_t)(cfg->stop_decel >> 16));
    }
#if defined(TDM_STOP_MODE)
    tdm_write(dev, TDM_STOP_MODE, cfg->stop_mode);
#endif
    refused = (uint16_t)((tdm_read(dev, TDM_IO_STATUS) & TDM_IO_STATUS_REFUSED_MASK)
                         | (tdm_read(dev, TDM_STOP_STATUS) & TDM_STOP_STATUS_REFUSED_MASK));
    return refused ? TDM_E_REFUSED : 0;
}

int tdm_io_arm(tdm_dev *dev, unsigned long poll_limit)
{
    unsigned long i;
#if defined(TDM_IO_STATUS_ESTOP_IN_MASK)
    for (i = 0; tdm_read(dev, TDM_IO_STATUS) & TDM_IO_STATUS_ESTOP_IN_MASK; i++) {
        if (i >= poll_limit) {
            return TDM_E_HALTED;
        }
    }
#endif
#if defined(TDM_IO_CMD)
    tdm_write(dev, TDM_IO_CMD, (uint16_t)(TDM_IO_CMD_ESTOP_REARM_MASK | TDM_IO_CMD_WD_REARM_MASK));
#endif
    for (i = 0; i < poll_limit; i++) {
        if ((tdm_read(dev, TDM_IO_STATUS) & (TDM_IO_STATUS_ESTOP_MASK | TDM_IO_STATUS_WATCHDOG_MASK)) == 0u) {
            return 0;
        }
    }
    return TDM_E_HALTED;
}

#if defined(TDM_WD_TIMEOUT)
void tdm_wd_feed(tdm_dev *dev)
{
    tdm_write(dev, TDM_IO_CMD, TDM_IO_CMD_WD_FEED_MASK);
}
#endif

int tdm_soft_limits(tdm_dev *dev, unsigned axis, int32_t min, int32_t max, int enable)
{
    if (axis >= dev->axes) {
        return TDM_E_AXIS;
    }
    if (enable && min > max) {
        return TDM_E_ARG;
    }
    tdm_write(dev, TDM_SL_STATUS, TDM_SL_STATUS_REFUSED_MASK);
    tdm_write(dev, TDM_SL_AXIS, (uint16_t)axis);
    tdm_write(dev, TDM_SL_MIN_LO, (uint16_t)((uint32_t)min & 0xFFFFu));
    tdm_write(dev, TDM_SL_MIN_HI, (uint16_t)((uint32_t)min >> 16));
    tdm_write(dev, TDM_SL_MAX_LO, (uint16_t)((uint32_t)max & 0xFFFFu));
    tdm_write(dev, TDM_SL_MAX_HI, (uint16_t)((uint32_t)max >> 16));
    tdm_write(dev, TDM_SL_APPLY, enable ? TDM_SL_APPLY_ENABLE_MASK : 0u);
    return (tdm_read(dev, TDM_SL_STATUS) & TDM_SL_STATUS_REFUSED_MASK) ? TDM_E_REFUSED : 0;
}

int tdm_stop(tdm_dev *dev, uint16_t mask)
{
    if (mask == 0u || !axis_mask_ok(dev, mask)) {
        return TDM_E_AXIS;
    }
    tdm_write(dev, TDM_STOP, mask);
    return 0;
}

#if defined(TDM_STOP_HOME)
int tdm_stop_on_home(tdm_dev *dev, uint16_t mask)
{
    if (!axis_mask_ok(dev, mask)) {
        return TDM_E_AXIS;
    }
    tdm_write(dev, TDM_STOP_HOME, mask);
    return 0;
}

#endif

#if defined(TDM_STOP_HOME)
int32_t tdm_home_position(tdm_dev *dev, unsigned axis)
{
    return axis < dev->axes ? read_latched(dev, TDM_HOME_POS_LO(axis), TDM_HOME_POS_HI(axis)) : 0;
}
#endif

#if defined(TDM_PROBE_POS_LO)
int32_t tdm_probe_position(tdm_dev *dev, unsigned axis)
{
    return axis < dev->axes ? read_latched(dev, TDM_PROBE_POS_LO(axis), TDM_PROBE_POS_HI(axis)) : 0;
}
#endif

tdm_io_events tdm_io_service(tdm_dev *dev)
{
    tdm_io_events ev = {0, 0, 0, 0, 0};
    uint16_t irq = tdm_read(dev, TDM_IRQ_IO);
    unsigned a;
    ev.estop = (uint8_t)((irq & TDM_IRQ_IO_ESTOP_MASK) != 0u);
    ev.watchdog = (uint8_t)((irq & TDM_IRQ_IO_WATCHDOG_MASK) != 0u);
    ev.probe = (uint8_t)((irq & TDM_IRQ_IO_PROBE_MASK) != 0u);
    if (irq & (TDM_IRQ_IO_HOME_MASK | TDM_IRQ_IO_STOP_MASK)) {
        for (a = 0; a < dev->axes; a++) {
            uint16_t v = tdm_read(dev, TDM_IO_AXIS(a));
            if (v & TDM_IO_AXIS_HOME_LATCHED_MASK) {
                ev.home |= (uint16_t)(1u << a);
            }
            if (v & TDM_IO_AXIS_STOPPED_MASK) {
                ev.stopped |= (uint16_t)(1u << a);
            }
        }
    }
    if (irq) {
        tdm_write(dev, TDM_IRQ_IO, irq);
    }
    return ev;
}

#if defined(TDM_STOP_HOME)
int tdm_home(tdm_dev *dev, unsigned axis, const tdm_home_params *p, int32_t *home_pos)
{
    uint16_t bit;
    uint16_t armed;
    int32_t h;
    int32_t dir;
    int rc;
    if (axis >= dev->axes) {
        return TDM_E_AXIS;
    }
    if (p == 0 || home_pos == 0 || (p->dir != 1 && p->dir != -1) || p->max_travel == 0u
        || p->max_travel > 0x7FFFFFFFul || p->backoff == 0u || p->backoff > 0x7FFFFFFFul) {
        return TDM_E_ARG;
    }
    dir = p->dir;
    bit = (uint16_t)(1u << axis);
    /* Already on the switch: leave it first, so the search sees it become active. */
    if (tdm_read(dev, TDM_IO_AXIS(axis)) & TDM_IO_AXIS_HOME_MASK) {
        rc = rest_move(dev, axis, -dir * (int32_t)p->backoff, p->speed, p->accel, p->poll_limit);
        if (rc != 0) {
            return rc;
        }
    }
    tdm_write(dev, TDM_IRQ_IO, TDM_IRQ_IO_HOME_MASK); /* clears HOME_LATCHED */
    armed = tdm_read(dev, TDM_STOP_HOME);
    tdm_write(dev, TDM_STOP_HOME, (uint16_t)(armed | bit));
    rc = rest_move(dev, axis, dir * (int32_t)p->max_travel, p->speed, p->accel, p->poll_limit);
    tdm_write(dev, TDM_STOP_HOME, (uint16_t)(armed & ~bit));
    if (rc != 0) {
        return rc;
    }
    if ((tdm_read(dev, TDM_IO_AXIS(axis)) & TDM_IO_AXIS_HOME_LATCHED_MASK) == 0u) {
        return TDM_E_NOHOME;
    }
    h = tdm_home_position(dev, axis);
    /* Back off past the latched position, then approach it slowly. */
    rc = rest_move(dev, axis, h - dir * (int32_t)p->backoff - tdm_position(dev, axis), p->speed, p->accel, p->poll_limit);
    if (rc != 0) {
        return rc;
    }
    rc = rest_move(dev, axis, h - tdm_position(dev, axis), p->slow_speed, p->accel, p->poll_limit);
    if (rc != 0) {
        return rc;
    }
    *home_pos = h;
    return 0;
}
#endif /* TDM_STOP_HOME */
#endif /* TDM_STOP */

#if defined(TDM_ENC_AXIS)
/* ---- Encoder feedback (`export --encoder`) ---- */

int tdm_enc_configure(tdm_dev *dev, const tdm_enc_config *cfg)
{
    unsigned a;
    if (cfg == 0 || cfg->filter > TDM_ENC_FILTER_MAX || cfg->index_mode > 15u) {
        return TDM_E_ARG;
    }
#if defined(TDM_ENC_STOP_MODE)
    if (cfg->stop_controlled > 1u) {
        return TDM_E_ARG;
    }
#endif
    for (a = 0; a < dev->axes; a++) {
        if (cfg->ratio[a] == 0u || cfg->ratio[a] > TDM_ENC_RATIO_MAX) {
            return TDM_E_ARG;
        }
    }
    if (!axis_mask_ok(dev, cfg->invert) || !axis_mask_ok(dev, cfg->stop)) {
        return TDM_E_AXIS;
    }
    if (tdm_read(dev, TDM_GSTATUS) & TDM_GSTATUS_ENABLED_MASK) {
        return TDM_E_REFUSED;
    }
    tdm_write(dev, TDM_ENC_STATUS, TDM_ENC_STATUS_REFUSED_MASK);
    tdm_write(dev, TDM_ENC_FILTER, cfg->filter);
    tdm_write(dev, TDM_ENC_INDEX_MODE, cfg->index_mode);
    tdm_write(dev, TDM_ENC_INVERT, cfg->invert);
    tdm_write(dev, TDM_ENC_VEL_PRESCALE, cfg->vel_prescale);
    tdm_write(dev, TDM_ENC_STOP, cfg->stop);
#if defined(TDM_ENC_STOP_MODE)
    tdm_write(dev, TDM_ENC_STOP_MODE, cfg->stop_controlled);
#endif
    for (a = 0; a < dev->axes; a++) {
        dev->enc_ratio[a] = cfg->ratio[a];
        tdm_write(dev, TDM_ENC_AXIS, (uint16_t)a);
        tdm_write(dev, TDM_ENC_RATIO_LO, (uint16_t)(cfg->ratio[a] & 0xFFFFu));
        tdm_write(dev, TDM_ENC_RATIO_HI, (uint16_t)(cfg->ratio[a] >> 16));
        tdm_write(dev, TDM_ENC_TOL, cfg->tol[a]);
    }
    return (tdm_read(dev, TDM_ENC_STATUS) & TDM_ENC_STATUS_REFUSED_MASK) ? TDM_E_REFUSED : 0;
}

int tdm_enc_read(tdm_dev *dev, unsigned axis, tdm_enc_status *st, unsigned long poll_limit)
{
    unsigned long n;
    uint16_t state = 0;
    if (st == 0) {
        return TDM_E_ARG;
    }
    if (axis >= dev->axes) {
        return TDM_E_AXIS;
    }
    if ((tdm_read(dev, TDM_ENC_AXIS) & 0xFu) != axis) {
        tdm_write(dev, TDM_ENC_AXIS, (uint16_t)axis);
    }
    for (n = 0; n < poll_limit; n++) {
        state = tdm_read(dev, TDM_ENC_STATE);
        if (state & TDM_ENC_STATE_VALID_MASK) {
            break;
        }
    }
    if ((state & TDM_ENC_STATE_VALID_MASK) == 0u) {
        return TDM_E_TIMEOUT;
    }
    st->count = read_latched(dev, TDM_ENC_COUNT_LO, TDM_ENC_COUNT_HI);
    st->index = read_latched(dev, TDM_ENC_INDEX_LO, TDM_ENC_INDEX_HI);
    st->index_pos = read_latched(dev, TDM_ENC_INDEX_POS_LO, TDM_ENC_INDEX_POS_HI);
    st->probe = read_latched(dev, TDM_ENC_PROBE_LO, TDM_ENC_PROBE_HI);
    st->deviation = read_latched(dev, TDM_ENC_DEV_LO, TDM_ENC_DEV_HI);
    st->period = tdm_read(dev, TDM_ENC_PERIOD);
    st->age = tdm_read(dev, TDM_ENC_AGE);
    st->state = tdm_read(dev, TDM_ENC_STATE);
    return 0;
}

int tdm_enc_align(tdm_dev *dev, uint16_t mask)
{
    if (!axis_mask_ok(dev, mask)) {
        return TDM_E_AXIS;
    }
    tdm_write(dev, TDM_ENC_ALIGN, mask);
    return 0;
}

int tdm_enc_clear(tdm_dev *dev, uint16_t mask)
{
    if (!axis_mask_ok(dev, mask)) {
        return TDM_E_AXIS;
    }
    tdm_write(dev, TDM_ENC_CLEAR, mask);
    return 0;
}

int tdm_enc_correct(tdm_dev *dev, unsigned axis, uint32_t speed, uint32_t accel, unsigned long poll_limit, int32_t *moved)
{
    tdm_enc_status st;
    uint32_t ratio;
    int64_t num;
    int32_t steps;
    uint16_t bit;
    int rc;
    if (moved == 0) {
        return TDM_E_ARG;
    }
    *moved = 0;
    if (axis >= dev->axes) {
        return TDM_E_AXIS;
    }
    bit = (uint16_t)(1u << axis);
    if ((tdm_read(dev, TDM_BUSY) & bit) || (tdm_status(dev, axis).level != 0u)) {
        return TDM_E_BUSY;
    }
    rc = tdm_enc_read(dev, axis, &st, poll_limit);
    if (rc != 0) {
        return rc;
    }
    ratio = dev->enc_ratio[axis];
    if (ratio == 0u) {
        ratio = TDM_ENC_RATIO_ONE; /* not configured: the core's reset value */
    }
    /* The steps the encoder lags by: deviation / ratio, rounded to the nearest. */
    num = (int64_t)st.deviation * 65536;
    num += num >= 0 ? (int64_t)(ratio / 2u) : -(int64_t)(ratio / 2u);
    steps = (int32_t)(num / (int64_t)ratio);
    /* Keep the deviation relative to here, let the axis run again, and move the lost steps. */
    tdm_write(dev, TDM_ENC_ALIGN, bit);
    tdm_write(dev, TDM_ENC_CLEAR, bit);
    rc = rest_move(dev, axis, steps, speed, accel, poll_limit);
    if (rc == 0) {
        *moved = steps;
    }
    return rc;
}

uint16_t tdm_enc_service(tdm_dev *dev, uint16_t *failed)
{
    uint16_t irq = tdm_read(dev, TDM_IRQ_ENC);
    if (failed != 0) {
        *failed = tdm_read(dev, TDM_ENC_FAIL);
    }
    if (irq) {
        tdm_write(dev, TDM_IRQ_ENC, irq);
    }
    return irq;
}
#endif /* TDM_ENC_AXIS */
