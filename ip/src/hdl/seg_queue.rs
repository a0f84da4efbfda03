//! The segment queues of every axis: one RAM, K pairs of free-running pointers.
//!
//! Axis i's queue is words i·QDEPTH .. (i + 1)·QDEPTH of one [`BlockRam`] (96-bit
//! segments: v0 in bits 31..0, T in 63..32, steps in 95..64). Per axis the block keeps
//! two 8-bit counters and two flags (`full`, `nonempty`, below): `wr` counts the
//! segments pushed and `rd` the segments taken (popped by the scheduler, or flushed
//! by an abort). The queue holds
//! `wr − rd` segments (at most QDEPTH ≤ 32, so 8 bits never wrap into ambiguity), its
//! head is at `rd mod QDEPTH` and its tail at `wr mod QDEPTH`, and `rd` is the
//! wrapping taken counter the register file reports: no count or taken register of
//! its own.
//!
//! Ports and latency:
//! * **Push** (`push_valid`, `push_axis`, `push_word`): written at the clock edge when
//!   the axis is < K and its queue is not full. `push_ready` says the addressed
//!   axis's queue is not full, combinationally from `push_axis` (1 for an axis ≥ K,
//!   whose push is dropped; the core flags it): one registered flag per axis, `full`,
//!   through a K:1 multiplexer of single bits. The flag is exact: an edge that pushes
//!   into a queue one short of full sets it (that test, an XOR and a compare of
//!   wr + 1's and rd's low log2(QDEPTH) + 1 bits, comes from the counters alone), and a
//!   pop, an abort or a reset clears it. So no counter multiplexer or compare lies
//!   between `push_axis` and the write enables (on ECP5 at K = 16 they were the
//!   clock's critical path). Visible to `nonempty` and `sel_level` the cycle after
//!   the edge.
//! * **Head** (`axis`, `head`): `head` is the head of queue `axis` as it was at the
//!   last clock edge (the RAM's registered read; the read address follows `axis` and
//!   the pointers with no register of its own). The scheduler sets `axis` in the
//!   cycle before it reads the head.
//! * **Pop** (`pop`, one cycle): takes the head of queue `axis` at the clock edge, if
//!   the queue is not empty. A push to the same axis in that cycle is allowed.
//! * **Flush** (`flush`, one cycle): queue `axis` empties at the clock edge (`rd` takes
//!   `wr`, or `wr + 1` with a push to it in that cycle, which is written and counted
//!   taken with the rest). The per-axis stop; tied to 0 it costs nothing.
//! * **Abort** (one cycle): every queue empties at the clock edge (`rd` takes `wr`, so
//!   the taken counter counts the flushed segments), and a push in that cycle is
//!   dropped. **Reset** (synchronous) zeroes both counters and clears both flags of
//!   every axis.
//! * **Status**: `nonempty` (bit i: axis i has a queued segment) is a flag per axis,
//!   exact like `full`: a push sets it, a pop that leaves the queue empty (it held
//!   one, `rd + 1 ≡ wr` in the same low bits; no push to it in that cycle) clears it,
//!   and so do an abort and a reset. So no counter compare lies between the queue and
//!   an axis's `more` (the step generator's underrun test, through the scheduler's
//!   `pending`: on ECP5 at K = 8 and 16 that compare was on the clock's critical
//!   path). For axis `sel_axis`, its level (`wr − rd`) and taken counter (`rd`), from
//!   the counters through multiplexers, no register of their own.
//! * **The RAM's ports** (`ram_we`, `ram_waddr`, `ram_raddr`): a second RAM written and
//!   read with them holds more of each segment at the same entry, with the same
//!   latency as `head` (the S-curve option's fields). Wires only: unused, they cost
//!   nothing.

use super::bit_insert::BitInsert;
use super::block_ram::BlockRam;
use rust_hdl::prelude::*;

/// Width of a queued segment: v0 (31..0), T (63..32), steps (95..64).
pub const SEGMENT_BITS: usize = 96;
/// Deepest segment queue (a power of two: axis i's queue starts at i·QDEPTH).
pub const MAX_QUEUE_DEPTH: usize = 32;
/// Most axes the RAM's address reaches.
pub const MAX_QUEUE_AXES: usize = 16;
/// Address bits of the segment RAM: up to 16 axes × 32 entries.
pub const SEG_ADDR_BITS: usize = 9;
const _: () = assert!(MAX_QUEUE_AXES * MAX_QUEUE_DEPTH == 1 << SEG_ADDR_BITS);

#[derive(LogicBlock)]
pub struct SegQueue<const K: usize, const QDEPTH: usize> {
    pub clock: Signal<In, Clock>,
    pub flush: Signal<In, Bit>,
    pub reset: Signal<In, Bit>,
    pub abort: Signal<In, Bit>,
    pub push_valid: Signal<In, Bit>,
    pub push_axis: Signal<In, Bits<8>>,
    pub push_word: Signal<In, Bits<SEGMENT_BITS>>,
    pub push_ready: Signal<Out, Bit>,
    pub axis: Signal<In, Bits<8>>,
    pub pop: Signal<In, Bit>,
    pub head: Signal<Out, Bits<SEGMENT_BITS>>,
    pub nonempty: Signal<Out, Bits<K>>,
    pub sel_axis: Signal<In, Bits<8>>,
    pub sel_level: Signal<Out, Bits<8>>,
    pub sel_taken: Signal<Out, Bits<8>>,
    /// The RAM's write enable and addresses, for a RAM beside it that holds more of
    /// each segment at the same addresses (the S-curve option's fields).
    pub ram_we: Signal<Out, Bit>,
    pub ram_waddr: Signal<Out, Bits<SEG_ADDR_BITS>>,
    pub ram_raddr: Signal<Out, Bits<SEG_ADDR_BITS>>,
    ram: BlockRam<SEGMENT_BITS, SEG_ADDR_BITS>,
    wr: [DFF<Bits<8>>; K],
    rd: [DFF<Bits<8>>; K],
    /// Axis i's queue holds QDEPTH segments (wr − rd = QDEPTH), registered.
    full: [DFF<Bit>; K],
    /// Axis i's queue holds a segment (wr ≠ rd), registered.
    ne: [DFF<Bit>; K],
    ne_bus: [BitInsert<K>; K],
    base: [Constant<Bits<SEG_ADDR_BITS>>; K],
    c_mask: Constant<Bits<SEG_ADDR_BITS>>,
    c_depth: Constant<Bits<8>>,
    /// 2·QDEPTH − 1: the counters' bits that tell a full queue from an empty one.
    c_wrap: Constant<Bits<8>>,
    // The pushed axis's pointers and base, the popped (read) axis's, the selected one's.
    p_wr: Signal<Local, Bits<8>>,
    p_base: Signal<Local, Bits<SEG_ADDR_BITS>>,
    p_full: Signal<Local, Bit>,
    r_rd: Signal<Local, Bits<8>>,
    r_base: Signal<Local, Bits<SEG_ADDR_BITS>>,
    s_wr: Signal<Local, Bits<8>>,
    s_rd: Signal<Local, Bits<8>>,
}

impl<const K: usize, const QDEPTH: usize> SegQueue<K, QDEPTH> {
    pub fn new() -> Self {
        assert!((1..=MAX_QUEUE_AXES).contains(&K), "SegQueue: K = {K} outside 1..={MAX_QUEUE_AXES}");
        assert!(
            QDEPTH.is_power_of_two() && (2..=MAX_QUEUE_DEPTH).contains(&QDEPTH),
            "SegQueue: queue depth {QDEPTH} is not a power of two in 2..={MAX_QUEUE_DEPTH}"
        );
        SegQueue {
            clock: Default::default(),
            flush: Default::default(),
            reset: Default::default(),
            abort: Default::default(),
            push_valid: Default::default(),
            push_axis: Default::default(),
            push_word: Default::default(),
            push_ready: Default::default(),
            axis: Default::default(),
            pop: Default::default(),
            head: Default::default(),
            nonempty: Default::default(),
            sel_axis: Default::default(),
            sel_level: Default::default(),
            sel_taken: Default::default(),
            ram_we: Default::default(),
            ram_waddr: Default::default(),
            ram_raddr: Default::default(),
            ram: BlockRam::new(K * QDEPTH),
            wr: std::array::from_fn(|_| Default::default()),
            rd: std::array::from_fn(|_| Default::default()),
            full: std::array::from_fn(|_| Default::default()),
            ne: std::array::from_fn(|_| Default::default()),
            ne_bus: std::array::from_fn(BitInsert::new),
            base: std::array::from_fn(|i| Constant::new(((i * QDEPTH) as u64).into())),
            c_mask: Constant::new(((QDEPTH - 1) as u64).into()),
            c_depth: Constant::new((QDEPTH as u64).into()),
            c_wrap: Constant::new(((2 * QDEPTH - 1) as u64).into()),
            p_wr: Default::default(),
            p_base: Default::default(),
            p_full: Default::default(),
            r_rd: Default::default(),
            r_base: Default::default(),
            s_wr: Default::default(),
            s_rd: Default::default(),
        }
    }
}

impl<const K: usize, const QDEPTH: usize> Default for SegQueue<K, QDEPTH> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const K: usize, const QDEPTH: usize> Logic for SegQueue<K, QDEPTH> {
    #[hdl_gen]
    fn update(&mut self) {
        // The three axes' pointers through K:1 multiplexers (an axis ≥ K selects zeros:
        // an empty queue at the base of axis 0, which nothing writes or pops).
        self.p_wr.next = 0.into();
        self.p_full.next = false;
        self.p_base.next = 0.into();
        self.r_rd.next = 0.into();
        self.r_base.next = 0.into();
        self.s_wr.next = 0.into();
        self.s_rd.next = 0.into();
        for i in 0..K {
            if self.push_axis.val().index() == i {
                self.p_wr.next = self.wr[i].q.val();
                self.p_full.next = self.full[i].q.val();
                self.p_base.next = self.base[i].val();
            }
            if self.axis.val().index() == i {
                self.r_rd.next = self.rd[i].q.val();
                self.r_base.next = self.base[i].val();
            }
            if self.sel_axis.val().index() == i {
                self.s_wr.next = self.wr[i].q.val();
                self.s_rd.next = self.rd[i].q.val();
            }
        }
        self.push_ready.next = !self.p_full.val();
        self.sel_level.next = self.s_wr.val() - self.s_rd.val();
        self.sel_taken.next = self.s_rd.val();

        self.ram.clock.next = self.clock.val();
        self.ram.we.next = false;
        self.ram.waddr.next = self.p_base.val() | (bit_cast::<SEG_ADDR_BITS, 8>(self.p_wr.val()) & self.c_mask.val());
        self.ram.wdata.next = self.push_word.val();
        self.ram.raddr.next = self.r_base.val() | (bit_cast::<SEG_ADDR_BITS, 8>(self.r_rd.val()) & self.c_mask.val());
        self.head.next = self.ram.rdata.val();
        self.ram_waddr.next = self.ram.waddr.val();
        self.ram_raddr.next = self.ram.raddr.val();

        for i in 0..K {
            self.wr[i].clock.next = self.clock.val();
            self.rd[i].clock.next = self.clock.val();
            self.full[i].clock.next = self.clock.val();
            self.ne[i].clock.next = self.clock.val();
            self.ne[i].d.next = self.ne[i].q.val();
            self.wr[i].d.next = self.wr[i].q.val();
            self.rd[i].d.next = self.rd[i].q.val();
            self.full[i].d.next = self.full[i].q.val();
            if self.push_valid.val() & (self.push_axis.val().index() == i) & !self.full[i].q.val() {
                self.ram.we.next = true;
                self.wr[i].d.next = self.wr[i].q.val() + 1;
                // Full after it if it was one short: wr + 1 − rd = QDEPTH. The level
                // never exceeds QDEPTH, so that is wr + 1 ≡ rd + QDEPTH (mod 2·QDEPTH):
                // the low bits equal and the next one different, an XOR and a compare
                // of registers, no subtraction.
                self.full[i].d.next =
                    (((self.wr[i].q.val() + 1) ^ self.rd[i].q.val()) & self.c_wrap.val()) == self.c_depth.val();
            }
            // A pop leaves the queue short of full whether or not a push comes with it
            // (a push to a full queue is refused, and one to a shorter queue refills it).
            if self.pop.val() & (self.axis.val().index() == i) & (self.wr[i].q.val() != self.rd[i].q.val()) {
                self.rd[i].d.next = self.rd[i].q.val() + 1;
                self.full[i].d.next = false;
                // Empty after it if it held one: rd + 1 ≡ wr (mod 2·QDEPTH), as for
                // `full` (a push in the same cycle refills it, below).
                self.ne[i].d.next = (((self.rd[i].q.val() + 1) ^ self.wr[i].q.val()) & self.c_wrap.val()) != 0;
            }
            if self.push_valid.val() & (self.push_axis.val().index() == i) & !self.full[i].q.val() {
                self.ne[i].d.next = true;
            }
            if self.flush.val() & (self.axis.val().index() == i) {
                self.rd[i].d.next = self.wr[i].q.val();
                if self.push_valid.val() & (self.push_axis.val().index() == i) & !self.full[i].q.val() {
                    self.rd[i].d.next = self.wr[i].q.val() + 1;
                }
                self.full[i].d.next = false;
                self.ne[i].d.next = false;
            }
            if self.abort.val() {
                self.wr[i].d.next = self.wr[i].q.val();
                self.rd[i].d.next = self.wr[i].q.val();
                self.full[i].d.next = false;
                self.ne[i].d.next = false;
            }
            if self.reset.val() {
                self.wr[i].d.next = 0.into();
                self.rd[i].d.next = 0.into();
                self.full[i].d.next = false;
                self.ne[i].d.next = false;
            }
            self.ne_bus[i].value.next = self.ne[i].q.val();
        }
        self.ne_bus[0].bus_in.next = 0.into();
        for i in 1..K {
            self.ne_bus[i].bus_in.next = self.ne_bus[i - 1].bus_out.val();
        }
        // The last element of the chain holds the whole bus (last assignment wins).
        for i in 0..K {
            self.nonempty.next = self.ne_bus[i].bus_out.val();
        }
        self.ram_we.next = self.ram.we.val();
    }
}
