//! The final diagnostics of each file: syntax errors, the rules' diagnostics of its items, and
//! the workspace-wide diagnostics that land in it — with severities from the configuration,
//! inline suppressions applied (§1.4b), absolute ranges and output file ids.

use std::collections::{HashMap, HashSet};

use higraph_syntax::{TextRange, TextSize};

use crate::{
    Code, Diagnostic, DiagnosticTag, FileContents, FileId, Fix, LineIndex, PendingRename,
    RelatedInfo, Severity, TextEdit,
    db::{self, File, ItemLoc, Workspace},
    diag::Diag,
    registry, sdf, suppress,
};

/// Every file the diagnostics may refer to, in output order: the `.higraph` files, the loaded
/// import files, then `higraph.toml`. `FileId(i)` is the `i`th.
pub fn output_files(db: &dyn salsa::Database, ws: Workspace) -> Vec<File> {
    output_file_table(db, ws).files.clone()
}

/// The output files with their ids and which of them are sources, computed once per
/// workspace revision (each file's diagnostics need them; rebuilding them per file would cost
/// the square of the number of files).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct OutputFiles {
    pub files: Vec<File>,
    pub ids: HashMap<File, FileId>,
    pub sources: HashSet<File>,
    /// The source files by path.
    pub source_paths: HashMap<String, File>,
}

#[salsa::tracked(returns(ref))]
pub fn output_file_table(db: &dyn salsa::Database, ws: Workspace) -> OutputFiles {
    let mut files = ws.files(db).clone();
    files.extend(
        ws.imports(db)
            .iter()
            .filter_map(|i| i.file.as_ref().ok().copied()),
    );
    files.extend(ws.config_file(db));
    let ids = files
        .iter()
        .enumerate()
        .map(|(i, &f)| (f, FileId(i as u32)))
        .collect();
    OutputFiles {
        ids,
        sources: ws.files(db).iter().copied().collect(),
        source_paths: ws
            .files(db)
            .iter()
            .map(|&f| (f.path(db).clone(), f))
            .collect(),
        files,
    }
}

/// The diagnostics of every output file.
pub fn all_diagnostics(db: &dyn salsa::Database, ws: Workspace) -> Vec<(FileId, Vec<Diagnostic>)> {
    output_file_table(db, ws)
        .files
        .iter()
        .enumerate()
        .map(|(i, &file)| {
            (
                FileId(i as u32),
                cached_file_diagnostics(db, ws, file).clone(),
            )
        })
        .collect()
}

/// The diagnostics of one file, cached: after an edit only the files whose inputs changed are
/// converted again (severities, suppressions, absolute positions), not the whole workspace.
#[salsa::tracked(returns(ref))]
pub fn cached_file_diagnostics(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
) -> Vec<Diagnostic> {
    file_diagnostics(db, ws, file, &output_file_table(db, ws).ids)
}

/// The positions in [`db::workspace_diagnostics`] of the diagnostics of each file, and the
/// problems of the imported tables per file (positions: table, problem).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
struct WorkspaceDiagsByFile {
    workspace: HashMap<File, Vec<usize>>,
    imports: HashMap<File, Vec<(usize, usize)>>,
}

#[salsa::tracked(returns(ref))]
fn workspace_diags_by_file(db: &dyn salsa::Database, ws: Workspace) -> WorkspaceDiagsByFile {
    let mut by_file = WorkspaceDiagsByFile::default();
    for (t, table) in sdf::imported_tables(db, ws).iter().enumerate() {
        for (p, problem) in table.problems.iter().enumerate() {
            by_file
                .imports
                .entry(problem.at.file)
                .or_default()
                .push((t, p));
        }
    }
    for (i, diag) in db::workspace_diagnostics(db, ws).iter().enumerate() {
        by_file.workspace.entry(diag.at.file).or_default().push(i);
    }
    by_file
}

/// The workspace-wide diagnostics (imported tables' problems first, then
/// [`db::workspace_diagnostics`]) that land in one file. Equal as long as that file's share is,
/// so an edit elsewhere does not convert this file's diagnostics again.
#[salsa::tracked(returns(ref))]
fn file_workspace_diags(db: &dyn salsa::Database, ws: Workspace, file: File) -> Vec<Diag> {
    let by_file = workspace_diags_by_file(db, ws);
    let tables = sdf::imported_tables(db, ws);
    let all = db::workspace_diagnostics(db, ws);
    let mut out = Vec::new();
    for &(t, p) in by_file.imports.get(&file).into_iter().flatten() {
        out.extend(
            tables
                .get(t)
                .and_then(|table| table.problems.get(p))
                .cloned(),
        );
    }
    for &i in by_file.workspace.get(&file).into_iter().flatten() {
        out.extend(all.get(i).cloned());
    }
    out
}

/// The diagnostics of one file.
pub fn file_diagnostics(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    ids: &HashMap<File, FileId>,
) -> Vec<Diagnostic> {
    let contents = file.contents(db);
    let own = ids.get(&file).copied().unwrap_or(FileId(0));
    match &**contents {
        FileContents::NotUtf8 {
            invalid_offset,
            invalid_len,
            ..
        } => {
            let start = size(*invalid_offset);
            let len = size(invalid_len * char::REPLACEMENT_CHARACTER.len_utf8());
            return vec![Diagnostic::new(
                Code::INVALID_UTF8,
                Severity::Error,
                TextRange::at(start, len),
                format!("file is not valid UTF-8 (invalid byte at offset {invalid_offset})"),
            )];
        }
        FileContents::Unreadable { reason } => {
            return vec![Diagnostic::new(
                Code::UNREADABLE_FILE,
                Severity::Error,
                TextRange::empty(TextSize::from(0)),
                format!("cannot read file: {reason}"),
            )];
        }
        FileContents::Text(_) => {}
    }
    let config = ws.config(db);
    let mut diags: Vec<&Diag> = Vec::new();
    let is_source = output_file_table(db, ws).sources.contains(&file);
    let mut out = Vec::new();
    let mut config_problems = Vec::new();
    if is_source {
        let parse = db::parse(db, file);
        out.extend(
            parse
                .errors()
                .iter()
                .map(|e| Diagnostic::from_syntax_error(own, e)),
        );
        for index in 0..db::file_summary(db, file).items.len() {
            diags.extend(db::item_diagnostics(
                db,
                ws,
                ItemLoc::new(db, file, index as u32),
            ));
        }
    }
    if ws.config_file(db) == Some(file) {
        for (range, problem) in &config.problems {
            config_problems.push(Diag::new(
                "HG6101",
                crate::diag::Loc::in_file(file, *range),
                format!("higraph.toml: {problem}"),
            ));
        }
    }
    diags.extend(config_problems.iter());
    diags.extend(file_workspace_diags(db, ws, file).iter());

    let text = contents.text();
    // Only a file with `higraph-allow` comments needs lines (a line index is O(file)).
    let line_index = (is_source && suppress::may_allow(text)).then(|| LineIndex::new(text));
    let (allows, unknown_codes) = match &line_index {
        Some(line_index) => suppress::allows(text, db::parse(db, file), line_index),
        None => Default::default(),
    };
    let hg6104: Vec<Diag> = unknown_codes
        .iter()
        .map(|u| {
            Diag::new(
                "HG6104",
                crate::diag::Loc::in_file(file, u.range),
                format!("unknown diagnostic code '{}' in higraph-allow", u.code),
            )
        })
        .collect();
    diags.extend(hg6104.iter());

    for diag in diags {
        let code = diag.code.as_str();
        let Some(severity) = config.severity(code) else {
            continue;
        };
        let range = db::absolute_range(db, &diag.at);
        if let Some(line_index) = &line_index
            && suppress::is_suppressed(&allows, code, line_index.utf16_position(range.start()).line)
        {
            continue;
        }
        out.push(convert(db, diag, severity, range, ids));
    }
    out
}

/// Converts diagnostics found outside `check` (the HG81xx of `build`) like a file's own: the
/// configured severities (a rule set to "off" is dropped), inline suppressions (§1.4b) and
/// absolute ranges; each with its file.
pub(crate) fn convert_extra(
    db: &dyn salsa::Database,
    ws: Workspace,
    diags: &[Diag],
) -> Vec<(File, Diagnostic)> {
    let ids = &output_file_table(db, ws).ids;
    let config = ws.config(db);
    // The `higraph-allow` comments of each file, read once per file that has some.
    let mut allows: HashMap<File, Option<(Vec<suppress::Allow>, LineIndex)>> = HashMap::new();
    let mut out = Vec::new();
    for diag in diags {
        let code = diag.code.as_str();
        let Some(severity) = config.severity(code) else {
            continue;
        };
        let file = diag.at.file;
        let range = db::absolute_range(db, &diag.at);
        let file_allows = allows.entry(file).or_insert_with(|| {
            let contents = file.contents(db);
            let text = contents.text();
            if !suppress::may_allow(text) {
                return None;
            }
            let line_index = LineIndex::new(text);
            let (allows, _) = suppress::allows(text, db::parse(db, file), &line_index);
            Some((allows, line_index))
        });
        if let Some((allows, line_index)) = file_allows
            && suppress::is_suppressed(allows, code, line_index.utf16_position(range.start()).line)
        {
            continue;
        }
        out.push((file, convert(db, diag, severity, range, ids)));
    }
    out
}

fn convert(
    db: &dyn salsa::Database,
    diag: &Diag,
    severity: Severity,
    range: TextRange,
    ids: &HashMap<File, FileId>,
) -> Diagnostic {
    let file_id = |file: &File| ids.get(file).copied().unwrap_or(FileId(0));
    let rule = registry::rule_of(diag.code.as_str());
    debug_assert!(rule.is_some(), "unregistered code {}", diag.code);
    let mut fixes: Vec<Fix> = diag
        .fixes
        .iter()
        .map(|fix| match (&fix.rename_to, fix.edits.first()) {
            // The rename engine runs when the edit is wanted (`resolve_fixes`).
            (Some(new_name), Some((declaration, _))) => Fix {
                title: fix.title.clone(),
                edits: Vec::new(),
                preferred: fix.preferred,
                rename: Some(PendingRename {
                    file: file_id(&declaration.file),
                    offset: db::absolute_range(db, declaration).start(),
                    new_name: new_name.clone(),
                }),
            },
            _ => Fix {
                title: fix.title.clone(),
                edits: fix
                    .edits
                    .iter()
                    .map(|(loc, new_text)| TextEdit {
                        file: file_id(&loc.file),
                        range: db::absolute_range(db, loc),
                        new_text: new_text.clone(),
                    })
                    .collect(),
                preferred: fix.preferred,
                rename: None,
            },
        })
        .collect();
    mark_preferred(&mut fixes);
    Diagnostic {
        code: diag.code,
        severity,
        range,
        message: diag.message.clone(),
        related: diag
            .related
            .iter()
            .map(|(loc, message)| RelatedInfo {
                file: file_id(&loc.file),
                range: db::absolute_range(db, loc),
                message: message.clone(),
            })
            .collect(),
        fixes,
        tags: if diag.unnecessary {
            vec![DiagnosticTag::Unnecessary]
        } else {
            Vec::new()
        },
    }
}

/// At most one fix of a diagnostic is preferred: the first one a rule marked, else the only one.
fn mark_preferred(fixes: &mut [Fix]) {
    let only = fixes.len() == 1;
    let mut found = false;
    for fix in fixes.iter_mut() {
        fix.preferred = (fix.preferred || only) && !found;
        found |= fix.preferred;
    }
}

/// Carries out the pending renames of `fixes` ([`Fix::rename`]) through the workspace rename
/// engine; a fix whose rename the engine refuses is dropped, and the preferred fix is marked
/// again among those left.
pub(crate) fn resolve_fixes(db: &dyn salsa::Database, ws: Workspace, fixes: &mut Vec<Fix>) {
    if fixes.iter().all(|fix| fix.rename.is_none()) {
        return;
    }
    fixes.retain_mut(|fix| match fix.rename.take() {
        Some(pending) => match rename_edits(db, ws, &pending) {
            Some(edits) => {
                fix.edits = edits;
                true
            }
            None => false,
        },
        None => true,
    });
    mark_preferred(fixes);
}

/// The edits of a pending rename: the workspace rename of the name at its offset; `None` if
/// the rename engine refuses it.
pub(crate) fn rename_edits(
    db: &dyn salsa::Database,
    ws: Workspace,
    pending: &PendingRename,
) -> Option<Vec<TextEdit>> {
    let table = output_file_table(db, ws);
    let file = *table.files.get(pending.file.0 as usize)?;
    let change =
        crate::ide::rename::rename(db, ws, file, pending.offset, &pending.new_name).ok()?;
    let mut edits = Vec::new();
    for (path, file_edits) in &change.files {
        let file = table.ids.get(table.source_paths.get(path)?)?;
        edits.extend(file_edits.iter().map(|edit| TextEdit {
            file: *file,
            range: edit.range,
            new_text: edit.new_text.clone(),
        }));
    }
    Some(edits)
}

fn size(n: usize) -> TextSize {
    TextSize::from(u32::try_from(n).unwrap_or(u32::MAX))
}
