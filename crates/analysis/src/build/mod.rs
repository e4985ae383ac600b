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

use std::collections::{HashMap, HashSet};

use higraph_syntax::{SyntaxKind, ast};

use crate::db::{self, File, ItemKind, ItemLoc, Workspace};
use crate::{Analysis, Cancellable, Diagnostic, Severity, TextRange, TextSize, check, index};

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
    /// `check`'s error- and warning-level diagnostics of the items built and of what they
    /// depend on (the graphs their instances use, `symbols` and `block` items, imported symbol
    /// tables, `higraph.toml`), by workspace path, in workspace order: what `build` prints
    /// besides [`BuildResult::diagnostics`]. The errors among them stop the build.
    pub checked: Vec<(String, Diagnostic)>,
    /// Why the files could not be generated although no diagnostic stopped the build (a bug
    /// guard: the rules refuse such input first); the file concerned is in `refused`.
    pub failure: Option<String>,
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

/// The file name of the symbol table a build writes beside the sources (not with `--absolute`).
pub const SYMBOLS_FILE: &str = "symbols.sdf";
/// The file name of the PLCopen document of the charts.
pub const CHARTS_FILE: &str = "charts.xml";

/// Does the workspace path `path` lie under one of `paths` (a file path itself, or a folder
/// path with `/` separators)? An empty list, `""` and `"."` stand for the whole workspace.
fn under(path: &str, paths: &[String]) -> bool {
    paths.is_empty()
        || paths.iter().any(|p| {
            let p = p.trim_end_matches('/');
            p.is_empty()
                || p == "."
                || path == p
                || (path.starts_with(p) && path.as_bytes().get(p.len()) == Some(&b'/'))
        })
}

fn build(
    db: &dyn salsa::Database,
    ws: Workspace,
    paths: &[String],
    options: &BuildOptions,
) -> BuildResult {
    let mut groups = Vec::new();
    let mut charts = Vec::new();
    let mut selected = Vec::new();
    for &file in ws.files(db) {
        if !under(file.path(db), paths) {
            continue;
        }
        selected.push(file);
        for (i, item) in db::file_summary(db, file).items.iter().enumerate() {
            match item.kind {
                ItemKind::Group if options.target.awl() => groups.push((file, i as u32)),
                ItemKind::Chart if options.target.plcopen() => charts.push((file, i as u32)),
                _ => {}
            }
        }
    }
    run(db, ws, &groups, &charts, &selected, options)
}

fn build_item(
    db: &dyn salsa::Database,
    ws: Workspace,
    chart: bool,
    name: &str,
    options: &BuildOptions,
) -> BuildResult {
    let kind = if chart {
        ItemKind::Chart
    } else {
        ItemKind::Group
    };
    let Some(found) = db::global_index(db, ws)
        .items_named(name)
        .find(|item| item.kind == kind)
    else {
        return BuildResult::default();
    };
    // The item decides the target: a group gives its source, a chart the PLCopen document.
    let options = BuildOptions {
        target: if chart { Target::Plcopen } else { Target::Awl },
        ..*options
    };
    let item = [(found.file, found.item)];
    let none: &[(File, u32)] = &[];
    if chart {
        run(db, ws, none, &item, &[found.file], &options)
    } else {
        run(db, ws, &item, none, &[found.file], &options)
    }
}

fn build_items(db: &dyn salsa::Database, _ws: Workspace, file: File) -> Vec<BuildItem> {
    let offsets = db::item_offsets(db, file);
    let mut out = Vec::new();
    for (i, item) in db::file_summary(db, file).items.iter().enumerate() {
        let chart = match item.kind {
            ItemKind::Group => false,
            ItemKind::Chart => true,
            _ => continue,
        };
        let (Some(name), Some(name_range)) = (&item.name, item.name_range) else {
            continue;
        };
        let offset = offsets.get(i).copied().unwrap_or_default();
        // From the item's keyword (the first token that is not trivia) to the end of its name.
        let keyword = db::item_root(db, ItemLoc::new(db, file, i as u32))
            .and_then(|root| {
                root.descendants_with_tokens()
                    .filter_map(|e| e.into_token())
                    .find(|t| !t.kind().is_trivia() && t.kind() != SyntaxKind::LEX_ERROR)
            })
            .map_or(name_range.start(), |t| t.text_range().start());
        let start = keyword.min(name_range.start());
        out.push(BuildItem {
            chart,
            name: name.clone(),
            range: TextRange::new(start, name_range.end()) + offset,
        });
    }
    out
}

/// Builds `groups` and `charts` (in that order, as given): refuses when they or what they
/// depend on have errors, else generates the files. `selected`: the files the build covers
/// (errors outside every item of them stop it too).
fn run(
    db: &dyn salsa::Database,
    ws: Workspace,
    groups: &[(File, u32)],
    charts: &[(File, u32)],
    selected: &[File],
    options: &BuildOptions,
) -> BuildResult {
    let mut result = BuildResult {
        groups: groups.len(),
        charts: charts.len(),
        ..BuildResult::default()
    };
    if groups.is_empty() && charts.is_empty() {
        return result;
    }
    let mut refused: HashSet<File> = HashSet::new();

    // check's diagnostics of what the build reads.
    let regions = regions(db, ws, groups, charts, selected);
    for (file, region) in &regions {
        let diagnostics = check::cached_file_diagnostics(db, ws, *file);
        for diagnostic in diagnostics {
            if diagnostic.severity > Severity::Warning || !region.covers(diagnostic.range) {
                continue;
            }
            if diagnostic.severity == Severity::Error {
                refused.insert(*file);
            }
            let mut diagnostic = diagnostic.clone();
            check::resolve_fixes(db, ws, &mut diagnostic.fixes);
            result.checked.push((file.path(db).clone(), diagnostic));
        }
    }

    // build's own rules.
    let target = match (groups.is_empty(), charts.is_empty()) {
        (false, false) => Target::All,
        (true, _) => Target::Plcopen,
        (_, true) => Target::Awl,
    };
    let mut own = rules::diagnostics(db, ws, groups, charts, target);
    let order: HashMap<File, usize> = ws
        .files(db)
        .iter()
        .enumerate()
        .map(|(i, &f)| (f, i))
        .collect();
    // Stable: by file in workspace order, then position, as the rules gave them otherwise.
    own.sort_by_key(|(file, d)| {
        (
            order.get(file).copied().unwrap_or(usize::MAX),
            d.range.start(),
        )
    });
    for (file, diagnostic) in own {
        if diagnostic.severity == Severity::Error {
            refused.insert(file);
        }
        result.diagnostics.push((file.path(db).clone(), diagnostic));
    }

    if refused.is_empty() {
        match generate(db, ws, groups, charts, options) {
            Ok(files) => result.files = files,
            Err((file, why)) => {
                refused.insert(file);
                result.failure = Some(why);
            }
        }
    }
    let mut refused: Vec<File> = refused.into_iter().collect();
    refused.sort_by_key(|f| {
        (
            order.get(f).copied().unwrap_or(usize::MAX),
            f.path(db).clone(),
        )
    });
    result.refused = refused.iter().map(|f| f.path(db).clone()).collect();
    result
}

/// The generated files: one source per group (build order), the charts' document, the symbol
/// table. `Err` names the file of a group the generator could not write, and why (a bug
/// guard: errors are refused before).
fn generate(
    db: &dyn salsa::Database,
    ws: Workspace,
    groups: &[(File, u32)],
    charts: &[(File, u32)],
    options: &BuildOptions,
) -> Result<Vec<BuildFile>, (File, String)> {
    let mut files = Vec::new();
    let mut names: HashSet<String> = HashSet::new();
    let mut symbols: Vec<higraph_export::sdf::Symbol> = Vec::new();
    for &(file, item) in groups {
        let source = awl::group_source(db, ws, file, item, options).map_err(|why| (file, why))?;
        // Two files whose names differ only in letter case would be one file on some
        // systems; group names are unique case-insensitively, so this is a bug guard too.
        if !names.insert(source.file_name.to_ascii_uppercase()) {
            return Err((
                file,
                format!("two groups would both write {}", source.file_name),
            ));
        }
        symbols.extend(source.symbols);
        files.push(BuildFile {
            name: source.file_name,
            bytes: source.bytes,
        });
    }
    if !charts.is_empty() {
        files.push(BuildFile {
            name: CHARTS_FILE.to_owned(),
            bytes: plcopen::charts_xml(db, ws, charts),
        });
    }
    if let (Some(&(file, _)), false) = (groups.first(), options.absolute) {
        let bytes = higraph_export::sdf::write(&symbol_union(symbols))
            .map_err(|why| (file, format!("{SYMBOLS_FILE}: {why}")))?;
        files.push(BuildFile {
            name: SYMBOLS_FILE.to_owned(),
            bytes,
        });
    }
    Ok(files)
}

/// The groups' symbols once each (by name, case-insensitively; the first wins), sorted by
/// name so the table does not depend on which group uses a symbol first.
fn symbol_union(mut symbols: Vec<higraph_export::sdf::Symbol>) -> Vec<higraph_export::sdf::Symbol> {
    // A stable sort keeps the first of equal names first.
    symbols.sort_by_cached_key(|s| index::key(&s.name));
    symbols.dedup_by(|later, first| index::key(&later.name) == index::key(&first.name));
    symbols
}

/// Which diagnostics of a file concern a build.
#[derive(Debug, Default)]
struct Region {
    /// Every diagnostic of the file (an imported symbol table, `higraph.toml`).
    whole: bool,
    /// Diagnostics outside every item of the file (a file the build covers).
    outside_items: bool,
    /// The items' ranges (absolute, in text order).
    items: Vec<TextRange>,
    /// All items' ranges in text order, when `outside_items`.
    all_items: Vec<TextRange>,
}

impl Region {
    /// Item ranges are in text order and do not overlap, so the item that may hold a range is
    /// found by binary search (a file of many items and many diagnostics stays fast).
    fn covers(&self, range: TextRange) -> bool {
        let holder = |items: &[TextRange]| {
            let after = items.partition_point(|item| item.start() <= range.start());
            after.checked_sub(1).and_then(|i| items.get(i)).copied()
        };
        self.whole
            || holder(&self.items).is_some_and(|item| item.contains_range(range))
            || (self.outside_items
                && !holder(&self.all_items).is_some_and(|item| item.contains(range.start())))
    }
}

fn item_range(db: &dyn salsa::Database, file: File, item: u32) -> TextRange {
    let offset = db::item_offsets(db, file)
        .get(item as usize)
        .copied()
        .unwrap_or_default();
    let len = db::file_items(db, file)
        .get(item as usize)
        .map_or(TextSize::from(0), |g| g.0.text_len());
    TextRange::at(offset, len)
}

/// What a build reads, by file in output order: the items built, the graphs their instances
/// use, every `symbols` and `block` item, the imported symbol tables and `higraph.toml` (as
/// the test runner's HG9904 counts errors, plus the tables and the configuration), and what
/// lies outside every item in the files the build covers.
fn regions(
    db: &dyn salsa::Database,
    ws: Workspace,
    groups: &[(File, u32)],
    charts: &[(File, u32)],
    selected: &[File],
) -> Vec<(File, Region)> {
    let index = db::global_index(db, ws);
    let mut items: HashSet<(File, u32)> = HashSet::new();
    items.extend(groups.iter().copied());
    items.extend(charts.iter().copied());
    for &(file, item) in groups {
        let loc = ItemLoc::new(db, file, item);
        if let Some(ast::Item::Group(group)) = db::item_root(db, loc).and_then(ast::Item::cast) {
            for instance in group.instances() {
                if let Some(graph) = instance.graph().and_then(|g| index.graph(&g.text())) {
                    items.insert((graph.file, graph.item));
                }
            }
        }
    }
    let selected: HashSet<File> = selected.iter().copied().collect();
    let mut out = Vec::new();
    for &file in ws.files(db) {
        let mut region = Region::default();
        for (i, summary) in db::file_summary(db, file).items.iter().enumerate() {
            let i = i as u32;
            let relevant = items.contains(&(file, i))
                || matches!(summary.kind, ItemKind::Symbols | ItemKind::BlockInterface);
            if relevant {
                region.items.push(item_range(db, file, i));
            }
        }
        if selected.contains(&file) {
            region.outside_items = true;
            region.all_items = (0..db::file_summary(db, file).items.len() as u32)
                .map(|i| item_range(db, file, i))
                .collect();
        }
        if !region.items.is_empty() || region.outside_items {
            out.push((file, region));
        }
    }
    let whole = || Region {
        whole: true,
        ..Region::default()
    };
    for import in ws.imports(db) {
        if let Ok(file) = import.file {
            out.push((file, whole()));
        }
    }
    if let Some(config) = ws.config_file(db) {
        out.push((config, whole()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_cover_their_items_and_what_lies_outside_every_item() {
        let r = |a: u32, b: u32| TextRange::new(TextSize::from(a), TextSize::from(b));
        let region = Region {
            items: vec![r(10, 20), r(40, 50)],
            outside_items: true,
            all_items: vec![r(10, 20), r(25, 35), r(40, 50)],
            ..Region::default()
        };
        assert!(region.covers(r(12, 14)));
        assert!(region.covers(r(40, 50)));
        assert!(!region.covers(r(18, 22)), "runs out of its item");
        assert!(!region.covers(r(26, 30)), "in an item that is not built");
        assert!(region.covers(r(21, 23)), "between items");
        assert!(region.covers(r(0, 1)), "before every item");
        assert!(region.covers(r(60, 61)), "after every item");
        let whole = Region {
            whole: true,
            ..Region::default()
        };
        assert!(whole.covers(r(26, 30)));
    }

    #[test]
    fn paths_select_files_and_folders() {
        let p = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert!(under("a/b.higraph", &[]));
        assert!(under("a/b.higraph", &p(&["."])));
        assert!(under("a/b.higraph", &p(&["a"])));
        assert!(under("a/b.higraph", &p(&["a/"])));
        assert!(under("a/b.higraph", &p(&["a/b.higraph"])));
        assert!(!under("ab/b.higraph", &p(&["a"])));
        assert!(!under("a/b.higraph", &p(&["a/b"])));
        assert!(!under("c.higraph", &p(&["a", "b"])));
    }

    #[test]
    fn the_symbol_table_holds_each_name_once_sorted() {
        let s = |name: &str, address: &str| higraph_export::sdf::Symbol {
            name: name.to_owned(),
            address: address.to_owned(),
            ty: "BOOL".to_owned(),
            comment: String::new(),
        };
        let union = symbol_union(vec![s("b", "E 0.1"), s("A", "E 0.0"), s("B", "E 0.1")]);
        let names: Vec<&str> = union.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["A", "b"]);
    }
}
