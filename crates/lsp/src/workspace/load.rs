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
    let config_path = match config {
        Some(path) => Some(path.to_path_buf()),
        None => Some(workspace.root.join(CONFIG_FILE)).filter(|p| p.is_file()),
    };
    let config = match &config_path {
        Some(path) => {
            // `--config` names a file the user chose; the workspace's own must be inside.
            let bytes = match config {
                Some(_) => read_regular(path, MAX_CONFIG_BYTES),
                None => workspace.fence.read(path, MAX_CONFIG_BYTES),
            }
            .map_err(|reason| {
                WorkspaceError::new(format!(
                    "cannot read configuration file '{}': {reason}",
                    path.display(),
                ))
            })?;
            // The configuration governs the whole run: its problems are reported whatever the
            // PATHs (`diagnostics.md` §4.3: an invalid `higraph.toml` counts under status 1).
            let name = display_name(&workspace.root, path);
            selected.insert(name.clone(), true);
            Some((name, FileContents::from_bytes(bytes)))
        }
        None => None,
    };
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
                imports.insert(entry.clone(), read_regular(&real, MAX_SOURCE_BYTES));
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

    /// The filter of the workspace's `higraph.toml` (the defaults when there is none or it
    /// cannot be read; `check` reports such problems).
    pub(crate) fn for_workspace(root: &Path) -> FileFilter {
        let config = Fence::new(root.to_path_buf())
            .read(&root.join(CONFIG_FILE), MAX_CONFIG_BYTES)
            .map(|bytes| AnalysisHost::parse_config(&FileContents::from_bytes(bytes)))
            .unwrap_or_default();
        FileFilter::new(&config.include, &config.exclude)
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
