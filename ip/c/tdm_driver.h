/* tdm_driver.h: the MCU driver of the tdm-stepper IP core (portable C99).
 *
 * No heap, no floating point, no global state: everything lives in a tdm_dev the
 * caller owns. The bus is reached through a memory-mapped base pointer (the
 * FSMC/EXMC bank, 16-bit halfword accesses; or a Wishbone or AXI4-Lite core's
 * region, 32-bit accesses: tdm_open_mmio32()), through two user hooks, read16 and
 * write16, that take a byte offset from the bank base, or (a core exported with
 * `--bus spi`) through one SPI transfer hook: tdm_open_spi(). On SPI a segment push
 * is one 14-byte frame and 32-bit values are read in one frame.
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
#define TDM_E_CONFIG (-3)     /* K, clock, depths, minimum period or options differ from the header's */
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
/* One SPI frame (mode 0 or 3, MSB first): CS low, len bytes out of tx while len bytes
 * come into rx (full duplex), CS high. At most 3 + 2 * 8 = 19 bytes. */
typedef void (*tdm_spi_xfer_fn)(void *ctx, const uint8_t *tx, uint8_t *rx, unsigned len);

/* One motion segment in register units: start rate (Q0.32 steps per clk tick),
 * duration (clk ticks), signed steps. */
typedef struct {
    uint32_t v0_rate;
    uint32_t t_ticks;
    int32_t steps;
} tdm_segment;

/* What tdm_identify_as() expects of a core: its ID registers, and the smallest
 * STOP_DECEL its export accepts (0 without the machine I/O). Each export's register
 * header defines <NAME>_IDENTITY, an initialiser of this struct for that export
 * (NAME: its --name in capitals), so firmware with several cores includes each
 * export's header (the first one, the export with the most options, as
 * tdm_stepper_regs.h; the others under other file names, after it) and passes each
 * core its own: tdm_identity a = TDM_STEPPER_IDENTITY; tdm_identify_as(&dev, &a). */
typedef struct {
    uint16_t version;
    uint16_t axes;
    uint32_t clock_hz;
    uint16_t queue_depth;
    uint16_t fifo_depth;
    uint16_t min_period;
    uint32_t max_rate;
    uint16_t options;
    uint32_t stop_decel_min;
} tdm_identity;

/* A core as the driver knows it. Fill it with tdm_open_mmio(), tdm_open_mmio32(),
 * tdm_open_hooks() or tdm_open_spi(), then call tdm_identify(). */
typedef struct {
    volatile uint16_t *base; /* memory-mapped bank, or 0 when hooks are used */
    volatile uint32_t *base32; /* a 32-bit bus (Wishbone, AXI4-Lite): register w at word w */
    tdm_read16_fn read16;
    tdm_write16_fn write16;
    tdm_spi_xfer_fn spi_xfer;
    void *ctx;
    /* SPI only: the status byte of the last frame, and the frames whose status byte
     * had FRAME_ERR set (the frame before was refused in part) or a wrong pattern
     * (MISO stuck, wrong mode or wiring). Never cleared by the driver. */
    uint8_t spi_status;
    unsigned long bus_errors;
    /* Read from the ID registers by tdm_identify(). */
    uint16_t version;
    uint16_t axes;
    uint16_t queue_depth;
    uint16_t fifo_depth;
    uint16_t t_calc;
    uint16_t min_period;
    uint32_t clock_hz;
    uint32_t max_rate;
    uint16_t options; /* ID_OPTIONS: machine I/O groups 5:0, S-curve 8, encoder 9 */
    uint32_t stop_decel_min; /* from the identity tdm_identify checked */
#if defined(TDM_ENC_AXIS)
    /* Each axis's ENC_RATIO as tdm_enc_configure() wrote it (tdm_enc_correct uses it). */
    uint32_t enc_ratio[16];
#endif
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
/* A core on a 32-bit bus (`export --bus wb` or `--bus axil`) mapped at base: register
 * word w at base + 4 * w, in bits 15..0 (32-bit accesses). */
void tdm_open_mmio32(tdm_dev *dev, volatile void *base);
/* A core on SPI (`export --bus spi`): every access is a frame through xfer. */
void tdm_open_spi(tdm_dev *dev, tdm_spi_xfer_fn xfer, void *ctx);

/* One register access, through the base pointer, the hooks or an SPI frame. */
uint16_t tdm_read(tdm_dev *dev, uint32_t byte_offset);
void tdm_write(tdm_dev *dev, uint32_t byte_offset, uint16_t value);
/* count (0..) consecutive registers from byte_offset, in address order: on SPI one
 * frame per 8 words, else one access per word. */
void tdm_read_burst(tdm_dev *dev, uint32_t byte_offset, uint16_t *values, unsigned count);
void tdm_write_burst(tdm_dev *dev, uint32_t byte_offset, const uint16_t *values, unsigned count);

/* Reads the ID registers into dev and compares them with tdm_stepper_regs.h:
 * 0, TDM_E_MAGIC, TDM_E_VERSION or TDM_E_CONFIG (also when ID_OPTIONS differs from
 * TDM_OPTIONS: a header of an export with options the core lacks, or without
 * options it has). */
int tdm_identify(tdm_dev *dev);

/* The same against `want` instead of this header's values (several cores in one
 * build: see tdm_identity). */
int tdm_identify_as(tdm_dev *dev, const tdm_identity *want);

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

#if defined(TDM_STOP)
/* ---- Machine I/O: declared only with a header from `export --io` ---------------
 * With some groups only (`--io limits,home`, ...), the functions of a group that was
 * not exported are not declared (tdm_wd_feed: watchdog; tdm_stop_on_home,
 * tdm_home_position, tdm_home: home; tdm_probe_position: probe). */

#define TDM_E_NOHOME (-9)  /* tdm_home(): the search move ended without the home latch */
#define TDM_E_HALTED (-10) /* the e-stop input is active or its latch did not clear */

/* Input groups, in IO_POLARITY's bit order and tdm_io_config.filter's. */
enum { TDM_GROUP_ESTOP, TDM_GROUP_PROBE, TDM_GROUP_LIMIT_NEG, TDM_GROUP_LIMIT_POS, TDM_GROUP_HOME, TDM_GROUP_ALARM };

/* The machine I/O's configuration, written while the core is disabled. */
typedef struct {
    uint8_t polarity;    /* bit g (TDM_GROUP_*): group g's pins are active low; the reset value 1 has estop_n active low */
    uint8_t filter[6];   /* per group, 0..15 filter samples (0: no filter) */
    uint16_t prescale;   /* a filter sample every prescale + 1 clk ticks */
    uint8_t edges;       /* IO_EDGES: bit 0 the home latch, bit 1 the probe's, 1 = on release */
    uint16_t wd_timeout; /* the watchdog, in units of 1,024 clk ticks; 0 = off */
    uint32_t stop_decel; /* the controlled stop's deceleration, a = DECEL / 2^57 steps/tick^2; 0 keeps the reset value (the hardest) */
    uint8_t stop_mode;   /* STOP_MODE: TDM_STOP_MODE_*_MASK of the sources that take the controlled stop */
} tdm_io_config;

/* Writes the configuration. The core must be disabled (before tdm_enable, or after
 * tdm_disable). TDM_E_ARG for a filter above 15, a STOP_MODE bit above 3, a
 * deceleration below the export's minimum (TDM_STOP_DECEL_MIN, dev->stop_decel_min), or a non-zero prescale, edges or wd_timeout
 * whose register the export lacks, without touching the bus; TDM_E_REFUSED if the core
 * is enabled (nothing written) or refused a write. Fields of groups not exported are
 * ignored by the core (they read 0). */
int tdm_io_configure(tdm_dev *dev, const tdm_io_config *cfg);

/* After tdm_enable: waits (at most poll_limit reads) until the filtered e-stop reads
 * released, re-arms the e-stop latch and the watchdog, and checks that both cleared
 * (each if the export has it). 0 or TDM_E_HALTED. */
int tdm_io_arm(tdm_dev *dev, unsigned long poll_limit);

#if defined(TDM_WD_TIMEOUT)
/* Feeds the watchdog (IO_CMD.WD_FEED): call it more often than WD_TIMEOUT·1,024 ticks. */
void tdm_wd_feed(tdm_dev *dev);
#endif

/* Soft limits of an axis, inclusive (enable = 0 turns them off). TDM_E_AXIS, TDM_E_ARG
 * for min > max (no bus access), TDM_E_REFUSED if the core refused them. */
int tdm_soft_limits(tdm_dev *dev, unsigned axis, int32_t min, int32_t max, int enable);

/* The controlled stop of the masked axes (STOP): each ramps down to rest at
 * STOP_DECEL; wait for tdm_wait_idle() before reading its position. TDM_E_AXIS. */
int tdm_stop(tdm_dev *dev, uint16_t mask);

#if defined(TDM_STOP_HOME)
/* Arms (bit set) or disarms the stop on home of each axis (STOP_HOME). TDM_E_AXIS. */
int tdm_stop_on_home(tdm_dev *dev, uint16_t mask);

/* The position the home latch of an axis took, read tear-free. */
int32_t tdm_home_position(tdm_dev *dev, unsigned axis);
#endif
#if defined(TDM_PROBE_POS_LO)
/* The position the probe latch took on an axis, read tear-free. */
int32_t tdm_probe_position(tdm_dev *dev, unsigned axis);
#endif

/* What tdm_io_service() found (and cleared). */
typedef struct {
    uint8_t estop;    /* the filtered e-stop became active */
    uint8_t watchdog; /* the watchdog tripped */
    uint8_t probe;    /* the probe latch took every axis's position */
    uint16_t home;    /* bit a: axis a's home latch took its position */
    uint16_t stopped; /* bit a: a limit, the alarm, the stop on home or a watchdog ramp stopped axis a */
} tdm_io_events;

/* Reads and clears IRQ_IO (and, for HOME and STOP, which axes from IO_AXIS): call it
 * from the irq handler. A HOME or STOP event of another axis that comes between the
 * reads and the clear (a few bus accesses) is cleared with them unread. */
tdm_io_events tdm_io_service(tdm_dev *dev);

/* A homing sequence for one axis with the stop on home (hard or controlled, as
 * STOP_MODE.HOME says): if the switch is already active, back off first; then a move
 * of dir·max_travel steps toward the switch that the home latch ends, back off
 * `backoff` steps past the latched position, and approach it again at slow_speed:
 * the axis rests at the latched position, returned in *home_pos (the machine's zero is
 * POS − *home_pos). Speeds in steps/s, accel in steps/s^2 (the planner's ranges);
 * poll_limit bounds each wait. 0, TDM_E_ARG, TDM_E_AXIS, TDM_E_NOHOME (the search
 * ended without the switch; the stop on home is disarmed again), TDM_E_TIMEOUT, a
 * planner error (tdm_plan_rates) or the code (1..9) the core gave a push. The home
 * latch's edge (IO_EDGES bit 0) must be 0: on becoming active. */
typedef struct {
    int dir;              /* +1 or -1: toward the switch */
    uint32_t max_travel;  /* steps, at most 2^31 - 1 */
    uint32_t speed;       /* search and back-off speed */
    uint32_t slow_speed;  /* the final approach */
    uint32_t accel;
    uint32_t backoff;     /* steps, more than the stop's overshoot */
    unsigned long poll_limit;
} tdm_home_params;
#if defined(TDM_STOP_HOME)
int tdm_home(tdm_dev *dev, unsigned axis, const tdm_home_params *p, int32_t *home_pos);
#endif
#endif /* TDM_STOP */

#if defined(TDM_ENC_AXIS)
/* ---- Encoder feedback: declared only with a header from `export --encoder` ------- */

#define TDM_E_BUSY (-11) /* tdm_enc_correct(): the axis is moving or has segments queued */

/* The encoders' configuration, written while the core is disabled. */
typedef struct {
    uint8_t filter;          /* A, B and Z filter, clk ticks (0..TDM_ENC_FILTER_MAX; 0 = off) */
    uint8_t index_mode;      /* ENC_INDEX_MODE: Z_LOW, GATE, GATE_A, GATE_B */
    uint16_t invert;         /* bit a: axis a counts down when A leads B */
    uint16_t vel_prescale;   /* ENC_PERIOD and ENC_AGE count a tick every vel_prescale + 1 clk ticks */
    uint16_t stop;           /* bit a: axis a's ENC_FAIL stops it (hard, or see stop_controlled) */
#if defined(TDM_ENC_STOP_MODE)
    uint8_t stop_controlled; /* 1: that stop is the controlled stop (a ramp at STOP_DECEL); with the machine I/O only */
#endif
    uint32_t ratio[TDM_AXES]; /* counts per step, Q16.16 (TDM_ENC_RATIO_ONE = 1.0), 1..TDM_ENC_RATIO_MAX */
    uint16_t tol[TDM_AXES];  /* following-error tolerance, counts; 0 = no check */
} tdm_enc_config;

/* One axis's encoder, as its last copy showed it. */
typedef struct {
    int32_t count;     /* counts, signed */
    int32_t index;     /* the count the index latch took */
    int32_t index_pos; /* the step position at that index (0 before an index since reset) */
    int32_t probe;     /* the count the probe latched (with the machine I/O's probe) */
    int32_t deviation; /* position x ratio + offset - count: positive when the encoder lags */
    uint16_t period;   /* velocity ticks between the last two edges (saturating) */
    uint16_t age;      /* velocity ticks since the last edge (saturating): a stall shows here */
    uint16_t state;    /* ENC_STATE: ILLEGAL 7:0, ARMED, DIR, A, B, Z, FAIL, VALID */
} tdm_enc_status;

/* Writes the configuration and keeps the ratios in dev. The core must be disabled.
 * TDM_E_ARG (a filter above TDM_ENC_FILTER_MAX, an index mode above 15, a ratio of 0 or
 * above TDM_ENC_RATIO_MAX, stop_controlled above 1) and TDM_E_AXIS (a mask bit >= K) without touching the bus;
 * TDM_E_REFUSED if the core is enabled (nothing written) or refused a write. */
int tdm_enc_configure(tdm_dev *dev, const tdm_enc_config *cfg);

/* Reads axis `axis`'s encoder through the window (ENC_AXIS, then waits at most
 * poll_limit reads for ENC_STATE.VALID; each 32-bit value tear-free). 0, TDM_E_ARG,
 * TDM_E_AXIS or TDM_E_TIMEOUT. */
int tdm_enc_read(tdm_dev *dev, unsigned axis, tdm_enc_status *st, unsigned long poll_limit);

/* ENC_ALIGN (the masked axes' deviation becomes 0) and ENC_CLEAR (their ENC_FAIL
 * clears; align first, or it sets again). TDM_E_AXIS. */
int tdm_enc_align(tdm_dev *dev, uint16_t mask);
int tdm_enc_clear(tdm_dev *dev, uint16_t mask);

/* The correction the MCU makes after a lost step, as the source motion card does: on
 * an idle axis (BUSY 0, nothing queued; else TDM_E_BUSY), reads the deviation d,
 * aligns and clears the axis's ENC_FAIL, and moves round(d / ratio) steps (planned by
 * tdm_plan_rates at speed and accel, steps/s and steps/s^2; waited for within
 * poll_limit reads per wait), returned in *moved. Afterwards the encoder reads the
 * position the steps commanded before the loss would have put it at, within the
 * ratio's resolution (half a step's counts), and the deviation is measured from
 * there (POS counts the correction's steps too). 0, TDM_E_ARG, TDM_E_AXIS,
 * TDM_E_BUSY, TDM_E_TIMEOUT, a planner error or a push's code. */
int tdm_enc_correct(tdm_dev *dev, unsigned axis, uint32_t speed, uint32_t accel, unsigned long poll_limit, int32_t *moved);

/* Reads and clears IRQ_ENC (returned: TDM_IRQ_ENC_*_MASK bits); *failed (if not null)
 * gets ENC_FAIL (bit a: axis a). */
uint16_t tdm_enc_service(tdm_dev *dev, uint16_t *failed);
#endif /* TDM_ENC_AXIS */

#if defined(TDM_POLY_ARM)
/* ---- S-curve: declared only with a header from `export --profiles trapezoid,scurve`
 * Polynomial segments come from the S-curve planner (tdm_scurve.h: tdm_plan_jerk,
 * tdm_plan_fourth) and mix freely with trapezoid segments on every axis. */
#include "tdm_scurve.h"

/* Validates and pushes one polynomial segment: writes POLY_V1 and POLY_A (global
 * staging), sets POLY_ARM, writes the segment's V0, T and STEPS (the STEPS_HI write
 * pushes it), then reads POLY_ARM back: the core clears it when it takes the push, so
 * a 1 means the push was refused (the driver clears the arm, so the next trapezoid push
 * is not taken as polynomial, and returns TDM_E_REFUSED). TDM_E_AXIS, TDM_E_ARG, the
 * segment's code (1..6, tdm_poly_check) without touching the bus, or TDM_E_FULL when
 * the queue is full (nothing written). Not reentrant with another push: the staging
 * registers are shared by all axes. */
int tdm_push_poly(tdm_dev *dev, unsigned axis, const tdm_poly_segment *seg);

/* tdm_push_some for polynomial segments: as many of segs[0..count) as the queue has
 * room for, in order; *taken says how many went. 0, TDM_E_AXIS, TDM_E_ARG,
 * TDM_E_REFUSED, or the code (1..6) of the first invalid segment (segs[*taken]), which
 * is not pushed; nothing after it is. */
int tdm_push_poly_some(tdm_dev *dev, unsigned axis, const tdm_poly_segment *segs, unsigned count, unsigned *taken);
#endif /* TDM_POLY_ARM */

#ifdef __cplusplus
}
#endif

#endif /* TDM_DRIVER_H */
