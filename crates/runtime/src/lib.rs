//! The simulated machine of `runtime.md`: memory, registers, timers and counters (`machine`),
//! the STL interpreter (`stl`), one group call (`group`), one chart cycle (`chart`, PCS 7 and IEC 61131-3
//! profiles), the standard function blocks of IEC charts (`fb`) and the test
//! runner with its traces (`test`, `trace`).
//!
//! The input is a [`program::Program`]: a lowered, resolved, position-free model produced by
//! `higraph-analysis` (`lower`). This crate knows neither salsa nor the language server; it
//! does no I/O. Everything is deterministic: the same program gives the same trace, byte for
//! byte.

pub mod chart;
pub mod eval;
pub mod fb;
pub mod group;
pub mod machine;
pub mod program;
pub mod sim;
pub mod stl;
pub mod test;
pub mod trace;
pub mod value;
pub mod vcd;

pub use machine::{Fault, Machine};
pub use program::Program;
pub use value::{Ty, Value};
