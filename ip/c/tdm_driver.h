/* tdm_driver.h: the MCU driver of the tdm-stepper IP core (portable C99).
 *
 * No heap, no floating point, no global state: everything lives in a tdm_dev the
 * caller owns. The bus is reached either through a memory-mapped base pointer (the
 * FSMC/EXMC bank, 16-bit halfword accesses) or through two user hooks, read16 and
 * write16, that take a byte offset from the bank base.
 *
 * Compile it with the tdm_stepper_regs.h that `tdm-stepper export` wrote for your
 * bitstream: tdm_identify() refuses a core whose ID registers differ from that
 * header (axes, clock, depths, minimum period, register map major version).
 *
 * Return values: 0 is success; 1..6 are the segment error codes the core itself
 * reports in STATUS.ERROR_CODE (TDM_ERR_* in the register header); negative values
 * are the driver's own errors (TDM_E_*).
 *
 * Not reentrant per device: a position read uses one latch shared by all axes, so
 * do not read positions from an interrupt while the main loop reads them too. */
#ifndef TDM_DRIVER_H
#define TDM_DRIVER_H

#include <stdint.h>
#include "tdm_stepper_regs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The driver's own errors (negative). */
#define TDM_E_MAGIC (-1)      /* ID_MAGIC is not 0x5453: wrong bank, wiring or FSMC timing */
#define TDM_E_VERSION (-2)    /* register map major version differs from the header's */
#define TDM_E_CONFIG (-3)     /* K, clock, depths or minimum period differ from the header's */
#define TDM_E_AXIS (-4)       /* axis number >= K, or a mask with bits >= K */
#define TDM_E_TIMEOUT (-5)    /* the core did not answer within the poll limit */
#define TDM_E_REFUSED (-6)    /* the core refused the write (GSTATUS.REFUSED) */
#define TDM_E_ARG (-7)        /* a null pointer or an argument out of range */
#define TDM_E_FULL (-8)       /* the axis's queue is full: nothing was written */

/* Polls of a status register before TDM_E_TIMEOUT (each poll is one bus read). */
#ifndef TDM_POLL_LIMIT
#define TDM_POLL_LIMIT 100000ul
#endif

/* Segment limits (docs/model.md); the core checks the same. */
#define TDM_MAX_T_TICKS (1ul << 30)
#define TDM_MAX_STEPS (1ul << 24)
#define TDM_MAX_V0_RATE 0x7FFFFFFFul

typedef uint16_t (*tdm_read16_fn)(void *ctx, uint32_t byte_offset);
typedef void (*tdm_write16_fn)(void *ctx, uint32_t byte_offset, uint16_t value);

/* One motion segment in register units: start rate (Q0.32 steps per clk tick),
 * duration (clk ticks), signed steps. */
typedef struct {
    uint32_t v0_rate;
    uint32_t t_ticks;
    int32_t steps;
} tdm_segment;

/* A core as the driver knows it. Fill it with tdm_open_mmio() or tdm_open_hooks(),
 * then call tdm_identify(). */
typedef struct {
    volatile uint16_t *base; /* memory-mapped bank, or 0 when hooks are used */
    tdm_read16_fn read16;
    tdm_write16_fn write16;
    void *ctx;
    /* Read from the ID registers by tdm_identify(). */
    uint16_t version;
    uint16_t axes;
    uint16_t queue_depth;
    uint16_t fifo_depth;
    uint16_t t_calc;
    uint16_t min_period;
    uint32_t clock_hz;
    uint32_t max_rate;
} tdm_dev;

/* What tdm_irq_service() found (and cleared): bit a = axis a. */
typedef struct {
    uint16_t done;         /* a segment of the axis finished */
    uint16_t queue_low;    /* the axis's LEVEL fell to QLOW_LEVEL or below */
    uint16_t error;        /* UNDERRUN, OVERFLOW, ERROR or a failed START */
    uint16_t start_failed; /* GSTATUS.START_FAILED was set (1) or not (0) */
} tdm_events;

/* Axis status, decoded from STATUS. */
typedef struct {
    uint8_t level;      /* segments pushed and not yet taken */
    uint8_t busy;       /* segments queued, in flight or moving */
    uint8_t underrun;   /* a period came late (sticky until cleared) */
    uint8_t overflow;   /* a push was refused (sticky until cleared) */
    uint8_t error;      /* a segment was rejected (sticky until cleared) */
    uint8_t error_code; /* 1..6, the most recent rejection */
} tdm_axis_status;

void tdm_open_mmio(tdm_dev *dev, volatile void *bank_base);
void tdm_open_hooks(tdm_dev *dev, tdm_read16_fn read16, tdm_write16_fn write16, void *ctx);

/* One register access, through the base pointer or the hooks. */
uint16_t tdm_read(const tdm_dev *dev, uint32_t byte_offset);
void tdm_write(const tdm_dev *dev, uint32_t byte_offset, uint16_t value);

/* Reads the ID registers into dev and compares them with tdm_stepper_regs.h:
 * 0, TDM_E_MAGIC, TDM_E_VERSION or TDM_E_CONFIG. */
int tdm_identify(tdm_dev *dev);

/* Writes the output timing (clk ticks, each 1..65535) while the core is disabled,
 * then CTRL.ENABLE = 1, and waits for GSTATUS.ENABLED. TDM_E_ARG for a zero
 * value or timing that does not fit the minimum period (the core would refuse it),
 * TDM_E_REFUSED if the core refused anyway, TDM_E_TIMEOUT. */
int tdm_enable(tdm_dev *dev, uint16_t step_high, uint16_t step_low, uint16_t dir_setup, uint16_t dir_hold);

/* CTRL.ENABLE = 0: stops and clears everything (positions too). */
void tdm_disable(tdm_dev *dev);

/* Q0.32 rate of a speed in steps/s: round(sps * 2^32 / clock_hz). 0 when sps is
 * not below clock_hz / 2 (no valid rate). */
uint32_t tdm_rate_from_sps(uint32_t clock_hz, uint32_t steps_per_s);

/* The core's check, on the host: 0 or the code (1..6) the core would report, with
 * RMAX = max_rate (dev->max_rate). Touches no bus. */
int tdm_segment_check(const tdm_segment *seg, uint32_t max_rate);

/* Validates and pushes one segment. TDM_E_AXIS, the segment's code (1..6) without
 * touching the bus, or TDM_E_FULL when the queue is full (nothing written). */
int tdm_push(tdm_dev *dev, unsigned axis, const tdm_segment *seg);

/* Pushes as many of segs[0..count) as the axis's queue has room for (reading
 * LEVEL once), in order, never overflowing it. *taken says how many went. Returns
 * 0, TDM_E_AXIS, or the code (1..6) of the first invalid segment (segs[*taken]),
 * which is not pushed; nothing after it is. */
int tdm_push_some(tdm_dev *dev, unsigned axis, const tdm_segment *segs, unsigned count, unsigned *taken);

/* Queue room of an axis: ID_QUEUE_DEPTH - LEVEL (0 on a bad axis). */
unsigned tdm_queue_room(tdm_dev *dev, unsigned axis);

/* Releases the masked axes on one clk edge (each once its first period is ready). */
int tdm_start(tdm_dev *dev, uint16_t mask);

/* Hard stop of every axis; positions stay exact. */
void tdm_abort(tdm_dev *dev);

/* Bit a: axis a busy (queued, in flight, moving or its last pulse still high). */
uint16_t tdm_busy(tdm_dev *dev);

/* Waits until no axis of mask is busy: 0 or TDM_E_TIMEOUT (after poll_limit reads). */
int tdm_wait_idle(tdm_dev *dev, uint16_t mask, unsigned long poll_limit);

/* Signed position of an axis, read tear-free (POS_LO latches POS_HI). */
int32_t tdm_position(tdm_dev *dev, unsigned axis);

/* STATUS of an axis, decoded (all zero on a bad axis). */
tdm_axis_status tdm_status(tdm_dev *dev, unsigned axis);

/* Clears the axis's sticky STATUS flags (UNDERRUN, OVERFLOW, ERROR and its code). */
void tdm_clear_status(tdm_dev *dev, unsigned axis);

/* Reads and clears the events (IRQ_DONE, IRQ_QLOW, IRQ_ERROR, GSTATUS.START_FAILED):
 * call it from the irq handler. Only the bits it returns are cleared, so an event
 * that arrives in between is not lost. */
tdm_events tdm_irq_service(tdm_dev *dev);

#ifdef __cplusplus
}
#endif

#endif /* TDM_DRIVER_H */
