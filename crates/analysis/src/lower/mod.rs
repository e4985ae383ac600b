//! Lowering: from the analysed workspace to the position-free program the machine runs
//! (`higraph_runtime::program`). One [`LoweredTest`] per `test` item: exactly the groups,
//! graphs and charts of its run list, every name resolved to a place, and a side table that
//! maps each [`Origin`] back to a file range (for failures, faults and traces).

use higraph_runtime::Program;
use higraph_runtime::program::Origin;

use crate::{Analysis, Cancellable, Diagnostic, TextRange};

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
#[derive(Debug, Clone)]
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
