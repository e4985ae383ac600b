//! Lowering: from the analysed workspace to the position-free program the machine runs
//! (`higraph_runtime::program`). One [`LoweredTest`] per `test` item: exactly the groups,
//! graphs and charts of its run list, every name resolved to a place, and a side table that
//! maps each [`Origin`] back to a file range (for failures, faults and traces).
//!
//! | module   | what |
//! |----------|------|
//! | `build`  | the lowering state (program, origins, cells, blocks) and groups |
//! | `graph`  | graphs: variables, states, transitions, STL → [`higraph_runtime::program::Instr`] |
//! | `chart`  | charts: cells, statements, actions, steps and chart transitions |
//! | `values` | types, constants (literal adaptation), addresses → places |
//! | `paths`  | test paths (`runtime.md` §5.3): the resolver the rules, the lowering and the editor share |
//! | `test`   | test statements, HG9101–HG9111 |
//! | `dump`   | a readable text form of a program (snapshots) |
//!
//! Operands are resolved by the analysis' own resolvers (`resolve.rs` for graphs, the chart
//! rules' `operands` for charts, the group rules' `actuals` for instance actuals), so that the
//! lowered program means what the diagnostics checked.

use std::collections::HashMap;

use higraph_runtime::Program;
use higraph_runtime::program::{Origin, RunEntry};
use higraph_syntax::{TextSize, ast, ast::AstNode};

use crate::db::{self, File, ItemKind, ItemLoc, Workspace};
use crate::diag::Diag;
use crate::{Analysis, Cancellable, Code, Diagnostic, RelatedInfo, Severity, TextRange};

mod build;
mod chart;
mod dump;
mod graph;
mod names;
mod paths;
mod test;
mod values;

pub(crate) use build::Lowerer;
pub use build::dump;
pub use paths::SegmentDef;
pub(crate) use paths::{PathTarget, Resolution, RunScope, ScopeChart, block_key, run_list};

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

/// The test items of a file: (item index, test node). Each node is the root of its own tree,
/// so its ranges are item-relative like every item's (callers add the item's offset).
fn file_tests(db: &dyn salsa::Database, file: File) -> Vec<(u32, ast::Test)> {
    db::item_nodes(db::parse(db, file))
        .enumerate()
        .filter_map(|(i, node)| {
            match ast::Item::cast(higraph_syntax::SyntaxNode::new_root(
                node.green().to_owned(),
            )) {
                Some(ast::Item::Test(test)) => Some((i as u32, test)),
                _ => None,
            }
        })
        .collect()
}

/// Lowers the run list into `lw`: the program's run entries, and per scope group and chart
/// its program index.
fn lower_run(
    lw: &mut build::Lowerer<'_>,
    run: &[(ItemKind, File, u32)],
) -> (Vec<RunEntry>, Vec<u32>, Vec<u32>) {
    let mut entries = Vec::new();
    let (mut groups, mut charts) = (Vec::new(), Vec::new());
    for &(kind, file, item) in run {
        match kind {
            ItemKind::Group => {
                if let Some(g) = lw.group(file, item) {
                    entries.push(RunEntry::Group(g));
                    groups.push(g);
                }
            }
            ItemKind::Chart => {
                if let Some(c) = lw.chart(file, item) {
                    entries.push(RunEntry::Chart(c));
                    charts.push(c);
                }
            }
            _ => {}
        }
    }
    (entries, groups, charts)
}

impl Analysis {
    /// Lowers every group and plain chart of the workspace (the default run list, in
    /// workspace order) without a test: what benchmarks and the simulator's own tests run.
    pub fn lower_workspace(&self) -> Cancellable<LoweredTest> {
        self.with_db(|db, ws| {
            let mut lw = build::Lowerer::new(db, ws);
            let run = paths::default_run(db, ws);
            let _ = lower_run(&mut lw, &run);
            LoweredTest {
                program: lw.program,
                origins: lw.origins,
            }
        })
    }

    /// Every `test` item, in workspace order (files in workspace order, items in text order).
    pub fn tests(&self) -> Cancellable<Vec<TestItem>> {
        self.with_db(|db, ws| {
            let mut out = Vec::new();
            for &file in ws.files(db) {
                let offsets = db::item_offsets(db, file);
                for (i, test) in file_tests(db, file) {
                    let offset = offsets.get(i as usize).copied().unwrap_or_default();
                    let Some(name) = test.name() else { continue };
                    let Some(token) = name.token() else { continue };
                    out.push(TestItem {
                        name: name.text(),
                        path: file.path(db).clone(),
                        range: TextRange::at(offset, test.syntax().text_range().len()),
                        name_range: token.text_range() + offset,
                    });
                }
            }
            out
        })
    }

    /// Lowers one test. `Err` is the HG9904 diagnostic (on the test's name, in its file) when
    /// the test cannot run because of error-level diagnostics (`runtime.md` §6).
    #[allow(clippy::result_large_err)] // the interface the runner is built against
    pub fn lower_test(
        &self,
        path: &str,
        name: &str,
    ) -> Cancellable<Result<LoweredTest, Diagnostic>> {
        let Some(file) = self.file(path) else {
            return Ok(Err(not_found(name, path)));
        };
        self.with_db(|db, ws| lower_test(db, ws, file, name, true))
            .map(|r| r.unwrap_or_else(|| Err(not_found(name, path))))
    }

    /// [`Analysis::lower_test`] without HG9904: lowers the test even when error-level
    /// diagnostics would keep it from running. For tests of the simulator whose inputs use
    /// constructs the checker does not know yet; the command-line runner never uses it.
    #[doc(hidden)]
    #[allow(clippy::result_large_err)]
    pub fn lower_test_ignoring_errors(
        &self,
        path: &str,
        name: &str,
    ) -> Cancellable<Result<LoweredTest, Diagnostic>> {
        let Some(file) = self.file(path) else {
            return Ok(Err(not_found(name, path)));
        };
        self.with_db(|db, ws| lower_test(db, ws, file, name, false))
            .map(|r| r.unwrap_or_else(|| Err(not_found(name, path))))
    }

    /// What each segment of the test path at `offset` in `path` names (for hover,
    /// definition, references and rename): the segments' ranges in the file and their
    /// definitions. Empty when the offset is in no test path or the path does not resolve.
    pub fn test_path_at(
        &self,
        path: &str,
        offset: TextSize,
    ) -> Cancellable<Vec<(TextRange, SegmentDef)>> {
        let Some(file) = self.file(path) else {
            return Ok(Vec::new());
        };
        self.with_db(|db, ws| test_path_at(db, ws, file, offset))
    }
}

impl Analysis {
    /// Every resolved test path segment of the file's tests, in text order, with what it
    /// names: what references, rename and semantic tokens need of test paths. Paths that do
    /// not resolve are left out (they carry HG9101–HG9103).
    pub fn test_path_segments(&self, path: &str) -> Cancellable<Vec<(TextRange, SegmentDef)>> {
        let Some(file) = self.file(path) else {
            return Ok(Vec::new());
        };
        self.with_db(|db, ws| {
            let offsets = db::item_offsets(db, file);
            let mut out = Vec::new();
            for (i, test) in file_tests(db, file) {
                let start = offsets.get(i as usize).copied().unwrap_or_default();
                with_resolver(db, ws, file, &test, |r| {
                    for path in test.syntax().descendants().filter_map(ast::TestPath::cast) {
                        if let Ok(res) = r.resolve(&path) {
                            out.extend(
                                res.segments
                                    .into_iter()
                                    .map(|(range, def)| (range + start, def)),
                            );
                        }
                    }
                });
            }
            out
        })
    }
}

/// Every test path of a test item with what its segments name (ranges in `test`'s own
/// coordinates; paths that do not resolve have no segments): what the editor's per-item uses
/// (`ide/defs.rs`) record of a test.
pub(crate) fn test_item_paths(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    test: &ast::Test,
) -> Vec<(ast::TestPath, Vec<(TextRange, SegmentDef)>)> {
    with_resolver(db, ws, file, test, |r| {
        test.syntax()
            .descendants()
            .filter_map(ast::TestPath::cast)
            .map(|path| {
                let segments = r.resolve(&path).map(|res| res.segments).unwrap_or_default();
                (path, segments)
            })
            .collect()
    })
}

/// The test path at `offset` of `file` and its resolution, segment ranges made absolute (for
/// hover); `None` outside test paths and for paths that do not resolve.
pub(crate) fn test_path_resolution_at(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Option<(ast::TestPath, TextRange, Resolution)> {
    let offsets = db::item_offsets(db, file);
    for (i, test) in file_tests(db, file) {
        let start = offsets.get(i as usize).copied().unwrap_or_default();
        if !TextRange::at(start, test.syntax().text_range().len()).contains_inclusive(offset) {
            continue;
        }
        let local = offset - start;
        let path = test
            .syntax()
            .descendants()
            .filter_map(ast::TestPath::cast)
            .find(|p| p.syntax().text_range().contains_inclusive(local))?;
        let mut res = with_resolver(db, ws, file, &test, |r| r.resolve(&path)).ok()?;
        for (range, _) in &mut res.segments {
            *range += start;
        }
        let whole = path.syntax().text_range() + start;
        return Some((path, whole, res));
    }
    None
}

fn not_found(name: &str, path: &str) -> Diagnostic {
    Diagnostic::new(
        Code::new("HG9904"),
        Severity::Error,
        TextRange::default(),
        format!("test {name} cannot run: there is no test {name} in {path}"),
    )
}

/// The resolver of a test (its run scope built from its run list).
fn with_resolver<T>(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    test: &ast::Test,
    f: impl FnOnce(paths::Resolver<'_>) -> T,
) -> T {
    let run = paths::run_list(db, ws, test);
    let scope = paths::RunScope::build(db, ws, &run);
    let resolver = paths::Resolver {
        db,
        ws,
        index: db::global_index(db, ws),
        mnemonic: db::file_mnemonic(db, ws, file),
        scope: &scope,
    };
    f(resolver)
}

/// HG9101–HG9111 of a test item (called by the rules for `test` items), and the global
/// symbols its paths name.
pub(crate) fn check_test(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    item: u32,
    test: &ast::Test,
) -> (Vec<Diag>, Vec<String>) {
    with_resolver(db, ws, file, test, |r| {
        let mut walker = test::TestWalker::new(r, file, item, test, None);
        walker.statements(test);
        (walker.diags, walker.used_symbols)
    })
}

#[allow(clippy::result_large_err)]
fn lower_test(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    name: &str,
    check: bool,
) -> Option<Result<LoweredTest, Diagnostic>> {
    let (item, test) = file_tests(db, file).into_iter().find(|(_, t)| {
        t.name()
            .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
    })?;
    let run = paths::run_list(db, ws, &test);
    if check && let Some(diag) = cannot_run(db, ws, file, item, &test, &run) {
        return Some(Err(diag));
    }
    let mut lw = build::Lowerer::new(db, ws);
    let (entries, groups, charts) = lower_run(&mut lw, &run);
    let scope = paths::RunScope::build(db, ws, &run);
    let resolver = paths::Resolver {
        db,
        ws,
        index: db::global_index(db, ws),
        mnemonic: db::file_mnemonic(db, ws, file),
        scope: &scope,
    };
    let placer = test::Placer {
        lw: &mut lw,
        groups,
        charts,
    };
    let mut walker = test::TestWalker::new(resolver, file, item, &test, Some(placer));
    let lowered = test::lower(&mut walker, &test, entries);
    drop(walker);
    lw.program.test = Some(lowered);
    Some(Ok(LoweredTest {
        program: lw.program,
        origins: lw.origins,
    }))
}

/// HG9904: error-level diagnostics in the test, the groups and charts it runs, the graphs
/// they instantiate, or any `symbols` or `block` item.
fn cannot_run(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    item: u32,
    test: &ast::Test,
    run: &[(ItemKind, File, u32)],
) -> Option<Diagnostic> {
    let index = db::global_index(db, ws);
    // The items that matter, with how the message names them.
    let mut items: Vec<(File, u32, String)> = Vec::new();
    let test_name = test.name().map(|n| n.text()).unwrap_or_default();
    items.push((file, item, format!("test {test_name}")));
    let mut graphs = Vec::new();
    for &(kind, f, i) in run {
        let name = index
            .items
            .iter()
            .find(|g| g.file == f && g.item == i)
            .map(|g| g.name.clone())
            .unwrap_or_default();
        match kind {
            ItemKind::Group => {
                items.push((f, i, format!("group {name}")));
                let loc = ItemLoc::new(db, f, i);
                if let Some(ast::Item::Group(group)) =
                    db::item_root(db, loc).and_then(ast::Item::cast)
                {
                    for instance in group.instances() {
                        if let Some(g) = instance.graph().and_then(|g| index.graph(&g.text()))
                            && !graphs.contains(&(g.file, g.item))
                        {
                            graphs.push((g.file, g.item));
                            items.push((g.file, g.item, format!("graph {}", g.name)));
                        }
                    }
                }
            }
            _ => items.push((f, i, format!("chart {name}"))),
        }
    }
    for &f in ws.files(db) {
        for (i, summary) in db::file_summary(db, f).items.iter().enumerate() {
            match summary.kind {
                ItemKind::Symbols => {
                    items.push((f, i as u32, format!("symbols in {}", f.path(db))))
                }
                ItemKind::BlockInterface => {
                    let reference = index
                        .block_interfaces
                        .iter()
                        .find(|b| b.file == f && b.item == i as u32)
                        .map(|b| b.reference.clone())
                        .unwrap_or_default();
                    items.push((f, i as u32, format!("block {reference}")));
                }
                _ => {}
            }
        }
    }
    // Errors per item, from each file's final diagnostics.
    let table = crate::check::output_file_table(db, ws);
    let mut by_file: HashMap<File, Vec<&Diagnostic>> = HashMap::new();
    let mut total = 0usize;
    let mut names = Vec::new();
    let mut related = Vec::new();
    for (f, i, label) in &items {
        let diags = by_file.entry(*f).or_insert_with(|| {
            crate::check::cached_file_diagnostics(db, ws, *f)
                .iter()
                .filter(|d| d.severity == Severity::Error)
                .collect()
        });
        let offset = db::item_offsets(db, *f)
            .get(*i as usize)
            .copied()
            .unwrap_or_default();
        let len = db::file_items(db, *f)
            .get(*i as usize)
            .map(|g| g.0.text_len())
            .unwrap_or_default();
        let range = TextRange::at(offset, len);
        let errors: Vec<&&Diagnostic> = diags
            .iter()
            .filter(|d| range.contains_range(d.range))
            .collect();
        if let Some(first) = errors.first() {
            total += errors.len();
            names.push(label.clone());
            related.push(RelatedInfo {
                file: table.ids.get(f).copied().unwrap_or(crate::FileId(0)),
                range: first.range,
                message: first.message.clone(),
            });
        }
    }
    if total == 0 {
        return None;
    }
    let offset = db::item_offsets(db, file)
        .get(item as usize)
        .copied()
        .unwrap_or_default();
    let range = test
        .name()
        .and_then(|n| n.token())
        .map_or(test.syntax().text_range(), |t| t.text_range())
        + offset;
    let mut diag = Diagnostic::new(
        Code::new("HG9904"),
        Severity::Error,
        range,
        format!(
            "test {test_name} cannot run: {total} error(s) in {}",
            names.join(", ")
        ),
    );
    diag.related = related;
    Some(diag)
}

fn test_path_at(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Vec<(TextRange, SegmentDef)> {
    let offsets = db::item_offsets(db, file);
    for (i, test) in file_tests(db, file) {
        let start = offsets.get(i as usize).copied().unwrap_or_default();
        let range = TextRange::at(start, test.syntax().text_range().len());
        if !range.contains_inclusive(offset) {
            continue;
        }
        let local = offset - start;
        let Some(path) = test
            .syntax()
            .descendants()
            .filter_map(ast::TestPath::cast)
            .find(|p| p.syntax().text_range().contains_inclusive(local))
        else {
            return Vec::new();
        };
        return with_resolver(db, ws, file, &test, |r| match r.resolve(&path) {
            Ok(res) => res
                .segments
                .into_iter()
                .map(|(range, def)| (range + start, def))
                .collect(),
            Err(_) => Vec::new(),
        });
    }
    Vec::new()
}
