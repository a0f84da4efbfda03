//! The HDL blocks of the core, one block per file, each with its three-way test.
//!
//! | block | file | latency |
//! |---|---|---|
//! | pipelined 32×32 multiplier (custom Verilog leaf) | `mul_wide.rs` | 2 cycles |
//! | sequential multiplier, 100 × 32 → 100 bits, R bits per cycle | `mul_seq.rs` | `1 + 32/R` cycles |
//! | divider, 104-bit numerator by 64-bit denominator, R digits per cycle | `divider.rs` | `1 + 104/R` cycles |
//! | offset root ⌊√(p² + c)⌋ − p, 36 digits, R per cycle | `root.rs` | `1 + 36/R` cycles |
//! | control of an iterative unit (start, fixed cycles, valid) | `iterate.rs` | `1 + cycles` |
//! | distributed RAM, synchronous write, asynchronous read (custom Verilog leaf) | `lut_ram.rs` | 0 (read) |
//! | RAM with a registered read (custom Verilog leaf): the segment queues' words | `block_ram.rs` | 1 (read) |
//! | segment queues of every axis: one RAM, a push and a pop counter per axis | `seg_queue.rs` | 1 (head read), 1 (push, pop) |
//! | FIFO in LUT RAM (period FIFOs), show-ahead | `ram_fifo.rs` | 0 (head) |
//! | pulse stage: the STEP high time of every period entry, from the output timing | `pulse_stage.rs` | 2 cycles |
//! | step generator, and the FIFO plus generator (`StepAxis`) | `step_gen.rs` | edges at release + E_i |
//! | the axes' back ends: pulse stage, K `StepAxis`, synchronised start, K-bit flags | `axis_bank.rs` | entry to FIFO 2 cycles |
//! | per-axis scheduler context, in registers | `context.rs` | 1 cycle (write) |
//! | synchronised start of masked axes | `sync_start.rs` | `go` 2 cycles, `failed` 1 |
//! | K-bit bus assembly and bit selection | `bit_insert.rs` | 0 |
//! | the TDM core: contexts, step axes, shared units, scheduler | `core.rs` | `t_calc_sqrt(R)`, `t_setup(R, _)` |
//! | the non-TDM baseline: K one-axis cores | `baseline.rs` | as the core |
//! | 2-FF bit synchroniser and 4-deep Gray-pointer async FIFO | `cdc.rs` | 2 edges / 2–3 edges |
//! | EXMC/FSMC async SRAM slave, 16-bit | `exmc.rs` | write commits ≤ 4 bus clocks after NWE rises; read data ≤ 4 after NOE falls |
//! | EXMC master of the other buses' front ends: one access at the minimum MCU timing | `exmc_master.rs` | `done` 4 (write) / 6 (read) bus clocks after the request |
//! | SPI front end, modes 0 and 3 (`--bus spi`) | `spi_front.rs` | MISO 3 bus clocks after SCK rises |
//! | Wishbone B4 classic front end, 32-bit (`--bus wb`) | `wb_front.rs` | ACK 5 (write) / 7 (read) bus clocks after STB |
//! | AXI4-Lite front end, 32-bit (`--bus axil`) | `axil_front.rs` | BVALID 6 / RVALID 8 bus clocks after the handshake |
//! | status handshake, core clock to bus clock, one axis per copy | `status_sync.rs` | ~3 + 3 cycles per axis |
//! | push check: every command to the core, a push validated with the model's rules (bus clock) | `push_check.rs` | 4 cycles |
//! | register file: decoder of the register table, staging, mirror, events, commands | `regfile.rs` | 0 (read), 1 (write) |
//! | identity registers (ID_*), constants of the export | `id_regs.rs` | 0 (read) |
//! | output timing registers (STEP_HIGH … DIR_HOLD), the minima and their check | `timing_regs.rs` | 0 (read), 1 (write), `timing_ok` 3 |
//! | interrupt flags, masks, QLOW_LEVEL and the irq line | `irq_regs.rs` | 0 (read), 1 (write), `irq` 2 |
//! | one machine input: synchroniser, polarity, filter | `input_filter.rs` | 2 + n samples (pin to level) |
//! | machine I/O and safety: input filters, e-stop latch, watchdog, hard-stop request, driver enables, latch strobes | `machine_io.rs` | as its filters; `hard_stop` 3 + n ticks from the e-stop pin |
//! | encoder registers (bus clock) and their crossings: config, commands, ENC_FAIL, the window of one axis | `enc_regs.rs` | commands 3–4 clk; window copies every K·(3 clk + 3 bus clocks) |
//! | the whole IP core, `tdm_stepper` (and its baseline form) | `top.rs` | — |
//!
//! Timing conventions, latencies, sizes and what each test proves: docs/architecture.md.

/// `connect_ports()` of a core: `TdmCore` and `Baseline` have the same inputs.
macro_rules! core_connect_ports {
    () => {
        /// Marks the inputs as driven from outside and connects the block, for
        /// simulating the core on its own (tests, benches).
        pub fn connect_ports(&mut self) {
            self.clock.connect();
            self.reset.connect();
            self.cmd_valid.connect();
            self.cmd_axis.connect();
            self.cmd_v0.connect();
            self.cmd_t.connect();
            self.cmd_steps.connect();
            self.cmd_extra.connect();
            self.start.connect();
            self.start_mask.connect();
            self.sel_axis.connect();
            self.ext_go.connect();
            self.abort.connect();
            self.stop_axes.connect();
            self.cstop_axes.connect();
            self.decel.connect();
            self.high_min.connect();
            self.low_min.connect();
            self.home_latch.connect();
            self.probe_latch.connect();
            self.lsel_axis.connect();
            self.epos_axis.connect();
            self.connect_all();
        }
    };
}

/// A rust-hdl value of up to 128 bits as u128 (for simulations and tests that
/// inspect wide signals or memory words).
pub fn bits_to_u128<const N: usize>(x: rust_hdl::prelude::Bits<N>) -> u128 {
    let d = num_bigint::BigUint::from(x).to_u64_digits();
    d.first().copied().unwrap_or(0) as u128 | (d.get(1).copied().unwrap_or(0) as u128) << 64
}

/// A u128 as a rust-hdl value of up to 128 bits (the inverse of [`bits_to_u128`]).
pub fn u128_to_bits<const N: usize>(x: u128) -> rust_hdl::prelude::Bits<N> {
    num_bigint::BigUint::from(x).into()
}

pub mod axis_bank;
pub mod axis_view;
pub mod axil_front;
pub mod baseline;
pub mod bit_insert;
pub mod block_ram;
pub mod cdc;
pub mod context;
pub mod context_ram;
pub mod core;
pub mod divider;
pub mod enc_bank;
pub mod enc_decoder;
pub mod enc_extend;
pub mod enc_regs;
pub mod exmc;
pub mod exmc_master;
pub mod follow_err;
pub mod id_regs;
pub mod input_filter;
pub mod io_regs;
pub mod irq_regs;
pub mod iterate;
pub mod mul_seq;
pub mod mul_wide;
pub mod lut_ram;
pub mod machine_io;
pub mod pulse_stage;
pub mod poly_check;
pub mod poly_lane;
pub mod poly_regs;
pub mod poly_setup;
pub mod poly_step;
pub mod poly_unit;
pub mod push_check;
pub mod push_guard;
pub mod ram_fifo;
pub mod regfile;
pub mod root;
pub mod sched_states;
pub mod seg_queue;
pub mod spi_front;
pub mod setup_path;
pub mod status_sync;
pub mod step_gen;
pub mod wb_front;
pub mod stop_ramp;
pub mod stop_regs;
pub mod sync_start;
pub mod timing_regs;
pub mod top;
