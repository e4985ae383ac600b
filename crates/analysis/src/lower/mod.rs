//! Lowering: from the analysed workspace to the position-free program the machine runs
//! (`higraph_runtime::program`). One [`LoweredTest`] per `test` item: exactly the groups,
//! graphs and charts of its run list, every name resolved to a place, and a side table that
//! maps each [`Origin`] back to a file range (for failures, faults and traces).

use higraph_runtime::Program;
use higraph_runtime::program::{Origin, RunEntry};

use crate::db::ItemKind;
use crate::{Analysis, Cancellable, Diagnostic, TextRange};

mod build;
mod chart;
mod dump;
mod graph;
mod values;

pub use build::dump;

/// A `test` item of the workspace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TestItem {
    pub name: String,
    /// The workspace path of its file.
    pub path: String,
    /// The whole item.
    pub range: TextRange,
    /// The name after `test`.
    pub name_range: TextRange,
}

/// A test ready to run.
#[derive(Debug, Clone, Default)]
pub struct LoweredTest {
    pub program: Program,
    /// `origins[o]` is the file path and range of `Origin(o)`.
    pub origins: Vec<(String, TextRange)>,
}

impl LoweredTest {
    /// The file and range of an origin (`None` for [`Origin::NONE`]).
    pub fn origin(&self, origin: Origin) -> Option<&(String, TextRange)> {
        self.origins.get(origin.0 as usize)
    }
}

impl Analysis {
    /// Lowers every group and plain chart of the workspace (the default run list, in
    /// workspace order) without a test: what benchmarks and the simulator's own tests run.
    pub fn lower_workspace(&self) -> Cancellable<LoweredTest> {
        self.with_db(|db, ws| {
            let mut lw = build::Lowerer::new(db, ws);
            let mut run = Vec::new();
            for (kind, file, item) in lw.default_run() {
                match kind {
                    ItemKind::Group => run.extend(lw.group(file, item).map(RunEntry::Group)),
                    ItemKind::Chart => {
                        run.extend(lw.chart(file, item).map(|(c, _)| RunEntry::Chart(c)))
                    }
                    _ => {}
                }
            }
            let _ = run;
            LoweredTest {
                program: lw.program,
                origins: lw.origins,
            }
        })
    }

    /// Every `test` item, in workspace order (files in workspace order, items in text order).
    pub fn tests(&self) -> Cancellable<Vec<TestItem>> {
        todo!("lower: test items")
    }

    /// Lowers one test. `Err` is the HG9904 diagnostic (on the test's name, in its file) when
    /// the test cannot run because of error-level diagnostics (`runtime.md` §6).
    pub fn lower_test(
        &self,
        path: &str,
        name: &str,
    ) -> Cancellable<Result<LoweredTest, Diagnostic>> {
        let _ = (path, name);
        todo!("lower: §5")
    }
}
