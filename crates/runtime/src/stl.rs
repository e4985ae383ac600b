//! The STL interpreter (`runtime.md` §3).

use crate::machine::{Fault, Machine};
use crate::program::{Block, Place};
use crate::value::Const;

/// Runs one instruction block (§3.1) with the running instance's variable binding. In the
/// RLO-0 pass (`rlo0`) the block starts with RLO = STA = 0. Returns the RLO at the block's end.
pub fn run_block(
    m: &mut Machine,
    binding: &[Place],
    block: &Block,
    rlo0: bool,
) -> Result<bool, Fault> {
    let _ = (m, binding, block, rlo0);
    todo!("stl: §3")
}

/// The 32-bit pattern `L` loads for a constant (§1.1).
pub fn load_pattern(c: &Const) -> u32 {
    let _ = c;
    todo!("stl: §1.1")
}
