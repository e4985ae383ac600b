//! Building from the editor (`export.md` §2, issue 13): the command `higraph.build` and the
//! code action "Build this group" / "Build this chart" on group and chart headers.
//!
//! * `workspace/executeCommand` `higraph.build` takes no argument (the whole workspace, every
//!   target: the groups' sources and the charts' PLCopen XML) or one
//!   `{"kind": "group"|"chart", "name": NAME}` (that item only: a group's source and the
//!   symbol table, or a chart's document). It builds from the snapshot of the request — the
//!   text as the editor has it, unsaved changes included — off the message loop like every
//!   request, and writes with [`crate::build`] into `build/` in the workspace root, exactly as
//!   `higraph-lsp build` does.
//! * The answer is `{"files": [...], "unchanged": [...], "refused": bool, "message": "..."}`:
//!   the workspace-relative paths written, those that already held the same bytes, whether
//!   errors stopped the build (then nothing is written and the message names the first
//!   error), and a one-line summary. The summary also goes to the client's log.
//! * The code action has no kind: a `source` action would not show in VS Code's light bulb,
//!   and the build is an action on the item under the cursor, not an edit of the file.

use higraph_analysis::TextRange;
use higraph_analysis::build::{BuildItem, BuildOptions, BuildResult, Target};
use serde_json::json;
use tower_lsp_server::ls_types as lsp;

use super::handlers::{HandlerError, HandlerResult};
use super::state::Snapshot;
use crate::build::{output_folder, write_files};
use crate::workspace;

/// The command that builds.
pub(crate) const BUILD: &str = "higraph.build";

/// The argument of `higraph.build`: one group or chart.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
pub(crate) struct BuildParams {
    pub kind: ItemKind,
    pub name: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum ItemKind {
    Group,
    Chart,
}

/// The answer of `higraph.build`.
#[derive(Debug, Clone, serde::Serialize)]
pub(crate) struct BuildAnswer {
    /// Workspace-relative paths of the files written.
    pub files: Vec<String>,
    /// Files of the build that already held the same bytes (not written).
    pub unchanged: Vec<String>,
    pub refused: bool,
    pub message: String,
}

/// The build actions of the items whose header the range touches.
pub(crate) fn code_actions(
    snapshot: &Snapshot,
    path: &str,
    range: TextRange,
) -> HandlerResult<Vec<lsp::CodeActionOrCommand>> {
    let items: Vec<BuildItem> = snapshot.analysis.build_items(path)?;
    Ok(items
        .into_iter()
        .filter(|item| item.range.intersect(range).is_some())
        .map(|item| {
            let (kind, word) = if item.chart {
                ("chart", "chart")
            } else {
                ("group", "group")
            };
            let title = format!("Build this {word} ({})", item.name);
            lsp::CodeActionOrCommand::CodeAction(lsp::CodeAction {
                title: title.clone(),
                kind: None,
                command: Some(lsp::Command {
                    title,
                    command: BUILD.to_owned(),
                    arguments: Some(vec![json!({ "kind": kind, "name": item.name })]),
                }),
                ..lsp::CodeAction::default()
            })
        })
        .collect())
}

/// `higraph.build`: builds and writes (see the module documentation).
pub(crate) fn build(
    snapshot: &Snapshot,
    params: Option<BuildParams>,
) -> HandlerResult<BuildAnswer> {
    let Some(root) = snapshot.root() else {
        return Err(HandlerError::Failed(
            "no workspace folder is open, so there is no build folder to write into".to_owned(),
        ));
    };
    let folder = output_folder(root, None, &[]).map_err(HandlerError::Failed)?;
    let options = BuildOptions {
        target: Target::All,
        ..BuildOptions::default()
    };
    let result: BuildResult = match &params {
        None => snapshot.analysis.build(&[], &options)?,
        Some(item) => {
            let chart = item.kind == ItemKind::Chart;
            let result = snapshot.analysis.build_item(chart, &item.name, &options)?;
            if result.groups + result.charts == 0 {
                return Err(HandlerError::Failed(format!(
                    "there is no {} named '{}'",
                    if chart { "chart" } else { "group" },
                    item.name
                )));
            }
            result
        }
    };
    let items = crate::build::items_text(result.groups, result.charts);
    if let Some(why) = &result.failure {
        return Ok(BuildAnswer {
            files: Vec::new(),
            unchanged: Vec::new(),
            refused: true,
            message: format!("nothing built: {why}"),
        });
    }
    if !result.refused.is_empty() {
        let first = result
            .checked
            .iter()
            .chain(&result.diagnostics)
            .find(|(_, d)| d.severity == higraph_analysis::Severity::Error)
            .map(|(path, d)| {
                let line = snapshot.line_index(path).map_or(1, |index| {
                    index
                        .position(d.range.start(), higraph_analysis::PositionEncoding::Utf16)
                        .line
                        + 1
                });
                format!(
                    "; first: {path}:{line}: error[{}] {}",
                    d.code.as_str(),
                    d.message
                )
            })
            .unwrap_or_default();
        let errors = result
            .checked
            .iter()
            .chain(&result.diagnostics)
            .filter(|(_, d)| d.severity == higraph_analysis::Severity::Error)
            .count();
        return Ok(BuildAnswer {
            files: Vec::new(),
            unchanged: Vec::new(),
            refused: true,
            message: format!(
                "nothing built: {errors} error{} in {} to build or in what {}{first}",
                if errors == 1 { "" } else { "s" },
                crate::build::items_to_build(result.groups, result.charts),
                if result.groups + result.charts == 1 {
                    "it uses"
                } else {
                    "they use"
                }
            ),
        });
    }
    if result.files.is_empty() {
        return Ok(BuildAnswer {
            files: Vec::new(),
            unchanged: Vec::new(),
            refused: false,
            message: "nothing to build: no group or chart in the workspace".to_owned(),
        });
    }
    if snapshot.is_cancelled() {
        return Err(HandlerError::Cancelled);
    }
    let written = write_files(&folder, &result.files).map_err(HandlerError::Failed)?;
    let name = |path: &std::path::Path| workspace::display_name(root, path);
    let files: Vec<String> = written
        .iter()
        .filter(|w| w.changed)
        .map(|w| name(&w.path))
        .collect();
    let unchanged: Vec<String> = written
        .iter()
        .filter(|w| !w.changed)
        .map(|w| name(&w.path))
        .collect();
    let mut message = format!(
        "built {items} into {}: {} file{} written",
        name(&folder.path),
        files.len(),
        if files.len() == 1 { "" } else { "s" }
    );
    if !unchanged.is_empty() {
        message.push_str(&format!(", {} unchanged", unchanged.len()));
    }
    Ok(BuildAnswer {
        files,
        unchanged,
        refused: false,
        message,
    })
}
