//! Small wiring blocks for buses: a bit or field placed or picked at a constant offset
//! and a sign extension, each a block because the expression inline would hit one of
//! rust-hdl's generator traps (named at each block).
//!
//! `BitInsert` builds a K-bit bus from one bit per axis without a combinational self-reference:
//! `bus_out = bus_in` with bit `index` replaced by `value`. Chained (bus_in of element i
//! from bus_out of element i − 1), K of them assemble a bus. Assigning
//! `x = x.replace_bit(i, ..)` in a loop instead would read `x` while writing it, which
//! rust-hdl simulation and the exported Verilog evaluate differently.

use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct BitInsert<const K: usize> {
    pub bus_in: Signal<In, Bits<K>>,
    pub value: Signal<In, Bit>,
    pub bus_out: Signal<Out, Bits<K>>,
    index: Constant<Bits<8>>,
}

impl<const K: usize> BitInsert<K> {
    pub fn new(index: usize) -> Self {
        assert!(index < K && K <= 255);
        BitInsert {
            bus_in: Default::default(),
            value: Default::default(),
            bus_out: Default::default(),
            index: Constant::new((index as u64).into()),
        }
    }
}

impl<const K: usize> Logic for BitInsert<K> {
    #[hdl_gen]
    fn update(&mut self) {
        self.bus_out.next = self.bus_in.val().replace_bit(self.index.val().index(), self.value.val());
    }
}

/// Picks bit `index` of a K-bit bus as an OR-reduction of the bus under a one-hot
/// constant mask. `bus[i]` would be illegal Verilog when K = 1: rust-hdl declares a
/// 1-bit signal without a range.
#[derive(LogicBlock)]
pub struct BitPick<const K: usize> {
    pub bus: Signal<In, Bits<K>>,
    pub value: Signal<Out, Bit>,
    mask: Constant<Bits<K>>,
}

impl<const K: usize> BitPick<K> {
    pub fn new(index: usize) -> Self {
        assert!(index < K && K <= 64);
        BitPick { bus: Default::default(), value: Default::default(), mask: Constant::new((1u64 << index).into()) }
    }
}

impl<const K: usize> Logic for BitPick<K> {
    #[hdl_gen]
    fn update(&mut self) {
        self.value.next = (self.bus.val() & self.mask.val()).any();
    }
}

/// Places a W-bit field at bit `offset` of an N-bit bus: `bus_out = bus_in | value <<
/// offset` (the field's bits of `bus_in` must be 0). Chained like [`BitInsert`], K of
/// them pack one field per axis at a power-of-two stride, so that the parent can pick
/// an axis's field by shifting the bus right by `axis << log2(stride)`: yosys makes
/// that a tree of multiplexers on the axis's bits (a quarter of a LUT6 per bit and
/// axis), where a chain of `if axis == i` assignments is a priority chain (about half).
#[derive(LogicBlock)]
pub struct FieldPlace<const W: usize, const N: usize> {
    pub bus_in: Signal<In, Bits<N>>,
    pub value: Signal<In, Bits<W>>,
    pub bus_out: Signal<Out, Bits<N>>,
    offset: Constant<Bits<16>>,
}

impl<const W: usize, const N: usize> FieldPlace<W, N> {
    pub fn new(offset: usize) -> Self {
        assert!(offset + W <= N && N < 1 << 16);
        FieldPlace {
            bus_in: Default::default(),
            value: Default::default(),
            bus_out: Default::default(),
            offset: Constant::new((offset as u64).into()),
        }
    }
}

impl<const W: usize, const N: usize> Logic for FieldPlace<W, N> {
    #[hdl_gen]
    fn update(&mut self) {
        self.bus_out.next = self.bus_in.val() | (bit_cast::<N, W>(self.value.val()) << self.offset.val());
    }
}

/// Picks the W-bit field at bit `offset` of an N-bit bus (a constant offset: wires).
/// `bus.get_bits::<W>(offset)` with a loop's index as the offset would be one of the
/// generator's traps (the index is not a Verilog constant there); this block takes it
/// as a constant.
#[derive(LogicBlock)]
pub struct FieldPick<const W: usize, const N: usize> {
    pub bus: Signal<In, Bits<N>>,
    pub value: Signal<Out, Bits<W>>,
    shifted: Signal<Local, Bits<N>>,
    offset: Constant<Bits<16>>,
}

impl<const W: usize, const N: usize> FieldPick<W, N> {
    pub fn new(offset: usize) -> Self {
        assert!(offset + W <= N && N < 1 << 16);
        FieldPick { bus: Default::default(), value: Default::default(), shifted: Default::default(), offset: Constant::new((offset as u64).into()) }
    }
}

impl<const W: usize, const N: usize> Logic for FieldPick<W, N> {
    #[hdl_gen]
    fn update(&mut self) {
        self.shifted.next = self.bus.val() >> self.offset.val();
        self.value.next = self.shifted.val().get_bits::<W>(0);
    }
}

/// Sign-extends an N-bit value to M bits (M ≤ 64): the M − N high bits copy bit N − 1.
/// Combinational, no latency. Its sign is an OR-reduction under a one-hot mask, not
/// `get_bit(N - 1)`: an expression of a const generic in a bit index is not exported.
#[derive(LogicBlock)]
pub struct SignExtend<const N: usize, const M: usize> {
    pub value: Signal<In, Bits<N>>,
    pub wide: Signal<Out, Bits<M>>,
    sign: Constant<Bits<N>>,
    hi: Constant<Bits<M>>,
}

impl<const N: usize, const M: usize> SignExtend<N, M> {
    pub fn new() -> Self {
        assert!(0 < N && N < M && M <= 64);
        let mask = if M == 64 { u64::MAX } else { (1u64 << M) - 1 };
        SignExtend {
            value: Default::default(),
            wide: Default::default(),
            sign: Constant::new((1u64 << (N - 1)).into()),
            hi: Constant::new(((u64::MAX << N) & mask).into()),
        }
    }
}

impl<const N: usize, const M: usize> Default for SignExtend<N, M> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize, const M: usize> Logic for SignExtend<N, M> {
    #[hdl_gen]
    fn update(&mut self) {
        self.wide.next = bit_cast::<M, N>(self.value.val());
        if (self.value.val() & self.sign.val()).any() {
            self.wide.next = bit_cast::<M, N>(self.value.val()) | self.hi.val();
        }
    }
}
