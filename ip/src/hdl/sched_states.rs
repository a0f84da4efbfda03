//! The scheduler's state codes, shared by the blocks that decode its state register
//! ([`super::core::TdmCore`], which holds it, and [`super::setup_path::SetupPath`]).
//! No logic: constants only.

use rust_hdl::prelude::*;

/// Width of the FSM state register.
pub const STATE_BITS: usize = 5;

/// The scheduler's states, in the order of their Gray codes (state k has code
/// `k ^ (k >> 1)`): consecutive states differ in one bit.
pub const STATES: [&str; 32] = [
    "PICK", "S_CHECK", "S_ISSUE_VT", "S_ISSUE_TR", "S_VT", "S_TR", "S_DWELL", "S_UDIV", "S_X", "S_P", "S_B", "S_NB", "S_COMMIT_SETUP", "P_START", "P_WAIT", "U_ADD", "U_STEP", "S_COMMIT_STEP", "S_PROMOTE", "S_PUSH_DWELL",
    "S_DRAIN", "C_V0", "C_V0_WAIT", "C_SQ1", "C_SQ2", "C_N", "C_N_WAIT", "C_T1", "C_T2", "C_T", "Y_SETUP", "Y_WAIT",
];

/// Gray code of state number `k`.
pub const fn gray(k: usize) -> u64 {
    (k ^ (k >> 1)) as u64
}

/// The code of the state named `name` (a name in [`STATES`]).
pub fn state(name: &str) -> Constant<Bits<STATE_BITS>> {
    let k = STATES.iter().position(|s| *s == name).expect("state name");
    Constant::new(gray(k).into())
}
