// Reference design for the Radiona ULX3S (Lattice ECP5 LFE5U-85F, CABGA381): the
// tdm-stepper IP (K = 2, exported with --bus spi --io all --clock-hz 50000000) on
// SPI to the board's GPIO header, STEP and DIR of both axes and the machine I/O
// (e-stop, probe, limits, home, drive alarms, driver enables) on the header, STEP and
// DIR on LEDs.
//
// Clocks: the board's 25 MHz oscillator into the ECP5 PLL (board_pll.v, made by
// ecppll at build time): clk = 50 MHz for the core, bus_clk = 100 MHz for the SPI
// front end and the register file (SCK up to 25 MHz). Reset: FIRE1 held, or the PLL
// not locked.
//
// Header J1 (3.3 V, see ulx3s.lpf): GP0 cs_n, GN0 sck, GP1 mosi, GN1 miso (driven
// only while cs_n is low), GP2/GN2 step/dir of axis 0, GP3/GN3 step/dir of axis 1,
// GP4 irq; GN4/GP5 drv_enable of axis 0/1; GN5 estop_n (pulled down: an open
// e-stop circuit stops the machine); GP6 probe; axis 0 GN6 limit_neg, GP7 limit_pos,
// GN7 home, GP8 alarm; axis 1 GN8 limit_neg, GP9 limit_pos, GN9 home, GP10 alarm
// (pulled up: normally-closed switches to ground, the fail-safe wiring, read high
// when tripped or broken, active at IO_POLARITY's reset value; docs/registers.md).
// LEDs: 0 step 0, 1 dir 0, 2 step 1, 3 dir 1, 4 a driver enabled, 5 e-stop active,
// 6 PLL locked, 7 irq.
//
// Built by `tdm-stepper board` (README, "Reference board design").
module ulx3s_top (
    input  wire       clk_25mhz,
    input  wire       btn_fire1,
    input  wire       spi_cs_n,
    input  wire       spi_sck,
    input  wire       spi_mosi,
    output wire       spi_miso,
    output wire [1:0] step,
    output wire [1:0] dir,
    output wire       irq,
    output wire [1:0] drv_enable,
    input  wire       estop_n,
    input  wire       probe,
    input  wire [1:0] limit_neg,
    input  wire [1:0] limit_pos,
    input  wire [1:0] home,
    input  wire [1:0] alarm,
    output wire [7:0] led
);
    wire clk, bus_clk, locked;
    board_pll pll (.clkin(clk_25mhz), .clkout0(clk), .clkout1(bus_clk), .locked(locked));

    wire miso, miso_oe;
    wire [4:0] fsm_state;
    tdm_stepper core (
        .clk(clk), .bus_clk(bus_clk), .reset(btn_fire1 | !locked),
        .cs_n(spi_cs_n), .sck(spi_sck), .mosi(spi_mosi), .miso(miso), .miso_oe(miso_oe),
        .step(step), .dir(dir), .irq(irq), .fsm_state(fsm_state),
        .estop_n(estop_n), .probe(probe), .limit_neg(limit_neg), .limit_pos(limit_pos),
        .home(home), .alarm(alarm), .drv_enable(drv_enable)
    );
    // MISO is released while the core is not selected, so other devices can share it.
    assign spi_miso = miso_oe ? miso : 1'bz;

    assign led = {irq, locked, !estop_n, |drv_enable, dir[1], step[1], dir[0], step[0]};
endmodule
