//! Simple dual-port RAM with a registered read: `words` words of `W` bits (`words` ≤
//! 2^N, chosen at construction), one synchronous write port and one synchronous read
//! port. A leaf block with hand-written Verilog, modelled in `update()`.
//!
//! Ports: at a rising `clock` edge with `we` high, `wdata` is written at `waddr`; at
//! every rising edge `rdata` takes the word at `raddr` as it was before that edge's
//! write (read-first; latency 1). No reset: the contents start undefined in the
//! Verilog (0 in the simulation), and the user (the core's segment queues) never reads
//! a word it has not written. An address ≥ `words` is never presented.
//!
//! The registered read is the shape of FPGA block RAM (xc7 RAMB18/36, ECP5 DP16KD),
//! and yosys maps it there or to LUT RAM with the output register, whichever the
//! memory's size favours; either way the words cost memory bits, not flip-flops and a
//! `words`:1 multiplexer.

use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct BlockRam<const W: usize, const N: usize> {
    pub clock: Signal<In, Clock>,
    pub we: Signal<In, Bit>,
    pub waddr: Signal<In, Bits<N>>,
    pub wdata: Signal<In, Bits<W>>,
    pub raddr: Signal<In, Bits<N>>,
    pub rdata: Signal<Out, Bits<W>>,
    _mem: Box<Vec<Bits<W>>>,
}

impl<const W: usize, const N: usize> BlockRam<W, N> {
    /// A RAM of `words` words (1..=2^N).
    pub fn new(words: usize) -> Self {
        assert!(N <= 16 && (1..=1usize << N).contains(&words), "BlockRam<{W}, {N}>: {words} words");
        BlockRam {
            clock: Default::default(),
            we: Default::default(),
            waddr: Default::default(),
            wdata: Default::default(),
            raddr: Default::default(),
            rdata: Default::default(),
            _mem: Box::new(vec![Bits::<W>::default(); words]),
        }
    }

    /// Number of words.
    pub fn words(&self) -> usize {
        self._mem.len()
    }

    /// The word at `addr` as the simulation holds it (for tests that inspect state).
    pub fn word(&self, addr: usize) -> Bits<W> {
        self._mem[addr]
    }
}

impl<const W: usize, const N: usize> Logic for BlockRam<W, N> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            let r = self.raddr.val().index();
            self.rdata.next = if r < self._mem.len() { self._mem[r] } else { Bits::<W>::default() };
            if self.we.val() {
                let w = self.waddr.val().index();
                if w < self._mem.len() {
                    self._mem[w] = self.wdata.val();
                }
            }
        }
    }

    fn connect(&mut self) {
        self.rdata.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
reg [{msb}:0] mem [0:{last}];
// The address bits above the last word are 0 by contract; this reads them, so that
// lint does not flag them (the wire drives nothing and synthesis drops it).
wire unused_addr_bits = ^{{waddr, raddr}};
always @(posedge clock) begin
   if (we) mem[waddr] <= wdata;
   rdata <= mem[raddr];
end",
            msb = W - 1,
            last = self._mem.len() - 1,
        ))
    }
}
