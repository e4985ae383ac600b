//! Reading a workspace's files into the [`WorkspaceData`] the analysis loads: the
//! configuration, every `.higraph` file that `include`/`exclude` accept, and the imported
//! symbol tables. The command line and the language server load a workspace the same way, so
//! they see the same diagnostics (`diagnostics.md` §4.4).

use std::collections::HashMap;
use std::path::Path;

use globset::{Glob, GlobSet, GlobSetBuilder};
use higraph_analysis::{AnalysisHost, FileContents, WorkspaceData};

use super::{CONFIG_FILE, Workspace, WorkspaceError, display_name, io_reason};

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
/// that file. An unreadable `config` file (the command line's `--config`) is an error.
pub(crate) fn load(workspace: &Workspace, config: Option<&Path>) -> Result<Loaded, WorkspaceError> {
    let mut selected = HashMap::new();
    let config_path = match config {
        Some(path) => Some(path.to_path_buf()),
        None => Some(workspace.root.join(CONFIG_FILE)).filter(|p| p.is_file()),
    };
    let config = match &config_path {
        Some(path) => {
            let bytes = std::fs::read(path).map_err(|error| {
                WorkspaceError::new(format!(
                    "cannot read configuration file '{}': {}",
                    path.display(),
                    io_reason(&error)
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
        let contents = match std::fs::read(&file.path) {
            Ok(bytes) => FileContents::from_bytes(bytes),
            Err(error) => FileContents::unreadable(io_reason(&error)),
        };
        selected.insert(file.name.clone(), file.selected);
        files.push((file.name.clone(), contents));
    }
    let mut imports = HashMap::new();
    for (entry, _) in &parsed.symbols {
        let path = workspace.root.join(entry);
        let read = std::fs::read(&path).map_err(|error| io_reason(&error));
        let absolute = std::fs::canonicalize(&path).unwrap_or(path);
        selected.insert(entry.clone(), workspace.selects(&absolute));
        imports.insert(entry.clone(), read);
    }
    Ok(Loaded {
        data: WorkspaceData {
            files,
            config,
            imports,
        },
        selected,
    })
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
        let config = std::fs::read(root.join(CONFIG_FILE))
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
