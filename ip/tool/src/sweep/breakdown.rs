//! The per-block breakdown: the blocks kept as hierarchy in one xc7 synthesis, each
//! module of the netlist assigned to its block, and the table of them.
use super::*;

/// The block a module of the exported core belongs to (a module is named by its
/// instance path, `tdm_stepper__core__ctx__0__r_a`; rust-hdl's own `$` form is read too).
pub fn block_of(module: &str) -> &'static str {
    let path = module.trim_start_matches('\\').replace("__", "$");
    let rest = match path.split_once('$') {
        Some((_, r)) => r,
        None => return "top level (IO, glue)",
    };
    // A core on another bus is `<top>__exmc` inside the top, beside its front end.
    const FRONTS: [(&str, &str); 3] = [("spi", "SPI front end"), ("wb", "Wishbone front end"), ("axil", "AXI4-Lite front end")];
    if let Some(f) = FRONTS.iter().find(|(p, _)| rest == *p || rest.starts_with(&format!("{p}$"))) {
        return f.1;
    }
    let rest = match rest.strip_prefix("exmc$") {
        Some(inner) if BLOCKS.iter().any(|(p, _)| inner.starts_with(p)) => inner,
        _ => rest,
    };
    const BLOCKS: [(&str, &str); 19] = [
        ("core$ctx$", "per-axis contexts (current and next segment)"),
        ("core$ctx_ram", "per-axis contexts (current and next segment)"),
        ("core$queues", "segment queues (one RAM for every axis, two counters each)"),
        ("core$bank$axes$", "per-axis step generators and period FIFOs"),
        ("core$div", "shared divider"),
        ("core$root", "shared offset root"),
        ("core$mul", "shared multipliers"),
        ("core$bank$pulse", "pulse stage (STEP high times)"),
        ("core$bank", "axis bank: synchronised start, per-axis flags, status multiplexers"),
        (
            "core",
            "scheduler: FSM, working copy, K:1 multiplexers, counters",
        ),
        ("regs", "register file: staging, status mirror, IRQ"),
        ("status", "status crossing (core to bus clock)"),
        ("busy_q", "status crossing (core to bus clock)"),
        ("cmd_fifo", "command FIFO and stage (bus to core clock)"),
        ("c_", "command FIFO and stage (bus to core clock)"),
        ("exmc", "EXMC slave"),
        ("rst_", "single-bit synchronisers (reset, enable, start failure)"),
        ("en_core", "single-bit synchronisers (reset, enable, start failure)"),
        ("fail_sync", "single-bit synchronisers (reset, enable, start failure)"),
    ];
    BLOCKS
        .iter()
        .find(|(p, _)| rest.starts_with(p))
        .map(|b| b.1)
        .unwrap_or("other")
}

/// Resources by block from `stat -json` of a hierarchical synthesis of `top`. Each
/// module counts once per instance (rust-hdl writes one module per instance, but the
/// count does not rely on it).
pub fn breakdown_blocks(json: &str, top: &str, family: Family) -> Result<Vec<Block>, String> {
    // yosys 0.23 prints the hierarchy as text after "modules" when it is three or more
    // levels deep, so the file is not JSON: read the "modules" object alone.
    let at = json.find("\"modules\":").ok_or("stat -json: no modules")? + "\"modules\":".len();
    let v = serde_json::Deserializer::from_str(&json[at..])
        .into_iter::<serde_json::Value>()
        .next()
        .ok_or("stat -json: no modules")?
        .map_err(|e| format!("stat -json: {e}"))?;
    let modules = v.as_object().ok_or("stat -json: modules is not an object")?;
    let cells = |name: &str| -> Option<&serde_json::Map<String, serde_json::Value>> {
        modules
            .get(&format!("\\{name}"))
            .or_else(|| modules.get(name))?
            .get("num_cells_by_type")?
            .as_object()
    };
    cells(top).ok_or(format!("stat -json: no module {top}"))?;
    let mut blocks: Vec<Block> = Vec::new();
    let mut stack = vec![(top.to_string(), 1u64)];
    while let Some((m, n)) = stack.pop() {
        let c = cells(&m).ok_or(format!("stat -json: no module {m}"))?;
        let r = count_cells(c, family);
        let name = block_of(&m);
        let b = match blocks.iter_mut().position(|b| b.name == name) {
            Some(i) => &mut blocks[i],
            None => {
                blocks.push(Block {
                    name: name.into(),
                    luts: 0,
                    ffs: 0,
                    dsps: 0,
                    brams: 0,
                    carry: 0,
                });
                blocks.last_mut().unwrap()
            }
        };
        b.luts += n * r.luts;
        b.ffs += n * r.ffs;
        b.dsps += n * r.dsps;
        b.brams += n * r.brams;
        b.carry += n * r.carry;
        for (ty, k) in c {
            if cells(ty).is_some() {
                stack.push((ty.clone(), n * k.as_u64().unwrap_or(0)));
            }
        }
    }
    blocks.sort_by(|a, b| b.luts.cmp(&a.luts).then(a.name.cmp(&b.name)));
    Ok(blocks)
}

/// The modules [`breakdown_point`] keeps as blocks; the rest (rust-hdl's one-register
/// modules, small helpers) is flattened into them, so that a block is optimised as it
/// is in the flattened design (a register's hold multiplexer becomes its clock enable).
pub fn breakdown_blocks_kept(axes: usize, bus: export::Bus) -> Vec<String> {
    // On another bus the core is `tdm_stepper__exmc` and the front end is kept whole.
    let (core, front) = match bus {
        export::Bus::Exmc => ("tdm_stepper".to_string(), None),
        b => ("tdm_stepper__exmc".to_string(), Some(format!("tdm_stepper__{}", b.name()))),
    };
    let mut m: Vec<String> = ["core", "core$div", "core$root", "core$mul", "core$mulw", "core$ctx_ram", "core$queues", "core$bank", "regs", "status", "cmd_fifo", "exmc"]
        .iter()
        .map(|b| format!("{core}__{}", b.replace('$', "__")))
        .collect();
    for a in 0..axes {
        for b in ["ctx", "bank__axes"] {
            m.push(format!("{core}__core__{b}__{a}"));
        }
    }
    m.extend(front);
    m
}

/// The yosys script of a breakdown: `synth_xilinx -flatten` with the blocks of
/// [`breakdown_blocks_kept`] marked `keep_hierarchy`.
pub fn breakdown_script(axes: usize, bus: export::Bus) -> String {
    format!(
        "read_verilog tdm_stepper.v; hierarchy -top tdm_stepper; setattr -mod -set keep_hierarchy 1 {}; synth_xilinx -flatten -top tdm_stepper; tee -q -o stat.json stat -json",
        breakdown_blocks_kept(axes, bus).join(" ")
    )
}

pub(super) fn breakdown_point(axes: usize, opts: &SweepOptions) -> Breakdown {
    let dir = opts.work.join(format!("breakdown_xc7_tdm_k{axes}{}", opts.io_suffix()));
    let log = dir.join("yosys.log");
    let t0 = Instant::now();
    let mut reused = false;
    let result = (|| -> Result<Vec<Block>, String> {
        let v = export::verilog(&ExportOptions { axes, clock_hz: opts.clock_hz, io: opts.io, io_omit: opts.io_omit, scurve: opts.scurve, encoder: opts.encoder, bus: opts.bus, ..Default::default() })?;
        breakdown_blocks(&yosys_stat(&dir, &v, &breakdown_script(axes, opts.bus), opts, &mut reused)?, "tdm_stepper", Family::Xc7)
    })();
    let seconds = t0.elapsed().as_secs_f64();
    match result {
        Ok(blocks) => Breakdown {
            axes,
            status: "ok".into(),
            blocks,
            seconds,
            tool_seconds: run_seconds(&dir, "tdm_stepper.v", "stat.json"),
            log,
            message: reused_note(reused),
        },
        Err(e) => Breakdown {
            axes,
            status: status_of(&e),
            blocks: Vec::new(),
            seconds,
            tool_seconds: None,
            log,
            message: Some(e),
        },
    }
}

/// The table of [`Breakdown`]s: LUT6 and FF by block at each K and, with two or more
/// K, the LUT6 per extra axis between the smallest and the largest.
pub fn breakdown_markdown(bs: &[Breakdown]) -> String {
    let mut m = String::from("## Where the LUTs go (xc7, TDM, `synth_xilinx -flatten` with each block kept whole)\n\n");
    m += "The blocks are marked `keep_hierarchy` (`--breakdown`); everything inside a block is flattened into it, but nothing is optimised across blocks, so the totals are a little above the flattened design's.\n\n";
    let ok: Vec<&Breakdown> = bs.iter().filter(|b| b.status == "ok").collect();
    for b in bs.iter().filter(|b| b.status != "ok") {
        m += &format!(
            "* K = {}: {} ({})\n",
            b.axes,
            b.status,
            b.message.clone().unwrap_or_default()
        );
    }
    if ok.is_empty() {
        return m + "\n";
    }
    let mut names: Vec<&str> = Vec::new();
    for b in ok.iter().rev() {
        for x in &b.blocks {
            if !names.contains(&x.name.as_str()) {
                names.push(&x.name);
            }
        }
    }
    let per_axis = ok.len() >= 2;
    m += "| block |";
    for b in &ok {
        m += &format!(" LUT6 K = {} | FF K = {} |", b.axes, b.axes);
    }
    m += if per_axis {
        " LUT6 per extra axis |\n|---|"
    } else {
        "\n|---|"
    };
    m += &"---|".repeat(2 * ok.len() + per_axis as usize);
    m += "\n";
    let get = |b: &Breakdown, n: &str| {
        b.blocks
            .iter()
            .find(|x| x.name == n)
            .map_or((0, 0), |x| (x.luts, x.ffs))
    };
    let mut rows: Vec<(String, Vec<(u64, u64)>)> = names
        .iter()
        .map(|n| (n.to_string(), ok.iter().map(|b| get(b, n)).collect()))
        .collect();
    let total: Vec<(u64, u64)> = (0..ok.len())
        .map(|i| {
            rows.iter()
                .fold((0, 0), |a, r| (a.0 + r.1[i].0, a.1 + r.1[i].1))
        })
        .collect();
    rows.push(("**total**".into(), total));
    let (k0, k1) = (ok[0].axes, ok[ok.len() - 1].axes);
    for (n, v) in rows {
        m += &format!("| {n} |");
        for (l, f) in &v {
            m += &format!(" {l} | {f} |");
        }
        if per_axis {
            m += &format!(
                " {:.0} |",
                (v[v.len() - 1].0 as f64 - v[0].0 as f64) / (k1 - k0) as f64
            );
        }
        m += "\n";
    }
    // Block RAMs are not LUTs: say where they went, so that a LUT saving that is really
    // a move into block RAM is visible.
    for b in &ok {
        for x in b.blocks.iter().filter(|x| x.brams > 0) {
            m += &format!("\nK = {}: {} uses {} block RAM(s) (RAMB18/36), not counted above.\n", b.axes, x.name, x.brams);
        }
    }
    m + "\n"
}
