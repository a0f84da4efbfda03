//! Distributed (LUT) RAM: `2^N` words of `W` bits, one synchronous write port and
//! one asynchronous read port. A leaf block with hand-written Verilog (rust-hdl-widgets
//! `RAM` reads synchronously, which a show-ahead FIFO cannot use), modelled in
//! `update()`.
//!
//! Ports: at a rising `clock` edge with `we` high, `wdata` is written at `waddr`.
//! `rdata` is the word at `raddr`, combinationally (latency 0); a word written at an
//! edge is seen from that edge on. No reset: the contents start undefined in the
//! Verilog (0 in the simulation), and the users ([`super::ram_fifo::RamFifo`]) never
//! read a word before writing it.
//!
//! yosys maps it to LUT RAM: on xc7 a 32-word memory is RAM32M cells (6 bits per 4
//! LUTs), on ECP5 DPR16X4 cells; memory bits cost LUTs there, not flip-flops and
//! multiplexers.

use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct LutRam<const W: usize, const N: usize> {
    pub clock: Signal<In, Clock>,
    pub we: Signal<In, Bit>,
    pub waddr: Signal<In, Bits<N>>,
    pub wdata: Signal<In, Bits<W>>,
    pub raddr: Signal<In, Bits<N>>,
    pub rdata: Signal<Out, Bits<W>>,
    _mem: Box<Vec<Bits<W>>>,
}

impl<const W: usize, const N: usize> Default for LutRam<W, N> {
    fn default() -> Self {
        assert!((1..=8).contains(&N), "LutRam<{W}, {N}>: 2..=256 words");
        LutRam {
            clock: Default::default(),
            we: Default::default(),
            waddr: Default::default(),
            wdata: Default::default(),
            raddr: Default::default(),
            rdata: Default::default(),
            _mem: Box::new(vec![Bits::<W>::default(); 1 << N]),
        }
    }
}

impl<const W: usize, const N: usize> LutRam<W, N> {
    /// The word at `addr` as the simulation holds it (for tests that inspect state).
    pub fn word(&self, addr: usize) -> Bits<W> {
        self._mem[addr]
    }
}

impl<const W: usize, const N: usize> Logic for LutRam<W, N> {
    fn update(&mut self) {
        if self.clock.pos_edge() && self.we.val() {
            self._mem[self.waddr.val().index()] = self.wdata.val();
        }
        self.rdata.next = self._mem[self.raddr.val().index()];
    }

    fn connect(&mut self) {
        self.rdata.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
reg [{msb}:0] mem [0:{last}];
always @(posedge clock) begin
   if (we) mem[waddr] <= wdata;
end
// A continuous assignment follows writes to the selected word in every simulator
// (Icarus leaves memories out of an always @(*) sensitivity list).
wire [{msb}:0] rword = mem[raddr];
always @(*) rdata = rword;",
            msb = W - 1,
            last = (1usize << N) - 1,
        ))
    }
}
