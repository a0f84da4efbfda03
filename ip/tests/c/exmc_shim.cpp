// A pin-level EXMC shim: the C driver's read16/write16 hooks drive the exported
// tdm_stepper's NE/NOE/NWE/A/D pins in Verilator with the documented minimum FSMC
// timing (mode 1: ADDSET, then DATAST with the strobe low, then one HCLK of rest),
// from an MCU clock unrelated to bus_clk and clk. Time only passes through the bus
// accesses and shim_idle_ns(), as it would for firmware polling a real core.
//
// Printed on stdout (the Rust test parses it):
//   E <axis> <clk cycle> <dir>   every rising STEP edge (the cycle is counted from
//                                the first clk rising edge, as the system tests do)
//   H <axis> <clk cycle> <pos> <level>   (with SHIM_IO) the home pin of an axis changed
// and whatever the C program prints. Clock half periods come from the compile line.
//
// With SHIM_IO (an `--io all` export) the machine I/O pins are driven too: estop_n
// released, every other input inactive, and a home switch per axis that the C program
// places with shim_home_switch(): active while the axis's position (counted here from
// STEP and DIR) is at or beyond `at` in direction `dir`.
// With SHIM_SPI (an `--bus spi` export) the shim is an SPI master on cs_n/sck/mosi/
// miso instead (the board_spi_transfer of the README's SPI example, which opens the
// core), at the fastest documented timing (docs/registers.md, "SPI"): SCK =
// bus_clk/4 (2 T_bus low, 2 T_bus high), CS low 1 T_bus before the first edge and
// after the last, CS high 4 T_bus between frames; mode SHIM_SPI_MODE (0 or 3). MISO
// is sampled just before each rising SCK edge, as a mode 0/3 master does.
#include "Vtdm_stepper.h"
#include "verilated.h"
#include <cstdint>
#include <cstdio>
#include "tdm_driver.h"

#ifndef CLK_HALF_PS
#define CLK_HALF_PS 10000ull
#endif
#ifndef BUS_HALF_PS
#define BUS_HALF_PS 5003ull
#endif
#ifndef MCU_HALF_PS
#define MCU_HALF_PS 2976ull
#endif

static VerilatedContext *g_ctx;
static Vtdm_stepper *g_top;
static uint64_t g_now = 0;                  // ps
static uint64_t g_next_clk = CLK_HALF_PS;   // clk starts high at 0
static uint64_t g_next_bus = 1 + BUS_HALF_PS;
static uint64_t g_clk_cycles = 0;           // clk rising edges seen
static uint32_t g_last_step = 0;
static unsigned long g_accesses = 0;
#ifdef SHIM_IO
static int32_t g_pos[16];
static int32_t g_home_at[16];
static int g_home_dir[16];
static uint32_t g_home = 0;

static void update_home(void)
{
    uint32_t h = 0;
    for (unsigned a = 0; a < 16; a++) {
        int on = (g_home_dir[a] < 0 && g_pos[a] <= g_home_at[a]) || (g_home_dir[a] > 0 && g_pos[a] >= g_home_at[a]);
        if (on) h |= 1u << a;
        if (((h ^ g_home) >> a) & 1u) {
            printf("H %u %llu %d %d\n", a, (unsigned long long)g_clk_cycles, (int)g_pos[a], on);
        }
    }
    g_home = h;
    g_top->home = h;
}
#endif

#ifdef SHIM_ENC
// With SHIM_ENC (an `--encoder` export): a motor per axis that takes a step at each
// rising STEP edge (DIR says which way) unless the C program stalls it
// (shim_enc_stall), and its encoder: ENC_NUM / 2^ENC_SHIFT counts per step (5/4), the
// lines A and B moving one count every ENC_GAP clk ticks towards floor(steps x ratio),
// A leading B when counting up; an index (Z high) while the count is ENC_INDEX_AT
// modulo ENC_CPR (4,000 counts per revolution).
#define ENC_NUM 5
#define ENC_SHIFT 2
#define ENC_GAP 4u
#define ENC_CPR 4000
#define ENC_INDEX_AT 1000
static int64_t g_motor[16];
static int64_t g_cnt[16];
static unsigned g_gap[16];
static uint32_t g_stall = 0;

static int64_t floor_shift(int64_t v, unsigned sh) { return v >= 0 ? v >> sh : -((-v + (1 << sh) - 1) >> sh); }

static void enc_tick(uint32_t rose, uint32_t dir)
{
    uint32_t a_bits = 0;
    uint32_t b_bits = 0;
    uint32_t z_bits = 0;
    for (unsigned a = 0; a < 16; a++) {
        if (((rose >> a) & 1u) && !((g_stall >> a) & 1u)) g_motor[a] += ((dir >> a) & 1u) ? -1 : 1;
        int64_t target = floor_shift(g_motor[a] * ENC_NUM, ENC_SHIFT);
        if (g_gap[a] != 0) {
            g_gap[a]--;
        } else if (g_cnt[a] != target) {
            g_cnt[a] += target > g_cnt[a] ? 1 : -1;
            g_gap[a] = ENC_GAP - 1;
        }
        unsigned ph = (unsigned)(g_cnt[a] & 3);
        if (ph == 1 || ph == 2) a_bits |= 1u << a;
        if (ph == 2 || ph == 3) b_bits |= 1u << a;
        if ((g_cnt[a] - ENC_INDEX_AT) % ENC_CPR == 0) z_bits |= 1u << a;
    }
    g_top->enc_a = a_bits;
    g_top->enc_b = b_bits;
    g_top->enc_z = z_bits;
}
#endif

// FSMC timing in HCLK cycles: ADDSET = ceil(2 T_bus / T_hclk), DATAST = ceil(3 T_bus /
// T_hclk) for writes and ceil(5 T_bus / T_hclk) for reads (docs/registers.md).
static uint64_t hclk(uint64_t bus_periods) { return (bus_periods * BUS_HALF_PS + MCU_HALF_PS - 1) / MCU_HALF_PS; }

static void advance_to(uint64_t t)
{
    for (;;) {
        uint64_t e = g_next_clk < g_next_bus ? g_next_clk : g_next_bus;
        if (e > t) break;
        g_now = e;
        if (e == g_next_clk) {
            g_top->clk = !g_top->clk;
            g_next_clk += CLK_HALF_PS;
            g_top->eval();
            if (g_top->clk) {
                g_clk_cycles++;
                uint32_t s = (uint32_t)g_top->step;
                uint32_t rose = s & ~g_last_step;
                for (unsigned a = 0; rose; a++, rose >>= 1) {
                    if (rose & 1u) {
                        unsigned d = ((uint32_t)g_top->dir >> a) & 1u;
                        printf("E %u %llu %u\n", a, (unsigned long long)g_clk_cycles, d);
#ifdef SHIM_IO
                        g_pos[a] += d ? -1 : 1;
#endif
                    }
                }
#ifdef SHIM_ENC
                enc_tick(s & ~g_last_step, (uint32_t)g_top->dir);
#endif
                g_last_step = s;
#ifdef SHIM_IO
                update_home();
#endif
            }
        } else {
            g_top->bus_clk = !g_top->bus_clk;
            g_next_bus += BUS_HALF_PS;
            g_top->eval();
        }
    }
    g_now = t;
}

static void mcu_cycles(uint64_t n) { advance_to(g_now + 2 * MCU_HALF_PS * n); }

extern "C" {

unsigned long shim_accesses(void) { return g_accesses; }
unsigned long long shim_clk_cycles(void) { return (unsigned long long)g_clk_cycles; }

void shim_idle_ns(unsigned long ns) { advance_to(g_now + (uint64_t)ns * 1000u); }

#ifdef SHIM_ENC
void shim_enc_stall(uint32_t mask) { g_stall = mask; }
long long shim_enc_count(unsigned axis) { return (long long)g_cnt[axis]; }
long long shim_motor(unsigned axis) { return (long long)g_motor[axis]; }
#endif

#ifdef SHIM_IO
void shim_home_switch(unsigned axis, int32_t at, int dir)
{
    g_home_at[axis] = at;
    g_home_dir[axis] = dir;
    update_home();
    g_top->eval();
}
#endif

#ifndef SHIM_SPI
// ADDSET: NE low with the address out, both strobes high.
static void address_phase(uint32_t byte_offset)
{
    g_accesses++;
    g_top->addr = byte_offset / 2u;
    g_top->ne = 0;
    g_top->eval();
    mcu_cycles(hclk(2));
}

// NE and the strobes rise together; the bus rests one HCLK.
static void end_access(void)
{
    g_top->nwe = 1;
    g_top->noe = 1;
    g_top->ne = 1;
    g_top->eval();
    mcu_cycles(1);
}

void shim_write16(void *ctx, uint32_t byte_offset, uint16_t value)
{
    (void)ctx;
    address_phase(byte_offset);
    g_top->data_in = value;
    g_top->nwe = 0;
    g_top->eval();
    mcu_cycles(hclk(3));
    end_access();
}

uint16_t shim_read16(void *ctx, uint32_t byte_offset)
{
    (void)ctx;
    address_phase(byte_offset);
    g_top->noe = 0;
    g_top->eval();
    mcu_cycles(hclk(5));
    uint16_t v = g_top->data_oe ? (uint16_t)g_top->data_out : 0xDEADu;
    end_access();
    return v;
}

void shim_open(tdm_dev *dev) { tdm_open_hooks(dev, shim_read16, shim_write16, 0); }

// No SPI pins: nothing to glitch.
int shim_spi_glitch(void) { return 0; }
#else
#ifndef SHIM_SPI_MODE
#define SHIM_SPI_MODE 0
#endif
static const uint64_t T_BUS = 2 * BUS_HALF_PS;
static const uint8_t SCK_IDLE = SHIM_SPI_MODE == 3 ? 1 : 0;

static void pins(int cs_n, int sck, int mosi)
{
    g_top->cs_n = cs_n;
    g_top->sck = sck;
    g_top->mosi = mosi;
    g_top->eval();
}

// One frame of `bits` bits (MSB first from tx), MISO into rx.
static void spi_bits(const uint8_t *tx, uint8_t *rx, unsigned bits)
{
    g_accesses++;
    pins(0, SCK_IDLE, 0);
    advance_to(g_now + T_BUS);
    for (unsigned i = 0; i < bits; i++) {
        int b = (tx[i / 8] >> (7 - i % 8)) & 1;
        pins(0, 0, b);
        advance_to(g_now + 2 * T_BUS);
        int m = g_top->miso_oe ? (g_top->miso & 1) : 1;
        if (rx) {
            if (i % 8 == 0) rx[i / 8] = 0;
            rx[i / 8] |= (uint8_t)(m << (7 - i % 8));
        }
        pins(0, 1, b);
        advance_to(g_now + 2 * T_BUS);
    }
    if (!SCK_IDLE && bits) {
        pins(0, 0, 0);
        advance_to(g_now + T_BUS);
    }
    pins(1, SCK_IDLE, 0);
    advance_to(g_now + 4 * T_BUS);
}

// The README's SPI example (linked in): its board hook is this shim's frame.
int open_core_on_spi(tdm_dev *dev);
void board_spi_transfer(const uint8_t *tx, uint8_t *rx, unsigned len) { spi_bits(tx, rx, 8 * len); }

void shim_open(tdm_dev *dev) { printf("SPIOPEN %d\n", open_core_on_spi(dev)); }

// A frame cut mid-word: a write of 0x0007 to QLOW_LEVEL with CS raised after 12 of
// the word's 16 bits. The core must refuse it (FRAME_ERR in the next status byte).
int shim_spi_glitch(void)
{
    uint8_t tx[4] = {TDM_SPI_CMD_WRITE, (uint8_t)(TDM_QLOW_LEVEL / 2u), 0x00, 0x07};
    spi_bits(tx, 0, 16 + 12);
    return 1;
}
#endif

int driver_check_main(int argc, char **argv);

}  // extern "C"

int main(int argc, char **argv)
{
    g_ctx = new VerilatedContext;
    g_ctx->commandArgs(argc, argv);
    g_top = new Vtdm_stepper{g_ctx};
    g_top->clk = 1;
    g_top->bus_clk = 1;
#ifdef SHIM_SPI
    g_top->cs_n = 1;
    g_top->sck = SCK_IDLE;
    g_top->mosi = 0;
#else
    g_top->ne = 1;
    g_top->noe = 1;
    g_top->nwe = 1;
    g_top->addr = 0;
    g_top->data_in = 0;
#endif
#ifdef SHIM_IO
    g_top->estop_n = 1;
#endif
    g_top->reset = 1;
    g_top->eval();
    mcu_cycles(200);
    g_top->reset = 0;
    g_top->eval();
    mcu_cycles(200);
    int rc = driver_check_main(argc, argv);
    g_top->final();
    fflush(stdout);
    delete g_top;
    delete g_ctx;
    return rc;
}
