//! How the command line names files (`tooling.md` §2, "Paths"): relative to the current
//! directory, so that a terminal, an editor's problem matcher, GitHub annotations and code
//! scanning find them when the workspace is a sub-folder of the repository. A file outside the
//! current directory is named by its absolute path. The workspace-relative names of the
//! analysis (and of `--format json`) are converted here, and nowhere else.

use std::path::{Path, PathBuf};

use crate::workspace::{display_name, name_path};

/// Converts workspace-relative names to names relative to the current directory.
#[derive(Debug, Clone)]
pub(crate) struct OutputPaths {
    /// The workspace root (absolute, canonical).
    root: PathBuf,
    /// The current directory (canonical when it can be), `None` when it cannot be read: then
    /// every name is absolute.
    cwd: Option<PathBuf>,
}

impl OutputPaths {
    /// For a run in the process's current directory.
    pub(crate) fn new(root: &Path) -> OutputPaths {
        let cwd = std::env::current_dir()
            .ok()
            .map(|dir| std::fs::canonicalize(&dir).unwrap_or(dir));
        OutputPaths::with_cwd(root, cwd)
    }

    pub(crate) fn with_cwd(root: &Path, cwd: Option<PathBuf>) -> OutputPaths {
        OutputPaths {
            root: root.to_path_buf(),
            cwd,
        }
    }

    /// The output name of the file whose workspace name is `name` (a workspace-relative `/`
    /// path, or an absolute path for a file outside the workspace).
    pub(crate) fn name(&self, name: &str) -> String {
        // Names are written by `workspace::name_text` component by component (bytes that are
        // not UTF-8 as `\xNN`): turn them back into the real path, or they would be escaped
        // twice.
        let start = if name.starts_with('/') {
            PathBuf::from("/")
        } else {
            self.root.clone()
        };
        let path = name
            .split('/')
            .filter(|part| !part.is_empty())
            .map(name_path)
            .fold(start, |path, part| path.join(part));
        self.of_path(&normalize(&path))
    }

    /// The output name of an absolute path: relative to the current directory with `/`, or
    /// the absolute path for one outside it (`.` for the current directory itself).
    pub(crate) fn of_path(&self, path: &Path) -> String {
        match &self.cwd {
            Some(cwd) => display_name(cwd, path),
            // `display_name` names a path outside its first argument absolutely, and no
            // absolute path is under the relative path `\0`.
            None => display_name(Path::new("\0"), path),
        }
    }

    /// The workspace root relative to the current directory (`.` when they are the same), as
    /// `--format json` reports it.
    pub(crate) fn root(&self) -> String {
        self.of_path(&self.root)
    }
}

/// Removes `.` and resolves `..` components lexically (a `--config ../x.toml` names a file
/// outside the workspace by a relative path).
fn normalize(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push(component);
                }
            }
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_relative_to_the_current_directory() {
        let paths = OutputPaths::with_cwd(Path::new("/repo/plc"), Some("/repo".into()));
        assert_eq!(paths.name("ablauf.higraph"), "plc/ablauf.higraph");
        assert_eq!(paths.name("sub/a.higraph"), "plc/sub/a.higraph");
        assert_eq!(paths.root(), "plc");
        assert_eq!(paths.name("/etc/x.toml"), "/etc/x.toml");

        let same = OutputPaths::with_cwd(Path::new("/repo"), Some("/repo".into()));
        assert_eq!(same.name("a.higraph"), "a.higraph");
        assert_eq!(same.root(), ".");

        // Below the root: files outside the current directory are named absolutely.
        let below = OutputPaths::with_cwd(Path::new("/ws"), Some("/ws/graphs/deep".into()));
        assert_eq!(below.name("graphs/deep/a.higraph"), "a.higraph");
        assert_eq!(below.name("graphs/b.higraph"), "/ws/graphs/b.higraph");
        assert_eq!(below.root(), "/ws");

        // A name with `..` (a `--config` outside the workspace) is resolved first.
        assert_eq!(same.name("../cfg.toml"), "/cfg.toml");
        assert_eq!(below.name("./graphs/deep/../deep/a.higraph"), "a.higraph");

        let unknown = OutputPaths::with_cwd(Path::new("/ws"), None);
        assert_eq!(unknown.name("a.higraph"), "/ws/a.higraph");
    }
}
