//! Reading a workspace's files into the [`WorkspaceData`] the analysis loads: the
//! configuration, every `.higraph` file that `include`/`exclude` accept, and the imported
//! symbol tables. The command line and the language server load a workspace the same way, so
//! they see the same diagnostics (`diagnostics.md` §4.4).

use std::collections::HashMap;
use std::path::Path;

use globset::{Glob, GlobSet, GlobSetBuilder};
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

use super::{
    CONFIG_FILE, Fence, MAX_CONFIG_BYTES, MAX_SOURCE_BYTES, Workspace, WorkspaceError,
    display_name, read_regular,
};

/// What [`load`] read: the workspace data for the analysis, and which output paths are under
/// the PATHs (their diagnostics are reported).
pub(crate) struct Loaded {
    /// The files, configuration and imports to hand to [`AnalysisHost::load`].
    pub data: WorkspaceData,
    /// For each output path (source file, import, configuration): whether it is under one of
    /// the PATHs.
    pub selected: HashMap<String, bool>,
}

/// Reads the configuration, every file of the workspace and the imported symbol tables. A
/// file that cannot be read is not an error of the run: it becomes a diagnostic (HG6103) on
/// that file (also a link out of the workspace, a FIFO or a file over
/// [`MAX_SOURCE_BYTES`]); a symbol table outside the workspace is HG6101 on its entry and is
/// not read. An unreadable configuration file (the workspace's `higraph.toml` or the command
/// line's `--config`) is an error.
pub(crate) fn load(workspace: &Workspace, config: Option<&Path>) -> Result<Loaded, WorkspaceError> {
    let mut selected = HashMap::new();
    let config = read_config(workspace, config)?;
    if let Some((name, _)) = &config {
        // The configuration governs the whole run: its problems are reported whatever the
        // PATHs (`diagnostics.md` §4.3: an invalid `higraph.toml` counts under status 1).
        selected.insert(name.clone(), true);
    }
    let parsed = config
        .as_ref()
        .map(|(_, contents)| AnalysisHost::parse_config(contents))
        .unwrap_or_default();
    let filter = FileFilter::new(&parsed.include, &parsed.exclude);
    let mut files = Vec::new();
    for file in &workspace.files {
        if !filter.accepts(&file.name) && !file.explicit {
            continue;
        }
        let contents = match workspace.fence.read(&file.path, MAX_SOURCE_BYTES) {
            Ok(bytes) => FileContents::from_bytes(bytes),
            Err(reason) => FileContents::unreadable(reason),
        };
        selected.insert(file.name.clone(), file.selected);
        files.push((file.name.clone(), contents));
    }
    let mut imports = HashMap::new();
    let mut refused_imports = HashMap::new();
    // Symbol tables are named in the workspace's files: only the root is theirs to read.
    let root_only = Fence::new(workspace.root.clone());
    for (entry, _) in &parsed.symbols {
        let path = workspace.root.join(entry);
        match root_only.resolve(&path) {
            Ok(real) => {
                selected.insert(entry.clone(), workspace.selects(&real));
                imports.insert(entry.clone(), root_only.read(&real, MAX_SOURCE_BYTES));
            }
            Err(reason) if path.exists() || is_link(&path) => {
                refused_imports.insert(
                    entry.clone(),
                    format!("symbol table '{entry}' cannot be used: {reason}"),
                );
            }
            // A missing table is the import's own problem (HG6005); `..` still counts.
            Err(_) if outside_by_name(entry) => {
                refused_imports.insert(
                    entry.clone(),
                    format!("symbol table '{entry}' cannot be used: it is outside the workspace"),
                );
            }
            Err(reason) => {
                selected.insert(entry.clone(), workspace.selects(&path));
                imports.insert(entry.clone(), Err(reason));
            }
        }
    }
    Ok(Loaded {
        data: WorkspaceData {
            files,
            config,
            imports,
            refused_imports,
        },
        selected,
    })
}

/// The configuration: `--config FILE` (a file the user chose), else the workspace's own
/// `higraph.toml` if there is an entry of that name (which must be a regular file inside the
/// workspace), with its output name. Either way at most [`MAX_CONFIG_BYTES`]; a file that
/// cannot be read is an error of the run.
fn read_config(
    workspace: &Workspace,
    config: Option<&Path>,
) -> Result<Option<(String, FileContents)>, WorkspaceError> {
    let own = workspace.root.join(CONFIG_FILE);
    let (path, bytes) = match config {
        Some(path) => (path, read_regular(path, MAX_CONFIG_BYTES)),
        None if std::fs::symlink_metadata(&own).is_ok() => {
            (own.as_path(), workspace.fence.read(&own, MAX_CONFIG_BYTES))
        }
        None => return Ok(None),
    };
    let bytes = bytes.map_err(|reason| {
        WorkspaceError::new(format!(
            "cannot read configuration file '{}': {reason}",
            path.display(),
        ))
    })?;
    let name = display_name(&workspace.root, path);
    Ok(Some((name, FileContents::from_bytes(bytes))))
}

fn is_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

/// Whether a `symbols` entry (normalised: `x/..` folded away) leaves the root by its
/// spelling: absolute, or starting with `..`.
fn outside_by_name(entry: &str) -> bool {
    Path::new(entry).is_absolute() || entry == ".." || entry.starts_with("../")
}

/// The `include` / `exclude` globs of `higraph.toml`, matched against workspace-relative
/// paths.
pub(crate) struct FileFilter {
    include: GlobSet,
    exclude: GlobSet,
}

impl FileFilter {
    /// The filter of a configuration's `include` and `exclude` patterns.
    pub(crate) fn new(include: &[String], exclude: &[String]) -> FileFilter {
        FileFilter {
            include: glob_set(include),
            exclude: glob_set(exclude),
        }
    }

    /// The filter of the workspace's `higraph.toml` (the defaults when there is none; an
    /// error, as for `check`, when it cannot be read).
    pub(crate) fn for_workspace(workspace: &Workspace) -> Result<FileFilter, WorkspaceError> {
        let config = read_config(workspace, None)?
            .map(|(_, contents)| AnalysisHost::parse_config(&contents))
            .unwrap_or_default();
        Ok(FileFilter::new(&config.include, &config.exclude))
    }

    /// Whether a workspace-relative path is a file of the workspace.
    pub(crate) fn accepts(&self, name: &str) -> bool {
        self.include.is_match(name) && !self.exclude.is_match(name)
    }
}

fn glob_set(patterns: &[String]) -> GlobSet {
    let mut builder = GlobSetBuilder::new();
    for pattern in patterns {
        // The configuration keeps only valid patterns (an invalid one is HG6101 and its key
        // keeps the default), so nothing is lost here.
        if let Ok(glob) = Glob::new(pattern) {
            builder.add(glob);
        }
    }
    builder.build().unwrap_or_else(|_| GlobSet::empty())
}
