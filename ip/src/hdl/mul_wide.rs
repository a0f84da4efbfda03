//! Wide unsigned multiplier for the setup's 32×32 products (v0·T, T·RMAX, T²): a leaf
//! block with hand-written Verilog, since rust-hdl 0.46 only multiplies 16×16 bits.
//! Its `update()` models the same pipeline in u64. `A + B ≤ P ≤ 64` is checked at
//! construction, so the product never wraps.

use rust_hdl::prelude::*;

/// Pipelined multiplier: `p` is a × b of two clock edges before (latency 2, a new
/// product every cycle). Stage 1 registers the four 16-bit partial products (each one
/// DSP multiplier: xc7 DSP48E1, ECP5 MULT18X18D); stage 2 registers their sum. A
/// single-cycle 32×32 product chains the DSPs with a LUT adder tree, which was the
/// core's critical path on ECP5 (23.6 ns); split, each stage is one multiplier or
/// one two-level add. Custom Verilog, modelled in `update()`; needs 17 ≤ A, B ≤ 32.
#[derive(LogicBlock)]
pub struct MulReg<const A: usize, const B: usize, const P: usize> {
    pub clock: Signal<In, Clock>,
    pub a: Signal<In, Bits<A>>,
    pub b: Signal<In, Bits<B>>,
    pub p: Signal<Out, Bits<P>>,
    /// Stage 1: lo·lo, lo(a)·hi(b), hi(a)·lo(b), hi·hi.
    _pp: [u64; 4],
}

/// Cycles from `a`, `b` to `p`.
pub use crate::latency::MUL_REG_LATENCY;

impl<const A: usize, const B: usize, const P: usize> Default for MulReg<A, B, P> {
    fn default() -> Self {
        assert!(
            (17..=32).contains(&A) && (17..=32).contains(&B) && A + B <= P && P <= 64,
            "MulReg<{A}, {B}, {P}>: need 17 <= A, B <= 32 and A + B <= P <= 64"
        );
        MulReg { clock: Default::default(), a: Default::default(), b: Default::default(), p: Default::default(), _pp: [0; 4] }
    }
}

impl<const A: usize, const B: usize, const P: usize> Logic for MulReg<A, B, P> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            let [ll, lh, hl, hh] = self._pp;
            self.p.next = Bits::<P>::from((hh << 32) + ll + ((lh + hl) << 16));
            let (a, b) = (self.a.val().to_u64(), self.b.val().to_u64());
            self._pp = [(a & 0xffff) * (b & 0xffff), (a & 0xffff) * (b >> 16), (a >> 16) * (b & 0xffff), (a >> 16) * (b >> 16)];
        }
    }

    fn connect(&mut self) {
        self.p.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
reg [31:0] pp_ll;
reg [{lh}:0] pp_lh;
reg [{hl}:0] pp_hl;
reg [{hh}:0] pp_hh;
wire [{mid}:0] mid = pp_lh + pp_hl;
always @(posedge clock) begin
   pp_ll <= a[15:0] * b[15:0];
   pp_lh <= a[15:0] * b[{bm}:16];
   pp_hl <= a[{am}:16] * b[15:0];
   pp_hh <= a[{am}:16] * b[{bm}:16];
   p <= {{pp_hh, pp_ll}} + ({{{pz}'d0, mid}} << 16);
end",
            lh = 16 + (B - 16) - 1,
            hl = (A - 16) + 16 - 1,
            hh = (A - 16) + (B - 16) - 1,
            mid = 32,
            am = A - 1,
            bm = B - 1,
            pz = P - 33,
        ))
    }
}
