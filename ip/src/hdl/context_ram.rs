//! The scheduler's context memory: the wide per-axis fields of every axis's current
//! and next segment, in LUT RAM addressed by `{axis, slot}` (32 words: K ≤ 16).
//!
//! The scheduler works on one axis at a time, so it reads one word (into its working
//! copy, in PICK) and writes one word back (a step's commit into the current slot, a
//! setup's commit into the next slot): one more axis costs two words of memory, not
//! registers behind a K:1 multiplexer. Which slot is current is a per-axis flag
//! ([`super::context::AxisContext`]); promoting the next segment flips it.
//!
//! Ports: at a rising `clock` edge with `we`, the `w_*` fields are written at
//! `waddr`; the `r_*` fields are the word at `raddr`, combinationally (latency 0).
//! No reset: a word is read only after a setup wrote it (the per-axis flags say so).
//!
//! | field | bits | meaning |
//! |---|---|---|
//! | rev | 1 | direction of the segment's steps |
//! | n, i | 32 each | steps in the segment, steps computed so far |
//! | t | 32 | T, ticks |
//! | e | 32 | edge tick of the last computed step (E_i), from the segment start |
//! | p | 64 | P' |
//! | b, a | 100 each | B' and the accumulator C = A − P'² |
//! | uq, ur, uqs, urs | 32 each | uniform path: quotient, remainder and their steps |
//!
//! Five RAMs of at most 128 bits share the addresses (rust-hdl simulates values up
//! to 128 bits fast): 521 bits per word.

use super::bits_to_u128;
use super::lut_ram::LutRam;
use rust_hdl::prelude::*;

/// Address bits: `{axis (4), slot (1)}`.
pub const CTX_ADDR_BITS: usize = 5;
/// Most axes a context memory holds.
pub const CTX_MAX_AXES: usize = 1 << (CTX_ADDR_BITS - 1);

/// One context word, for simulations that inspect the scheduler.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ContextWord {
    pub rev: bool,
    pub n: u32,
    pub i: u32,
    pub t: u32,
    pub e: u32,
    pub p: u64,
    pub b: u128,
    pub a: u128,
    pub uq: u32,
    pub ur: u32,
    pub uqs: u32,
    pub urs: u32,
}

#[derive(LogicBlock, Default)]
pub struct ContextRam {
    pub clock: Signal<In, Clock>,
    pub we: Signal<In, Bit>,
    pub waddr: Signal<In, Bits<CTX_ADDR_BITS>>,
    pub raddr: Signal<In, Bits<CTX_ADDR_BITS>>,
    pub w_rev: Signal<In, Bit>,
    pub w_n: Signal<In, Bits<32>>,
    pub w_i: Signal<In, Bits<32>>,
    pub w_t: Signal<In, Bits<32>>,
    pub w_e: Signal<In, Bits<32>>,
    pub w_p: Signal<In, Bits<64>>,
    pub w_b: Signal<In, Bits<100>>,
    pub w_a: Signal<In, Bits<100>>,
    pub w_uq: Signal<In, Bits<32>>,
    pub w_ur: Signal<In, Bits<32>>,
    pub w_uqs: Signal<In, Bits<32>>,
    pub w_urs: Signal<In, Bits<32>>,
    pub r_rev: Signal<Out, Bit>,
    pub r_n: Signal<Out, Bits<32>>,
    pub r_i: Signal<Out, Bits<32>>,
    pub r_t: Signal<Out, Bits<32>>,
    pub r_e: Signal<Out, Bits<32>>,
    pub r_p: Signal<Out, Bits<64>>,
    pub r_b: Signal<Out, Bits<100>>,
    pub r_a: Signal<Out, Bits<100>>,
    pub r_uq: Signal<Out, Bits<32>>,
    pub r_ur: Signal<Out, Bits<32>>,
    pub r_uqs: Signal<Out, Bits<32>>,
    pub r_urs: Signal<Out, Bits<32>>,
    ram_b: LutRam<100, CTX_ADDR_BITS>,
    ram_a: LutRam<100, CTX_ADDR_BITS>,
    /// p (63..0), n (95..64), t (127..96).
    ram_pnt: LutRam<128, CTX_ADDR_BITS>,
    /// i (31..0), e (63..32), uq (95..64), ur (127..96).
    ram_ie: LutRam<128, CTX_ADDR_BITS>,
    /// uqs (31..0), urs (63..32), rev (64).
    ram_u: LutRam<65, CTX_ADDR_BITS>,
}

impl ContextRam {
    /// The word at `addr` as the simulation holds it (for tests that inspect the
    /// scheduler's state; the hardware has no such port).
    pub fn word(&self, addr: usize) -> ContextWord {
        let lo = |x: u128, at: u32, bits: u32| ((x >> at) & ((1u128 << bits) - 1)) as u64;
        let pnt = bits_to_u128(self.ram_pnt.word(addr));
        let ie = bits_to_u128(self.ram_ie.word(addr));
        let u = bits_to_u128(self.ram_u.word(addr));
        ContextWord {
            rev: lo(u, 64, 1) == 1,
            n: lo(pnt, 64, 32) as u32,
            i: lo(ie, 0, 32) as u32,
            t: lo(pnt, 96, 32) as u32,
            e: lo(ie, 32, 32) as u32,
            p: lo(pnt, 0, 64),
            b: bits_to_u128(self.ram_b.word(addr)),
            a: bits_to_u128(self.ram_a.word(addr)),
            uq: lo(ie, 64, 32) as u32,
            ur: lo(ie, 96, 32) as u32,
            uqs: lo(u, 0, 32) as u32,
            urs: lo(u, 32, 32) as u32,
        }
    }
}

impl Logic for ContextRam {
    #[hdl_gen]
    fn update(&mut self) {
        self.ram_b.clock.next = self.clock.val();
        self.ram_a.clock.next = self.clock.val();
        self.ram_pnt.clock.next = self.clock.val();
        self.ram_ie.clock.next = self.clock.val();
        self.ram_u.clock.next = self.clock.val();
        self.ram_b.we.next = self.we.val();
        self.ram_a.we.next = self.we.val();
        self.ram_pnt.we.next = self.we.val();
        self.ram_ie.we.next = self.we.val();
        self.ram_u.we.next = self.we.val();
        self.ram_b.waddr.next = self.waddr.val();
        self.ram_a.waddr.next = self.waddr.val();
        self.ram_pnt.waddr.next = self.waddr.val();
        self.ram_ie.waddr.next = self.waddr.val();
        self.ram_u.waddr.next = self.waddr.val();
        self.ram_b.raddr.next = self.raddr.val();
        self.ram_a.raddr.next = self.raddr.val();
        self.ram_pnt.raddr.next = self.raddr.val();
        self.ram_ie.raddr.next = self.raddr.val();
        self.ram_u.raddr.next = self.raddr.val();
        self.ram_b.wdata.next = self.w_b.val();
        self.ram_a.wdata.next = self.w_a.val();
        self.ram_pnt.wdata.next = bit_cast::<128, 64>(self.w_p.val())
            | (bit_cast::<128, 32>(self.w_n.val()) << 64)
            | (bit_cast::<128, 32>(self.w_t.val()) << 96);
        self.ram_ie.wdata.next = bit_cast::<128, 32>(self.w_i.val())
            | (bit_cast::<128, 32>(self.w_e.val()) << 32)
            | (bit_cast::<128, 32>(self.w_uq.val()) << 64)
            | (bit_cast::<128, 32>(self.w_ur.val()) << 96);
        self.ram_u.wdata.next = bit_cast::<65, 32>(self.w_uqs.val())
            | (bit_cast::<65, 32>(self.w_urs.val()) << 32)
            | (bit_cast::<65, 1>(self.w_rev.val().into()) << 64);
        self.r_b.next = self.ram_b.rdata.val();
        self.r_a.next = self.ram_a.rdata.val();
        self.r_p.next = self.ram_pnt.rdata.val().get_bits::<64>(0);
        self.r_n.next = self.ram_pnt.rdata.val().get_bits::<32>(64);
        self.r_t.next = self.ram_pnt.rdata.val().get_bits::<32>(96);
        self.r_i.next = self.ram_ie.rdata.val().get_bits::<32>(0);
        self.r_e.next = self.ram_ie.rdata.val().get_bits::<32>(32);
        self.r_uq.next = self.ram_ie.rdata.val().get_bits::<32>(64);
        self.r_ur.next = self.ram_ie.rdata.val().get_bits::<32>(96);
        self.r_uqs.next = self.ram_u.rdata.val().get_bits::<32>(0);
        self.r_urs.next = self.ram_u.rdata.val().get_bits::<32>(32);
        self.r_rev.next = self.ram_u.rdata.val().get_bit(64);
    }
}
