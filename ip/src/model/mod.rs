//! The reference model: plain Rust, no HDL.
//!
//! * [`segment`]: segments in register units, the documented range, validation and
//!   error codes;
//! * [`exact`]: exact kinematics, the yardstick;
//! * [`integer`]: the bit-accurate integer model of the hardware algorithm;
//! * [`axis`]: one axis running segments back to back;
//! * [`units`]: steps/s and seconds to register units;
//! * [`poly`]: polynomial (S-curve) segments: the form, validation, the exact edge search;
//! * [`planner`]: trapezoid moves to segments;
//! * [`scurve`]: jerk-limited and fourth-order (S-curve) moves to segments;
//! * [`guard`]: the machine I/O's push checks (limits, soft limits, a held axis) and the planned position;
//! * [`io`]: machine inputs and safety (filters, e-stop latch, watchdog, latches), clock by clock;
//! * [`stop`]: the controlled stop's segment, formed from an axis's last period;
//! * [`pulse`]: STEP high times and DIR changes on the pins, from the output timing;
//! * [`alternatives`]: other period algorithms, for the accuracy report.

pub mod alternatives;
pub mod axis;
pub mod encoder;
pub mod exact;
pub mod guard;
pub mod integer;
pub mod io;
pub mod planner;
pub mod poly;
pub mod pulse;
pub mod scurve;
pub mod segment;
pub mod stop;
pub mod units;

pub use axis::{AxisRun, FifoEntry, Motion, Rejected};
pub use integer::{
    offset_root, PlanKind, SegmentPlan, ACC_BITS, EDGE_ERROR_BOUND_TICKS, OFFSET_ROOT_BITS, ROOT_BITS, TAU_FRAC_BITS,
};
pub use pulse::{PulseTiming, MAX_PULSE_TICKS};
pub use segment::{Limits, Segment, SegmentError, MAX_STEPS, MAX_T_TICKS, MAX_V0_RATE};
