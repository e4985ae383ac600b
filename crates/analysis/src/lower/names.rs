//! The lowering's side table of names for `build`: what the position-free program forgets but
//! a generated STEP 7 source must say as the text did — which operands were written as
//! symbols (and which symbol), constants as written, each group instance's own cells before
//! its actuals replaced them. Filled as the lowering goes; tests and benchmarks ignore it.

use std::collections::HashMap;

use higraph_runtime::program::{CellId, GraphId, Origin, VarIdx};

/// Where an operand is: the instruction's origin and a slot (0 the instruction's own operand,
/// `1 + i` the actual of its `i`-th `CALL` parameter).
pub(crate) type Slot = (Origin, u32);

#[derive(Debug, Clone, Default)]
pub(crate) struct LowerNames {
    /// Per group of the program: per instance, its own cell of every variable.
    pub group_own: Vec<Vec<Vec<CellId>>>,
    /// Per group: `(instance, variable)` → the symbol its actual was written as.
    pub actual_symbols: Vec<HashMap<(u32, VarIdx), String>>,
    /// Operands written as (or resolved through) a symbol: the symbol's name.
    pub operand_symbols: HashMap<Slot, String>,
    /// Constant operands as written, white space removed.
    pub literals: HashMap<Slot, String>,
    /// `wait`/`supervise` operands written as a symbol: (graph, state, supervise) → name.
    pub time_symbols: HashMap<(GraphId, u16, bool), String>,
    /// `CALL FB n, DB m`: the instance data block as written, by the call's origin.
    pub call_dbs: HashMap<Origin, String>,
}
