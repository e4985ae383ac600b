//! `higraph-lsp build` (the export contract): which groups and charts a build covers, the
//! diagnostics only `build` raises (HG81xx), and the files it writes. The analysis collects
//! (lowering groups, reading charts), `higraph_export` writes bytes, the CLI and the server put
//! them on disk.
//!
//! | module    | what |
//! |-----------|------|
//! | `awl`     | one group → its STEP 7 source (through the lowering and `higraph_export::awl`) |
//! | `plcopen` | the charts → one PLCopen XML document (`higraph_export::plcopen`) |
//! | `rules`   | HG81xx: what `build` needs beyond `check` |

use crate::db::{File, Workspace};
use crate::{Analysis, Cancellable, Diagnostic, TextRange};

mod awl;
mod plcopen;
pub(crate) mod rules;

/// What `build` generates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Target {
    /// STEP 7 sources for the groups (the default).
    #[default]
    Awl,
    /// PLCopen XML for the charts.
    Plcopen,
    All,
}

impl Target {
    pub fn awl(self) -> bool {
        matches!(self, Target::Awl | Target::All)
    }
    pub fn plcopen(self) -> bool {
        matches!(self, Target::Plcopen | Target::All)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BuildOptions {
    pub target: Target,
    /// Also generate an `ORGANIZATION_BLOCK OB 1` calling each group's FC.
    pub with_ob1: bool,
    /// Absolute addresses and block numbers instead of symbols (no symbol table needed).
    pub absolute: bool,
}

/// A file `build` writes, relative to the output folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BuildFile {
    pub name: String,
    pub bytes: Vec<u8>,
}

#[derive(Debug, Clone, Default)]
pub struct BuildResult {
    /// The diagnostics only `build` raises (HG81xx), by workspace path. `check`'s own
    /// diagnostics are not repeated here.
    pub diagnostics: Vec<(String, Diagnostic)>,
    /// Workspace paths with an error-level diagnostic (`check`'s or `build`'s) that stop the
    /// build; empty when it went through.
    pub refused: Vec<String>,
    /// How many groups and charts were built.
    pub groups: usize,
    pub charts: usize,
    /// The files, in a stable order; empty when the build was refused.
    pub files: Vec<BuildFile>,
}

/// A group or chart a build can cover (for "Build this group/chart").
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BuildItem {
    pub chart: bool,
    pub name: String,
    /// The item's header (the keyword and the name).
    pub range: TextRange,
}

impl Analysis {
    /// Builds every group and chart of the files whose workspace paths start with one of
    /// `paths` (all of the workspace when `paths` is empty).
    pub fn build(&self, paths: &[String], options: &BuildOptions) -> Cancellable<BuildResult> {
        self.with_db(|db, ws| build(db, ws, paths, options))
    }

    /// Like [`Analysis::build`] for one group or chart, by name.
    pub fn build_item(
        &self,
        chart: bool,
        name: &str,
        options: &BuildOptions,
    ) -> Cancellable<BuildResult> {
        self.with_db(|db, ws| build_item(db, ws, chart, name, options))
    }

    /// The groups and charts of a file, for code actions.
    pub fn build_items(&self, path: &str) -> Cancellable<Vec<BuildItem>> {
        let Some(file) = self.file(path) else {
            return Ok(Vec::new());
        };
        self.with_db(|db, ws| build_items(db, ws, file))
    }
}

fn build(
    db: &dyn salsa::Database,
    ws: Workspace,
    paths: &[String],
    options: &BuildOptions,
) -> BuildResult {
    let _ = (
        db,
        ws,
        paths,
        options,
        awl::group_source,
        plcopen::charts_xml,
    );
    let _ = rules::diagnostics;
    todo!("build")
}

fn build_item(
    db: &dyn salsa::Database,
    ws: Workspace,
    chart: bool,
    name: &str,
    options: &BuildOptions,
) -> BuildResult {
    let _ = (db, ws, chart, name, options);
    todo!("build_item")
}

fn build_items(db: &dyn salsa::Database, ws: Workspace, file: File) -> Vec<BuildItem> {
    let _ = (db, ws, file);
    todo!("build_items")
}
