"""The exported core driven through its host bus by the ecosystem's own masters.

cocotb test module (cocotb 1.9): the case file named by $TDM_CASE (written by
ip/tool/tests/export.rs) gives the bus, the clocks, the register table of the export,
the paper's experiment (segments from vectors/paper_experiment.json) and the STEP
edges the reference model gives for it. The masters are cocotbext-spi's SpiMaster
(`--bus spi`), cocotbext-wishbone's WishboneMaster (`--bus wb`) and cocotbext-axi's
AxiLiteMaster (`--bus axil`). The test:

1. reads every register of the map and finds its documented reset value, then
   writes and reads back the plain read/write registers;
2. sends bad framing, which must be refused as docs/registers.md says and change no
   register (SPI: CS raised mid-word, a frame one word too long; Wishbone: unmapped
   addresses, a write without SEL[1:0]; AXI4-Lite: unmapped addresses, half a
   register's strobes);
3. runs the paper's experiment with random register traffic while the axes move,
   and checks every STEP edge (and DIR) against the model's, both axes from one
   release tick, and the positions read back.
"""

import json
import logging
import os
import random

import cocotb
from cocotb.triggers import Edge, RisingEdge, Timer
from cocotb.utils import get_sim_time

with open(os.environ["TDM_CASE"]) as f:
    CASE = json.load(f)
BUS = CASE["bus"]


class Refused(Exception):
    pass


class SpiRegs:
    """Register access in SPI frames (docs/registers.md, "SPI")."""

    def __init__(self, dut):
        from cocotb_bus.bus import Bus
        from cocotbext.spi import SpiConfig, SpiMaster

        bus = Bus(dut, None, {"sclk": "sck", "mosi": "mosi", "miso": "miso", "cs": "cs_n"})
        # Mode 0 at SCK = 25 MHz (bus_clk/4 at the case's bus clock or slower); CS
        # high at least 4 bus clocks between frames.
        cfg = SpiConfig(word_width=8, sclk_freq=CASE["sck_hz"], cpol=False, cpha=False, msb_first=True,
                        frame_spacing_ns=CASE["spi_gap_ns"], data_output_idle=0, cs_active_low=True)
        self.m = SpiMaster(bus, cfg)
        self.status = []

    async def frame(self, tx):
        self.m.clear()
        await self.m.write(bytes(tx), burst=True)
        rx = await self.m.read(len(tx))
        self.status.append(rx[0])
        return rx

    def last_status(self):
        return self.status[-1]

    async def read(self, word, n=1):
        cmd = (1 << 6) | ((n - 1) << 1) | (word >> 8)
        rx = await self.frame([cmd, word & 0xFF, 0] + [0] * (2 * n))
        vals = [rx[3 + 2 * k] << 8 | rx[4 + 2 * k] for k in range(n)]
        return vals[0] if n == 1 else vals

    async def write(self, word, value):
        await self.frame([0xC0 | (word >> 8), word & 0xFF, value >> 8, value & 0xFF])


class WbRegs:
    """Register access in Wishbone classic cycles, one access per cycle."""

    def __init__(self, dut):
        from cocotbext.wishbone.driver import WishboneMaster

        sig = {"cyc": "wb_cyc", "stb": "wb_stb", "we": "wb_we", "adr": "wb_adr", "datwr": "wb_dat_w",
               "datrd": "wb_dat_r", "ack": "wb_ack", "err": "wb_err", "sel": "wb_sel"}
        self.m = WishboneMaster(dut, None, dut.bus_clk, width=32, timeout=1000, signals_dict=sig)

    async def access(self, op):
        from cocotbext.wishbone.driver import WBOp

        res = await self.m.send_cycle([WBOp(**op)])
        assert len(res) == 1, f"one reply, got {len(res)}"
        if res[0].ack == 2:
            raise Refused("ERR")
        assert res[0].ack == 1, f"reply code {res[0].ack}"
        return int(res[0].datrd) & 0xFFFFFFFF

    async def read(self, word, n=1):
        vals = []
        for k in range(n):
            v = await self.access({"adr": word + k, "acktimeout": 100})
            assert v >> 16 == 0, f"bits 31..16 of word {word + k:#x} read {v:#x}"
            vals.append(v)
        return vals[0] if n == 1 else vals

    async def write(self, word, value, sel=0xF):
        await self.access({"adr": word, "dat": value, "sel": sel, "acktimeout": 100})


async def tick(clock):
    """Awaits every rising edge of `clock`, and does nothing else. With Verilator 5.006
    and cocotb 1.9, cocotbext-axi's channels stall from their second access on unless
    some coroutine waits on every clock edge: a channel that went idle re-arms its
    RisingEdge(clock) from an Event and that edge is never delivered. With this
    coroutine running, every access completes (one Python call per bus clock)."""
    edge = RisingEdge(clock)
    while True:
        await edge


class AxilRegs:
    """Register access through AXI4-Lite: register w at byte 4·w."""

    def __init__(self, dut):
        from cocotbext.axi import AxiLiteBus, AxiLiteMaster

        cocotb.start_soon(tick(dut.bus_clk))
        self.m = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axil"), dut.bus_clk, dut.reset)
        # One INFO line per access otherwise: thousands during the experiment.
        self.m.write_if.log.setLevel(logging.WARNING)
        self.m.read_if.log.setLevel(logging.WARNING)

    async def read(self, word, n=1):
        vals = []
        for k in range(n):
            r = await self.m.read(4 * (word + k), 4)
            if int(r.resp) != 0:
                assert r.data == bytes(4), f"a refused read returns 0, got {r.data}"
                raise Refused(f"RRESP {int(r.resp)}")
            v = int.from_bytes(r.data, "little")
            assert v >> 16 == 0, f"bits 31..16 of word {word + k:#x} read {v:#x}"
            vals.append(v)
        return vals[0] if n == 1 else vals

    async def write(self, word, value, nbytes=2):
        r = await self.m.write(4 * word, value.to_bytes(4, "little")[:nbytes])
        if int(r.resp) != 0:
            raise Refused(f"BRESP {int(r.resp)}")


def reg(name, axis=0):
    r = CASE["registers"][name]
    return r["word"] + (CASE["axis_stride"] * axis if r["per_axis"] else 0)


async def expect_refused(what, coro):
    try:
        await coro
    except Refused:
        return
    raise AssertionError(f"{what}: not refused")


async def watch_steps(dut, edges):
    last = 0
    k = len(edges)
    while True:
        await Edge(dut.step)
        v = int(dut.step.value)
        d = int(dut.dir.value)
        rose = v & ~last
        t = get_sim_time("ps")
        for a in range(k):
            if rose >> a & 1:
                edges[a].append((t // CASE["clk_ps"], d >> a & 1))
        last = v


@cocotb.test(timeout_time=CASE["timeout_ms"], timeout_unit="ms")
async def bus_registers_framing_and_paper_experiment(dut):
    # clk and bus_clk run in the wrapper (run_bench.py, cocotb_top).
    dut.reset.value = 1
    # Every bus input gets one ordinary write before a master drives it: with Verilator
    # 5.006 (cocotb 1.9), a signal whose first write was setimmediatevalue (as the
    # masters' constructors do) takes no later writes.
    idle = {
        "spi": {"cs_n": 1, "sck": 0, "mosi": 0},
        "wb": {"wb_cyc": 0, "wb_stb": 0, "wb_we": 0, "wb_adr": 0, "wb_sel": 0, "wb_dat_w": 0},
        "axil": {f"s_axil_{n}": 0 for n in ("awaddr", "awvalid", "wdata", "wstrb", "wvalid", "bready", "araddr", "arvalid", "rready")},
    }[BUS]
    for name, v in idle.items():
        getattr(dut, name).value = v
    await Timer(1, units="ns")
    regs = {"spi": SpiRegs, "wb": WbRegs, "axil": AxilRegs}[BUS](dut)
    await Timer(2, units="us")
    dut.reset.value = 0
    await Timer(2, units="us")

    # 1. Every register at its documented reset value; the plain RW ones written back.
    for name, r in CASE["registers"].items():
        for a in range(CASE["axes"] if r["per_axis"] else 1):
            got = await regs.read(reg(name, a))
            assert got == r["reset"], f"{name}[{a}] reads {got:#06x}, docs/registers.md says {r['reset']:#06x}"
    for name in CASE["rw"]:
        r = CASE["registers"][name]
        for v in (0x5A5A & r["mask"] or r["mask"], 0xFFFF & r["mask"]):
            await regs.write(reg(name), v)
            got = await regs.read(reg(name))
            assert got == v, f"{name}: wrote {v:#06x}, read {got:#06x}"
        await regs.write(reg(name), r["reset"])
    dut._log.info("%d registers read their reset values; %d written and read back", len(CASE["registers"]), len(CASE["rw"]))

    # 2. Bad framing, refused as documented; no register changes.
    qlow = reg("QLOW_LEVEL")
    before = await regs.read(qlow)
    if BUS == "spi":
        assert regs.last_status() & 0x7F == CASE["spi_status_pattern"], f"status {regs.last_status():#04x}"
        # CS raised after 8 bits of the word: the partial word is discarded.
        await regs.frame([0x80, qlow & 0xFF, 0x00])
        assert await regs.read(qlow) == before, "a partial word was written"
        assert regs.last_status() & 0x40, "FRAME_ERR after CS raised mid-word"
        # LEN 1 with two words: the first is written, the second refused.
        mask = reg("IRQ_MASK_DONE")
        await regs.frame([0xC0 | (mask >> 8), mask & 0xFF, 0x00, 0x01, 0x00, 0x03])
        assert await regs.read(mask) == 1, "the first word of an over-long frame is written"
        assert regs.last_status() & 0x40, "FRAME_ERR after a frame one word too long"
        assert await regs.read(mask + 1) == 0, "a word past LEN was written"
        await regs.write(mask, 0)
        assert not regs.last_status() & 0x40, "a good frame reports no error"
    else:
        for w in CASE["holes"]:
            await expect_refused(f"read of unmapped {w:#x}", regs.read(w))
            await expect_refused(f"write of unmapped {w:#x}", regs.write(w, 0x1234))
        if BUS == "wb":
            await expect_refused("write without SEL[1:0]", regs.write(qlow, 0x0007, sel=0x1))
            await expect_refused("write without SEL[1:0]", regs.write(qlow, 0x0007, sel=0xC))
        else:
            await expect_refused("write of one byte", regs.write(qlow, 0x0007, nbytes=1))
    assert await regs.read(qlow) == before, "a refused access changed QLOW_LEVEL"
    dut._log.info("bad framing refused")

    # 3. The paper's experiment, with traffic while the axes move.
    edges = [[] for _ in range(CASE["axes"])]
    cocotb.start_soon(watch_steps(dut, edges))
    await regs.write(reg("CTRL"), 1)
    for _ in range(200):
        if await regs.read(reg("GSTATUS")) & CASE["gstatus_enabled"]:
            break
    else:
        raise AssertionError("the core did not enable")
    for a, segs in enumerate(CASE["segments"]):
        for v0, t, steps in segs:
            s = steps & 0xFFFFFFFF
            for name, v in (("V0_LO", v0 & 0xFFFF), ("V0_HI", v0 >> 16), ("T_LO", t & 0xFFFF), ("T_HI", t >> 16),
                            ("STEPS_LO", s & 0xFFFF), ("STEPS_HI", s >> 16)):
                await regs.write(reg(name, a), v)
    await Timer(CASE["settle_us"], units="us")
    await regs.write(reg("START"), (1 << len(CASE["segments"])) - 1)
    rng = random.Random(0x7D3)
    traffic = 0
    while True:
        busy = await regs.read(reg("BUSY"))
        if busy == 0:
            break
        a = rng.randrange(CASE["axes"])
        pick = rng.randrange(4)
        if pick == 0:
            await regs.read(reg("STATUS", a))
        elif pick == 1:
            await regs.read(reg("POS_LO", a), 2)
        elif pick == 2:
            await regs.write(reg("IRQ_MASK_DONE"), rng.randrange(1 << CASE["axes"]))
        else:
            await regs.read(reg("ID_MAGIC"), 3)
        traffic += 1
        await Timer(rng.randrange(1, 40), units="us")
    await Timer(100, units="us")
    assert traffic >= CASE["min_traffic"], f"only {traffic} accesses during the move"

    want = CASE["edges"]
    release = None
    for a in range(len(want)):
        got = edges[a]
        assert len(got) == len(want[a]), f"axis {a}: {len(got)} STEP edges, the model {len(want[a])}"
        l0 = got[0][0] - want[a][0]
        release = l0 if release is None else release
        assert l0 == release, f"axis {a} released at {l0}, axis 0 at {release} (skew)"
        for i, ((c, d), w) in enumerate(zip(got, want[a])):
            assert c == release + w, f"axis {a} edge {i}: clk cycle {c}, the model {release + w}"
            assert d == CASE["dirs"][a], f"axis {a} edge {i}: DIR {d}"
        lo, hi = await regs.read(reg("POS_LO", a), 2)
        pos = lo | hi << 16
        pos = pos - (1 << 32) if pos >> 31 else pos
        assert pos == CASE["positions"][a], f"axis {a}: position {pos}, want {CASE['positions'][a]}"
    dut._log.info("PASS %s: %d edges equal to the model, %d accesses during the move", BUS,
                  sum(len(e) for e in edges), traffic)
