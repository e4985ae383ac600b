//! Finding a workspace and the files in it (`tooling.md` §2), shared by the command line
//! (`check`, `fmt`) and the language server; [`load`] reads them for the analysis.
//!
//! * The root is the nearest folder upwards from the first PATH (a file PATH: its folder)
//!   that holds `higraph.toml`, else that folder itself.
//! * The workspace's files are the `*.higraph` entries below the root, skipping hidden
//!   entries (names starting with `.`), `node_modules` folders, the root's `target` and
//!   `build` folders and every folder holding the marker [`OUTPUT_MARKER`] (the output
//!   folders of `higraph-lsp build`). Symbolic links to files are listed, links to folders are not followed (no
//!   cycles). A folder, FIFO or other special file named `*.higraph` counts as a file, which
//!   then cannot be read (HG6103).
//! * Files named explicitly on the command line are always part of the workspace, whatever
//!   their name; so are the `*.higraph` files under a PATH folder that the walk from the root
//!   skips or that lies outside the root.
//! * Nothing outside the workspace is read ([`Fence`]): a file whose real path (every link
//!   and `..` resolved) is not below the root is refused with HG6103 — a link out of the
//!   workspace, a dangling link, a link loop. The one exception are PATHs the user names on
//!   the command line outside the root (the root is found from the first PATH): what lies
//!   under such a PATH may be read too, as the user asked for it. A file PATH's own last
//!   component is not resolved for this, so `check env.higraph` with a link
//!   `env.higraph -> /proc/self/environ` is refused like the walk refuses it.
//! * A file is *selected* (reported on) when it is under one of the PATHs.
//! * Files are named by their workspace-relative path with `/` separators; a file outside the
//!   root keeps its absolute path; bytes of a file name that are not UTF-8 are written
//!   `\xNN` (and a backslash `\\`), so different files never print alike ([`name_text`]).
//!   They are sorted in workspace order (code-point order of that name).

use std::collections::BTreeSet;
use std::ffi::OsStr;
use std::fs;
use std::io;
use std::path::{Component, Path, PathBuf};

mod load;
mod read;

pub(crate) use load::{FileFilter, load};
pub(crate) use read::{
    Fence, MAX_CONFIG_BYTES, MAX_SOURCE_BYTES, open_regular, read_regular, size_text,
};

/// The name of the workspace configuration file.
pub(crate) const CONFIG_FILE: &str = "higraph.toml";
/// The extension of HiGraph source files.
pub(crate) const EXTENSION: &str = "higraph";
/// The file `higraph-lsp build` leaves in its output folder: the walk never enters a folder
/// holding it, so generated files are never analysed as sources.
pub(crate) const OUTPUT_MARKER: &str = ".higraph-build";
/// The default output folder of `higraph-lsp build`, in the workspace root (skipped by the
/// walk like `target`).
pub(crate) const BUILD_FOLDER: &str = "build";

/// A problem that stops loading a workspace: a PATH that does not exist, an unreadable root
/// or configuration file. The command line reports it with exit status 2.
#[derive(Debug)]
pub(crate) struct WorkspaceError {
    message: String,
}

impl WorkspaceError {
    pub(crate) fn new(message: impl Into<String>) -> WorkspaceError {
        WorkspaceError {
            message: message.into(),
        }
    }
}

impl std::fmt::Display for WorkspaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

/// An I/O error's text without the trailing " (os error N)".
pub(crate) fn io_reason(error: &io::Error) -> String {
    let text = error.to_string();
    match text.rfind(" (os error ") {
        Some(at) if text.ends_with(')') => text[..at].to_string(),
        _ => text,
    }
}

/// A workspace: its root and its files in workspace order.
#[derive(Debug)]
pub(crate) struct Workspace {
    /// The root folder (absolute, canonical); `higraph.toml` is read from here.
    pub root: PathBuf,
    /// The files, sorted by `name`.
    pub files: Vec<WorkspaceFile>,
    /// The PATH arguments (absolute, see `Target`): diagnostics are reported for files
    /// under them.
    pub targets: Vec<PathBuf>,
    /// What may be read: the root and the PATHs outside it.
    pub fence: Fence,
}

impl Workspace {
    /// Is `path` (absolute) under one of the PATHs?
    pub(crate) fn selects(&self, path: &Path) -> bool {
        self.targets.iter().any(|target| path.starts_with(target))
    }
}

/// One source file of the workspace.
#[derive(Debug)]
pub(crate) struct WorkspaceFile {
    /// Where to read it.
    pub path: PathBuf,
    /// The workspace-relative `/` path (absolute for a file outside the root).
    pub name: String,
    /// Whether it is under one of the PATHs, so its diagnostics are reported.
    pub selected: bool,
    /// Named on the command line itself (checked whatever `include`/`exclude` say).
    pub explicit: bool,
}

/// A PATH argument after checking that it exists.
struct Target {
    /// Absolute path: a folder canonical, a file in its canonical folder (a link in the last
    /// component is not resolved, so it is read, or refused, as the walk would).
    path: PathBuf,
    is_dir: bool,
}

/// Finds the workspace for the PATH arguments (default: the current folder) and lists its
/// files. Fails when a PATH does not exist or the root cannot be read.
pub(crate) fn discover(paths: &[PathBuf]) -> Result<(Workspace, Vec<String>), WorkspaceError> {
    let default = [PathBuf::from(".")];
    let paths = if paths.is_empty() {
        &default[..]
    } else {
        paths
    };
    let targets = paths
        .iter()
        .map(|path| resolve(path))
        .collect::<Result<Vec<_>, _>>()?;

    let first = &targets[0];
    let start = if first.is_dir {
        first.path.clone()
    } else {
        first
            .path
            .parent()
            .map_or_else(|| first.path.clone(), Path::to_path_buf)
    };
    let root = find_root(&start);

    let mut walk = Walk {
        files: BTreeSet::new(),
        warnings: Vec::new(),
    };
    fs::read_dir(&root).map_err(|error| {
        WorkspaceError::new(format!(
            "cannot read the workspace folder '{}': {}",
            root.display(),
            io_reason(&error)
        ))
    })?;
    walk.folder(&root, &root);
    let mut fence = Fence::new(root.clone());
    for target in &targets {
        fence.admit(target.path.clone());
        if !target.is_dir {
            walk.files.insert(target.path.clone());
        } else if !covered_by_root_walk(&root, &target.path) {
            walk.folder(&target.path, &root);
        }
    }

    let mut files: Vec<WorkspaceFile> = walk
        .files
        .into_iter()
        .map(|path| {
            let selected = targets.iter().any(|target| path.starts_with(&target.path));
            let explicit = targets
                .iter()
                .any(|target| !target.is_dir && target.path == path);
            WorkspaceFile {
                name: display_name(&root, &path),
                path,
                selected,
                explicit,
            }
        })
        .collect();
    files.sort_by(|a, b| a.name.cmp(&b.name));
    let targets = targets.into_iter().map(|t| t.path).collect();
    Ok((
        Workspace {
            root,
            files,
            targets,
            fence,
        },
        walk.warnings,
    ))
}

/// Checks that a PATH exists and makes it absolute.
fn resolve(path: &Path) -> Result<Target, WorkspaceError> {
    let shown = path.display();
    let metadata = fs::metadata(path).map_err(|error| match error.kind() {
        io::ErrorKind::NotFound => WorkspaceError::new(format!("path '{shown}' does not exist")),
        _ => WorkspaceError::new(format!("cannot access '{shown}': {}", io_reason(&error))),
    })?;
    let cannot = |error: io::Error| {
        WorkspaceError::new(format!("cannot access '{shown}': {}", io_reason(&error)))
    };
    let is_dir = metadata.is_dir();
    let location = match (is_dir, path.file_name()) {
        (false, Some(name)) => {
            let folder = match path.parent() {
                Some(folder) if !folder.as_os_str().is_empty() => folder,
                _ => Path::new("."),
            };
            fs::canonicalize(folder).map_err(cannot)?.join(name)
        }
        _ => fs::canonicalize(path).map_err(cannot)?,
    };
    Ok(Target {
        path: location,
        is_dir,
    })
}

/// The nearest folder upwards from `start` holding `higraph.toml`, else `start`. Any entry of
/// that name counts (it is not opened here): one that is not a regular file inside the
/// workspace — a FIFO, a folder, a dangling link or a link out — is then refused when the
/// configuration is read, with a message, instead of being passed over silently.
pub(crate) fn find_root(start: &Path) -> PathBuf {
    start
        .ancestors()
        .find(|folder| fs::symlink_metadata(folder.join(CONFIG_FILE)).is_ok())
        .unwrap_or(start)
        .to_path_buf()
}

/// Whether the walk from `root` finds `path` (absolute) as a source file: a `*.higraph` file
/// below the root that is not in a skipped folder. The language server uses it for files that
/// appear after the start.
pub(crate) fn walk_finds(root: &Path, path: &Path) -> bool {
    let is_source = path.extension().is_some_and(|ext| ext == EXTENSION);
    let name_skipped = path
        .file_name()
        .is_some_and(|name| is_skipped(&name.to_string_lossy(), path.parent() == Some(root)));
    is_source
        && !name_skipped
        && path
            .parent()
            .is_some_and(|folder| folder == root || covered_by_root_walk(root, folder))
}

/// Whether `folder` is an output folder of `higraph-lsp build` (it holds the marker).
pub(crate) fn is_output_folder(folder: &Path) -> bool {
    fs::symlink_metadata(folder.join(OUTPUT_MARKER)).is_ok()
}

/// Whether the walk from the root already visited every file under `folder`.
fn covered_by_root_walk(root: &Path, folder: &Path) -> bool {
    let Ok(relative) = folder.strip_prefix(root) else {
        return false;
    };
    relative
        .components()
        .enumerate()
        .all(|(depth, component)| match component {
            Component::Normal(name) => !is_skipped(&name.to_string_lossy(), depth == 0),
            _ => false,
        })
        && !folder
            .ancestors()
            .take_while(|ancestor| *ancestor != root)
            .any(is_output_folder)
}

/// Whether the walk skips an entry of this name. `at_root`: the entry is directly in the
/// folder the walk started from.
fn is_skipped(name: &str, at_root: bool) -> bool {
    name.starts_with('.')
        || name == "node_modules"
        || (at_root && (name == "target" || name == BUILD_FOLDER))
}

struct Walk {
    /// Absolute paths found so far.
    files: BTreeSet<PathBuf>,
    /// Folders below the root that could not be read.
    warnings: Vec<String>,
}

impl Walk {
    fn folder(&mut self, folder: &Path, root: &Path) {
        let entries = match fs::read_dir(folder) {
            Ok(entries) => entries,
            Err(error) => {
                self.warnings.push(format!(
                    "cannot read folder '{}': {}",
                    display_name(root, folder),
                    io_reason(&error)
                ));
                return;
            }
        };
        // `target` is skipped only directly in the workspace root.
        let at_root = folder == root;
        for entry in entries.flatten() {
            let name = entry.file_name();
            let name = name.to_string_lossy();
            if is_skipped(&name, at_root) {
                continue;
            }
            let path = entry.path();
            let is_source = Path::new(&*name)
                .extension()
                .is_some_and(|ext| ext == EXTENSION);
            let Ok(file_type) = entry.file_type() else {
                if is_source {
                    self.files.insert(path);
                }
                continue;
            };
            if is_source {
                // A folder or broken link named `*.higraph` is a file that cannot be read.
                self.files.insert(path);
            } else if file_type.is_dir() && !is_output_folder(&path) {
                self.folder(&path, root);
            }
        }
    }
}

/// The name of a file in output: workspace-relative with `/`, or absolute outside the root.
/// Each component is written by [`name_text`].
pub(crate) fn display_name(root: &Path, path: &Path) -> String {
    match path.strip_prefix(root) {
        Ok(relative) if relative.as_os_str().is_empty() => ".".to_string(),
        Ok(relative) => relative
            .components()
            .map(|component| name_text(component.as_os_str()))
            .collect::<Vec<_>>()
            .join("/"),
        Err(_) => absolute_name(path),
    }
}

/// An absolute path as a name: its components by [`name_text`], joined by `/`.
pub(crate) fn absolute_name(path: &Path) -> String {
    let mut name = String::new();
    for component in path.components() {
        match component {
            Component::Prefix(prefix) => name.push_str(&prefix.as_os_str().to_string_lossy()),
            Component::RootDir => name.push('/'),
            other => {
                if !name.is_empty() && !name.ends_with('/') {
                    name.push('/');
                }
                name.push_str(&name_text(other.as_os_str()));
            }
        }
    }
    name
}

/// A file name as text that tells different names apart: valid UTF-8 as it is, each byte
/// that is not part of valid UTF-8 as `\xNN`, and a backslash as `\\` (so `a\xff` spelt out
/// and the byte 0xFF differ). [`name_path`] undoes it.
pub(crate) fn name_text(name: &OsStr) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt as _;
        let mut text = String::new();
        for chunk in name.as_bytes().utf8_chunks() {
            text.push_str(&chunk.valid().replace('\\', "\\\\"));
            for byte in chunk.invalid() {
                text.push_str(&format!("\\x{byte:02x}"));
            }
        }
        text
    }
    #[cfg(not(unix))]
    {
        name.to_string_lossy().into_owned()
    }
}

/// The file name [`name_text`] wrote as `text`.
pub(crate) fn name_path(text: &str) -> PathBuf {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStringExt as _;
        if !text.contains('\\') {
            return PathBuf::from(text);
        }
        let bytes = text.as_bytes();
        let mut out = Vec::with_capacity(bytes.len());
        let mut i = 0;
        while i < bytes.len() {
            let escaped_byte = (bytes[i] == b'\\' && bytes.get(i + 1) == Some(&b'x'))
                .then(|| text.get(i + 2..i + 4))
                .flatten()
                .and_then(|hex| u8::from_str_radix(hex, 16).ok());
            if let Some(byte) = escaped_byte {
                out.push(byte);
                i += 4;
            } else if bytes[i] == b'\\' && bytes.get(i + 1) == Some(&b'\\') {
                out.push(b'\\');
                i += 2;
            } else {
                out.push(bytes[i]);
                i += 1;
            }
        }
        PathBuf::from(std::ffi::OsString::from_vec(out))
    }
    #[cfg(not(unix))]
    {
        PathBuf::from(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skipped_names() {
        assert!(is_skipped(".git", false));
        assert!(is_skipped("node_modules", false));
        assert!(is_skipped("target", true));
        assert!(!is_skipped("target", false));
        assert!(is_skipped("build", true));
        assert!(!is_skipped("build", false));
        assert!(!is_skipped("graphs", true));
    }

    #[test]
    fn the_walk_finds_sources_outside_skipped_folders() {
        let root = Path::new("/ws");
        assert!(walk_finds(root, Path::new("/ws/a.higraph")));
        assert!(walk_finds(root, Path::new("/ws/graphs/b.higraph")));
        assert!(walk_finds(root, Path::new("/ws/graphs/target/b.higraph")));
        assert!(!walk_finds(root, Path::new("/ws/target/b.higraph")));
        assert!(!walk_finds(root, Path::new("/ws/build/b.higraph")));
        assert!(walk_finds(root, Path::new("/ws/graphs/build/b.higraph")));
        assert!(!walk_finds(root, Path::new("/ws/.git/b.higraph")));
        assert!(!walk_finds(root, Path::new("/ws/.b.higraph")));
        assert!(!walk_finds(root, Path::new("/ws/graphs/b.txt")));
        assert!(!walk_finds(root, Path::new("/other/b.higraph")));
    }

    #[cfg(unix)]
    #[test]
    fn names_that_are_not_utf8_stay_apart_and_come_back() {
        use std::os::unix::ffi::OsStrExt as _;
        let one = OsStr::from_bytes(b"a\xff.higraph");
        let two = OsStr::from_bytes(b"a\xfe.higraph");
        let spelt = OsStr::new("a\\xff.higraph");
        let texts = [name_text(one), name_text(two), name_text(spelt)];
        assert_eq!(texts[0], "a\\xff.higraph");
        assert_eq!(texts[1], "a\\xfe.higraph");
        assert_eq!(texts[2], "a\\\\xff.higraph");
        for (text, name) in texts.iter().zip([one, two, spelt]) {
            assert_eq!(name_path(text).as_os_str(), name, "{text}");
        }
        assert_eq!(name_text(OsStr::new("Zähler.higraph")), "Zähler.higraph");
        let root = Path::new("/ws");
        let path = Path::new("/ws/x").join(one);
        assert_eq!(display_name(root, &path), "x/a\\xff.higraph");
        assert_eq!(
            display_name(root, &Path::new("/other").join(one)),
            "/other/a\\xff.higraph"
        );
    }

    #[test]
    fn display_names_use_slashes() {
        let root = Path::new("/ws");
        assert_eq!(
            display_name(root, Path::new("/ws/a/b.higraph")),
            "a/b.higraph"
        );
        assert_eq!(
            display_name(root, Path::new("/other/b.higraph")),
            "/other/b.higraph"
        );
    }
}
