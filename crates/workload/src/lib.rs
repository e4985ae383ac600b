//! Deterministic generators of the benchmark workloads of `tooling.md` §7.
//!
//! * [`max_graph`] — one file with one graph at the limits: 255 states (0..254), 4090
//!   transitions (the startup any-transition, a fault any-transition and 4088 normal or return
//!   transitions, 3–6 STL statements each except the one-line startup transition).
//! * [`max_group`] — 20 graphs and one group of 255 instances of them, every message wired.
//!   The rename target of the benchmark is described by [`MAX_GROUP_RENAME`].
//! * [`plant`] — 300 graphs in 20 groups (one per area folder, one area in international
//!   mnemonics), 10 charts with parallel and alternative branches, jumps and loops, block
//!   interfaces and one `symbols` table of exactly 5000 symbols.
//!
//! [`iec_chart`] generates one random IEC 61131-3 chart from a seed (the PLCopen round trip's
//! input).
//!
//! [`scaling`] generates the inputs of the scaling families (one size parameter each).
//!
//! The output depends only on the seed: the PRNG is a built-in SplitMix64 and nothing iterates
//! over a hash map. All text is syntactically valid (`tests/valid.rs` parses it) and is meant to
//! be clean for the semantic rules too (see the module docs of `graph`), so a `check` benchmark
//! measures the checker rather than diagnostic rendering.

mod chart;
mod graph;
mod group;
mod iec;
mod mnemonic;
mod rng;
pub mod scaling;
mod symbols;
mod workloads;

pub use iec::{iec_chart, iec_chart_with};
pub use workloads::{max_graph, max_group, plant};

/// The message variable of [`max_group`] that every one of its 255 instances refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenameTarget {
    /// Workspace-relative path of the file that declares the variable.
    pub file: &'static str,
    /// The graph that declares it (`msg in`, in its `in_out` section).
    pub graph: &'static str,
    /// The variable.
    pub variable: &'static str,
    /// The one instance of `graph` in the group; every instance, this one included, wires its
    /// outgoing message `OM_Bereit` to `Leitstand.IM_Bereit`.
    pub instance: &'static str,
    /// Path of the group file.
    pub group_file: &'static str,
}

/// Renaming `IM_Bereit` of graph `Zentrale` touches its declaration, its uses inside
/// `Zentrale`, and the actual `OM_Bereit := Leitstand.IM_Bereit;` of all 255 instances.
pub const MAX_GROUP_RENAME: RenameTarget = RenameTarget {
    file: "graphs/Zentrale.higraph",
    graph: "Zentrale",
    variable: "IM_Bereit",
    instance: "Leitstand",
    group_file: "group.higraph",
};

/// Number of symbols in the `symbols` table of [`plant`].
pub const PLANT_SYMBOLS: usize = 5000;
