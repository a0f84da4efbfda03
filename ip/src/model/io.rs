//! Machine inputs and safety, clock by clock: the model of `hdl::input_filter` and
//! `hdl::machine_io` (plain Rust, no HDL).
//!
//! **An input** (limit, home, alarm, e-stop, probe) goes through two synchroniser
//! flip-flops, then its group's polarity (`invert`: 1 = active low at the pin), then a
//! digital filter: the filtered level takes a new value once the synchronised,
//! polarity-corrected input has differed from it at `n + 1` consecutive filter samples
//! (`n` = 0..=[`FILTER_MAX_SAMPLES`], 0 = no filter). Filter samples come from one
//! prescaler shared by every input: a sample every `prescale + 1` clk ticks
//! (`prescale` = 0: every tick). With `prescale` = 0 a pin change sampled at clk edge
//! e0 reaches the filtered level at edge e0 + 2 + n ([`pin_to_level_ticks`]). A pulse
//! (or a bounce) is taken only when it is seen at n + 1 consecutive samples; a
//! shorter one is ignored.
//!
//! A reset puts the e-stop, limit and alarm levels active and the home and probe levels
//! inactive: an input that stops motion counts as active until its filter has seen it
//! inactive, and no latch fires on the way out of a reset.
//!
//! **The block** ([`MachineIoModel`]) keeps the e-stop latch (set after reset and
//! whenever the filtered e-stop is active; cleared only by a re-arm while it is
//! inactive), the watchdog (trips [`WATCHDOG_UNIT_TICKS`]·timeout ticks after the
//! last feed or re-arm; sticky until a re-arm), the hard-stop request (`hard_stop`,
//! registered: a tick behind the e-stop level, its latch and the trip) and the
//! drivers' enables (registered from the same OR, so they fall with `hard_stop`), and
//! says in which cycle the home and probe latches take the positions (the cycle before their filtered level changes, so a latch and the
//! level change on the same clock edge). **The per-axis stop** (`axis_stop`, bit a,
//! registered): axis a moving (the core's `active`) toward an active limit (DIR 0
//! toward `limit_pos`, 1 toward `limit_neg`) in this cycle and the one before, or its
//! alarm active; `stop_tog` flips when it stops a moving axis (the event).
//!
//! **Groups** ([`IO_GROUPS`]): a block built with some groups only
//! ([`MachineIoModel::with_groups`]) reads the others' inputs as inactive, never sets
//! the e-stop latch (it resets clear) without the e-stop group and never trips without
//! the watchdog's.
//!
//! **Stop modes** ([`IoConfig::stop_mode`], STOP_MODE): each source of a stop (the
//! limits, the alarm, the watchdog, the stop on home) takes the hard stop or the
//! controlled stop. A source in controlled mode drives `axis_cstop` (bit a, registered)
//! instead of `axis_stop`: the limit's and the alarm's for as long as they hold, the
//! watchdog's on every axis for as long as it is tripped; the core ramps each axis down
//! once and keeps it stopped while the request holds. A controlled watchdog trip raises
//! `hard_stop` only once no axis is `active` (two ticks later), so the ramps
//! run; a controlled alarm keeps the axis's `drv_enable` while it is `active`. **Stop on
//! home** ([`IoConfig::home_stop`], bit a): the home latch's strobe on a moving axis
//! stops it one tick later (a one-cycle request), hard or controlled.

/// Largest filter length, in filter samples (the 4-bit field of each group).
pub const FILTER_MAX_SAMPLES: u8 = 15;
/// Filter groups, in the order of the polarity bits and filter fields.
pub const GROUPS: [&str; 6] = ["estop", "probe", "limit_neg", "limit_pos", "home", "alarm"];
pub const G_ESTOP: usize = 0;
pub const G_PROBE: usize = 1;
pub const G_LIMIT_NEG: usize = 2;
pub const G_LIMIT_POS: usize = 3;
pub const G_HOME: usize = 4;
pub const G_ALARM: usize = 5;
/// The watchdog's timeout unit, clk ticks.
pub const WATCHDOG_UNIT_BITS: u32 = 10;
pub const WATCHDOG_UNIT_TICKS: u64 = 1 << WATCHDOG_UNIT_BITS;
/// The machine I/O's groups, as `export --io` names them; bit g of a group mask.
pub const IO_GROUPS: [&str; 6] = ["estop", "probe", "limits", "home", "alarm", "watchdog"];
pub const IO_ESTOP: u8 = 1 << 0;
pub const IO_PROBE: u8 = 1 << 1;
pub const IO_LIMITS: u8 = 1 << 2;
pub const IO_HOME: u8 = 1 << 3;
pub const IO_ALARM: u8 = 1 << 4;
pub const IO_WATCHDOG: u8 = 1 << 5;
/// Every group (`--io all`).
pub const IO_ALL: u8 = 0x3F;
/// The groups with input pins and filters (all but the watchdog).
pub const IO_INPUTS: u8 = IO_ALL & !IO_WATCHDOG;

/// STOP_MODE bits: 1 = the source takes the controlled stop, 0 = the hard stop.
pub const MODE_LIMITS: u8 = 1;
pub const MODE_ALARM: u8 = 2;
pub const MODE_WATCHDOG: u8 = 4;
pub const MODE_HOME: u8 = 8;

/// Clk edges from the edge that first samples a pin change to the edge on which the
/// filtered level changes, with the prescaler at 0 (a sample every tick) and `n`
/// samples of filter: two synchroniser stages, then n + 1 samples, the first of which
/// is the second stage's.
pub const fn pin_to_level_ticks(n: u8) -> u64 {
    2 + n as u64
}

/// One input's synchroniser and filter. `Default` is an input whose level resets
/// inactive; [`InputModel::new`] chooses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InputModel {
    s1: bool,
    s2: bool,
    /// The filtered level, active high.
    pub level: bool,
    count: u8,
    /// The level a reset gives: active for the inputs that stop motion (e-stop,
    /// limits, alarm), so nothing moves until the filter has seen them inactive.
    reset_active: bool,
}

impl InputModel {
    pub fn new(reset_active: bool) -> Self {
        InputModel { level: reset_active, reset_active, ..Default::default() }
    }

    /// Whether the level changes at the coming clock edge.
    pub fn changes(&self, invert: bool, sample: bool, n: u8) -> bool {
        (self.s2 ^ invert) != self.level && sample && self.count >= n
    }

    /// One clock edge. `reset` clears the filter (the level to its reset value), not the
    /// synchroniser.
    pub fn clock(&mut self, pin: bool, invert: bool, sample: bool, n: u8, reset: bool) {
        let x = self.s2 ^ invert;
        if reset {
            self.level = self.reset_active;
            self.count = 0;
        } else if x == self.level {
            self.count = 0;
        } else if sample {
            if self.count >= n {
                self.level = x;
                self.count = 0;
            } else {
                self.count += 1;
            }
        }
        self.s2 = self.s1;
        self.s1 = pin;
    }
}

/// The block's configuration (quasi-static: it changes only between moves).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IoConfig {
    /// Bit g inverts group g's pin ([`GROUPS`]): 1 = active low.
    pub polarity: u8,
    /// Filter length of each group, samples (0..=15).
    pub filter: [u8; 6],
    /// A filter sample every `prescale + 1` ticks.
    pub prescale: u16,
    /// Bit 0: home latches when its input becomes inactive (else active); bit 1: probe.
    pub edges: u8,
    /// Watchdog timeout in units of [`WATCHDOG_UNIT_TICKS`]; 0 = off.
    pub wd_timeout: u16,
    /// [`MODE_LIMITS`] | [`MODE_ALARM`] | [`MODE_WATCHDOG`] | [`MODE_HOME`]: the
    /// sources that take the controlled stop.
    pub stop_mode: u8,
    /// Bit a: stop axis a on its home latch (it may change while the core runs).
    pub home_stop: u32,
}

impl IoConfig {
    /// `filter` packed as the HDL's port: group g in bits 4g + 3..4g.
    pub fn filter_word(&self) -> u32 {
        self.filter.iter().enumerate().map(|(g, &n)| (n as u32 & 0xF) << (4 * g)).sum()
    }
}

/// The pins in one cycle: e-stop (`estop_n`), probe, and per axis (bit a) the limits,
/// home and alarm.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IoPins {
    pub estop_n: bool,
    pub probe: bool,
    pub limit_neg: u32,
    pub limit_pos: u32,
    pub home: u32,
    pub alarm: u32,
    /// Not pins: the core's DIR (1 = negative) and moving (`active`) flags, bit a.
    pub dir: u32,
    pub active: u32,
}

/// One-cycle commands from the host (already in clk).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IoCommands {
    pub estop_rearm: bool,
    pub wd_feed: bool,
    pub wd_rearm: bool,
}

/// What the block shows in one cycle (before the clock edge).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IoOutputs {
    pub hard_stop: bool,
    pub estop_latched: bool,
    pub estop_active: bool,
    pub probe_active: bool,
    pub wd_tripped: bool,
    pub drv_enable: u32,
    pub limit_neg: u32,
    pub limit_pos: u32,
    pub home: u32,
    pub alarm: u32,
    /// Bit a: axis a's home latch takes its position at the coming edge.
    pub home_latch: u32,
    /// Every axis's probe latch takes its position at the coming edge.
    pub probe_latch: bool,
    /// Bit a: axis a is held in a hard stop by its inputs ([`MachineIoModel`]).
    pub axis_stop: u32,
    /// Bit a: axis a is asked for a controlled stop by its inputs or the watchdog.
    pub axis_cstop: u32,
    /// Bit a flips each time `axis_stop` or `axis_cstop` stops a moving axis a.
    pub stop_tog: u32,
}

/// The machine I/O block of `axes` axes.
#[derive(Clone, Debug)]
pub struct MachineIoModel {
    pub axes: usize,
    prescaler: u16,
    estop: InputModel,
    probe: InputModel,
    /// Per axis: limit_neg, limit_pos, home, alarm.
    axis_inputs: Vec<[InputModel; 4]>,
    estop_latched: bool,
    wd_count: u32,
    wd_tripped: bool,
    drv_enable: u32,
    /// Per axis, registered: moving toward an active limit, the stop, its toggle.
    toward: u32,
    axis_stop: u32,
    axis_cstop: u32,
    stop_tog: u32,
    /// A controlled watchdog trip with no axis active (registered).
    wd_rest: bool,
    /// The hard stop, registered: `hard_stop` is one tick behind [`Self::hard`].
    hard_q: bool,
    /// The groups built ([`IO_GROUPS`] bits).
    groups: u8,
}

impl MachineIoModel {
    /// The block as it is after reset.
    pub fn new(axes: usize) -> Self {
        assert!((1..=16).contains(&axes));
        MachineIoModel {
            axes,
            prescaler: 0,
            estop: InputModel::new(true),
            probe: InputModel::new(false),
            axis_inputs: vec![[InputModel::new(true), InputModel::new(true), InputModel::new(false), InputModel::new(true)]; axes],
            estop_latched: true,
            wd_count: 1,
            wd_tripped: false,
            drv_enable: 0,
            toward: 0,
            axis_stop: 0,
            axis_cstop: 0,
            stop_tog: 0,
            wd_rest: false,
            hard_q: true,
            groups: IO_ALL,
        }
    }

    /// The block with only the groups `groups` ([`IO_GROUPS`] bits), as after reset.
    pub fn with_groups(mut self, groups: u8) -> Self {
        self.groups = groups;
        self.estop_latched = self.on(IO_ESTOP);
        self.hard_q = self.on(IO_ESTOP);
        self
    }

    fn on(&self, group: u8) -> bool {
        self.groups & group != 0
    }

    fn estop_level(&self) -> bool {
        self.estop.level && self.on(IO_ESTOP)
    }

    fn probe_level(&self) -> bool {
        self.probe.level && self.on(IO_PROBE)
    }

    /// Axis a's filtered input j (limit_neg, limit_pos, home, alarm), if its group is built.
    fn axis_level(&self, a: usize, j: usize) -> bool {
        self.axis_inputs[a][j].level && self.on([IO_LIMITS, IO_LIMITS, IO_HOME, IO_ALARM][j])
    }

    fn hard(&self, cfg: &IoConfig) -> bool {
        self.estop_latched || self.estop_level() || (self.wd_tripped && cfg.stop_mode & MODE_WATCHDOG == 0) || self.wd_rest
    }

    fn sample(&self, cfg: &IoConfig) -> bool {
        self.prescaler >= cfg.prescale
    }

    fn bits(&self, f: impl Fn(usize) -> bool) -> u32 {
        (0..self.axes).filter(|&a| f(a)).map(|a| 1 << a).sum()
    }

    /// The outputs in this cycle, for these inputs.
    pub fn outputs(&self, cfg: &IoConfig) -> IoOutputs {
        let s = self.sample(cfg);
        let inv = |g: usize| cfg.polarity >> g & 1 == 1;
        let level = |j: usize| self.bits(|a| self.axis_level(a, j));
        let home_to = cfg.edges & 1 == 0;
        let home_latch = self.bits(|a| {
            let h = &self.axis_inputs[a][2];
            self.on(IO_HOME) && h.changes(inv(G_HOME), s, cfg.filter[G_HOME]) && h.level != home_to
        });
        let probe_to = cfg.edges >> 1 & 1 == 0;
        IoOutputs {
            hard_stop: self.hard_q,
            estop_latched: self.estop_latched,
            estop_active: self.estop_level(),
            probe_active: self.probe_level(),
            wd_tripped: self.wd_tripped,
            drv_enable: self.drv_enable,
            limit_neg: level(0),
            limit_pos: level(1),
            home: level(2),
            alarm: level(3),
            home_latch,
            probe_latch: self.on(IO_PROBE) && self.probe.changes(inv(G_PROBE), s, cfg.filter[G_PROBE]) && self.probe.level != probe_to,
            axis_stop: self.axis_stop,
            axis_cstop: self.axis_cstop,
            stop_tog: self.stop_tog,
        }
    }

    /// One clock edge with these pins, commands and `run` (the core is enabled).
    pub fn clock(&mut self, cfg: &IoConfig, pins: &IoPins, cmd: &IoCommands, run: bool, reset: bool) {
        let s = self.sample(cfg);
        let inv = |g: usize| cfg.polarity >> g & 1 == 1;
        let hard = self.hard(cfg);
        let ctl = |m: u8| cfg.stop_mode & m != 0;
        let active = |a: usize| pins.active >> a & 1 == 1;
        // Registered enables: the state of this cycle (a controlled alarm keeps the
        // enable while its axis is active: the ramp runs).
        self.drv_enable =
            self.bits(|a| run && !hard && !(self.axis_level(a, 3) && (!ctl(MODE_ALARM) || !active(a))));
        // The per-axis stop: moving toward an active limit (DIR 0 toward limit_pos, 1
        // toward limit_neg) in this cycle and the one before (a segment that starts
        // away from the limit shows the old DIR for one tick), the alarm active, or the
        // home latch on a moving axis armed to stop on it.
        let toward = self.bits(|a| {
            let d = pins.dir >> a & 1 == 1;
            active(a) && ((!d && self.axis_level(a, 1)) || (d && self.axis_level(a, 0)))
        });
        let limit = toward & self.toward;
        let alarm = self.bits(|a| self.axis_level(a, 3));
        let hit = self.outputs(cfg).home_latch & cfg.home_stop & pins.active;
        let pick = |m: u8, w: u32, controlled: bool| if ctl(m) == controlled { w } else { 0 };
        let stop = pick(MODE_LIMITS, limit, false) | pick(MODE_ALARM, alarm, false) | pick(MODE_HOME, hit, false);
        let all = self.bits(|_| true);
        let cstop = pick(MODE_LIMITS, limit, true)
            | pick(MODE_ALARM, alarm, true)
            | pick(MODE_HOME, hit, true)
            | if self.wd_tripped && ctl(MODE_WATCHDOG) { all } else { 0 };
        self.stop_tog ^= (stop | cstop) & !(self.axis_stop | self.axis_cstop) & pins.active;
        self.axis_stop = stop;
        self.axis_cstop = cstop;
        self.toward = toward;
        self.wd_rest = self.wd_tripped && ctl(MODE_WATCHDOG) && pins.active == 0;
        self.hard_q = hard;
        let estop_active = self.estop_level();
        self.estop_latched = estop_active || (self.estop_latched && !cmd.estop_rearm);
        let unit_end = (cfg.wd_timeout as u32) << WATCHDOG_UNIT_BITS;
        if cmd.wd_rearm {
            self.wd_tripped = false;
            self.wd_count = 1;
        } else if cfg.wd_timeout == 0 || cmd.wd_feed || self.wd_tripped {
            self.wd_count = 1;
        } else {
            if self.wd_count >= unit_end {
                self.wd_tripped = self.on(IO_WATCHDOG);
            }
            self.wd_count = (self.wd_count + 1) & ((1 << 26) - 1);
        }
        self.prescaler = if s { 0 } else { self.prescaler.wrapping_add(1) };
        self.estop.clock(pins.estop_n, inv(G_ESTOP), s, cfg.filter[G_ESTOP], reset);
        self.probe.clock(pins.probe, inv(G_PROBE), s, cfg.filter[G_PROBE], reset);
        for a in 0..self.axes {
            let pin = |w: u32| w >> a & 1 == 1;
            let groups = [G_LIMIT_NEG, G_LIMIT_POS, G_HOME, G_ALARM];
            let p = [pin(pins.limit_neg), pin(pins.limit_pos), pin(pins.home), pin(pins.alarm)];
            for j in 0..4 {
                self.axis_inputs[a][j].clock(p[j], inv(groups[j]), s, cfg.filter[groups[j]], reset);
            }
        }
        if reset {
            self.prescaler = 0;
            self.estop_latched = self.on(IO_ESTOP);
            self.hard_q = self.on(IO_ESTOP);
            self.wd_count = 1;
            self.wd_tripped = false;
            self.drv_enable = 0;
            self.toward = 0;
            self.axis_stop = 0;
            self.axis_cstop = 0;
            self.stop_tog = 0;
            self.wd_rest = false;
        }
    }
}
