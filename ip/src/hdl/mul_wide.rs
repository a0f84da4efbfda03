//! Wide unsigned multiplier: a leaf block with hand-written Verilog.
//!
//! rust-hdl 0.46 only multiplies 16×16 bits, so this leaf's `hdl()`
//! returns `p = a * b` as custom Verilog, and its `update()` models the same product
//! in u64. `A + B ≤ P ≤ 64` is checked at construction, so the product never wraps.
//! Combinational; [`MulReg`] puts the register behind it (latency 1, which lets
//! synthesis map it onto DSP blocks with their output register).

use rust_hdl::prelude::*;

/// p = a × b, combinational.
#[derive(LogicBlock)]
pub struct MulWide<const A: usize, const B: usize, const P: usize> {
    pub a: Signal<In, Bits<A>>,
    pub b: Signal<In, Bits<B>>,
    pub p: Signal<Out, Bits<P>>,
}

impl<const A: usize, const B: usize, const P: usize> Default for MulWide<A, B, P> {
    fn default() -> Self {
        assert!(A + B <= P && P <= 64, "MulWide<{A}, {B}, {P}>: need A + B <= P <= 64");
        MulWide { a: Default::default(), b: Default::default(), p: Default::default() }
    }
}

impl<const A: usize, const B: usize, const P: usize> Logic for MulWide<A, B, P> {
    fn update(&mut self) {
        let product = self.a.val().to_u64() * self.b.val().to_u64();
        self.p.next = Bits::<P>::from(product);
    }

    fn connect(&mut self) {
        self.p.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Custom("always @(*) p = a * b;".into())
    }
}

/// Registered multiplier: `p` is a × b of the previous clock edge. Latency 1 cycle.
#[derive(LogicBlock)]
pub struct MulReg<const A: usize, const B: usize, const P: usize> {
    pub clock: Signal<In, Clock>,
    pub a: Signal<In, Bits<A>>,
    pub b: Signal<In, Bits<B>>,
    pub p: Signal<Out, Bits<P>>,
    mul: MulWide<A, B, P>,
    product: DFF<Bits<P>>,
}

/// Cycles from `a`, `b` to `p`.
pub const MUL_REG_LATENCY: usize = 1;

impl<const A: usize, const B: usize, const P: usize> Default for MulReg<A, B, P> {
    fn default() -> Self {
        MulReg {
            clock: Default::default(),
            a: Default::default(),
            b: Default::default(),
            p: Default::default(),
            mul: Default::default(),
            product: Default::default(),
        }
    }
}

impl<const A: usize, const B: usize, const P: usize> Logic for MulReg<A, B, P> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, product);
        self.mul.a.next = self.a.val();
        self.mul.b.next = self.b.val();
        self.product.d.next = self.mul.p.val();
        self.p.next = self.product.q.val();
    }
}
