//! Putting what `build` generates on disk, shared by `higraph-lsp build` (`cli/build.rs`) and
//! the server's command `higraph.build` (`server/build.rs`), so both write the same files the
//! same way (`export.md` §2).
//!
//! * The output folder is `build/` in the workspace root unless the command line names one
//!   (`-o DIR`). The default folder must lie inside the workspace: a `build` that is a link
//!   out of it, or not a folder, is refused. A folder named with `-o` may lie anywhere, but
//!   not be the workspace root or a folder above it, nor hold source files of the workspace.
//! * The folder gets the marker [`OUTPUT_MARKER`]: the workspace walk never enters a folder
//!   holding it (nor the root's `build`), so nothing generated is ever analysed as a source.
//! * Each file is written atomically: a temporary file `.NAME.PID.N.build-tmp` in the output
//!   folder, then a rename over `NAME`. A rename replaces a link of that name instead of
//!   writing through it, so nothing outside the folder is written. A file whose bytes would
//!   not change is not written at all (its modification time stays). Other files in the
//!   folder are left alone.

use std::fs;
use std::io::{self, Read as _, Write as _};
use std::path::{Component, Path, PathBuf};

use higraph_analysis::build::BuildFile;

use crate::workspace::{BUILD_FOLDER, OUTPUT_MARKER, io_reason};

/// What the marker file says to whoever opens it.
const MARKER_TEXT: &str = "This folder is written by `higraph-lsp build`. The workspace walk \
skips every folder holding this file, so nothing in it is analysed as a HiGraph source.\n";

/// The largest existing file compared with a new one (a larger one is simply replaced).
const MAX_COMPARED_BYTES: u64 = 64 * 1024 * 1024;

/// Where a build writes.
#[derive(Debug, Clone)]
pub(crate) struct OutputFolder {
    /// Absolute; existing folders in it resolved (links included).
    pub path: PathBuf,
}

/// The result of writing one file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Written {
    /// The file's name in the output folder.
    pub name: String,
    /// Absolute path.
    pub path: PathBuf,
    /// `false` when the file already held exactly these bytes and was left as it was.
    pub changed: bool,
}

/// The output folder: `explicit` (the command line's `-o`, relative to the current folder)
/// or `build/` in `root` (canonical). `sources`: the workspace's source files (absolute), which
/// an explicit folder must not hold. Nothing is created yet ([`write_files`] does).
pub(crate) fn output_folder(
    root: &Path,
    explicit: Option<&Path>,
    sources: &[PathBuf],
) -> Result<OutputFolder, String> {
    let Some(explicit) = explicit else {
        let path = root.join(BUILD_FOLDER);
        return match fs::symlink_metadata(&path) {
            Err(error) if error.kind() == io::ErrorKind::NotFound => Ok(OutputFolder { path }),
            Err(error) => Err(format!(
                "cannot use the output folder '{}': {}",
                path.display(),
                io_reason(&error)
            )),
            Ok(_) => {
                let real = fs::canonicalize(&path).map_err(|error| {
                    format!(
                        "cannot use the output folder '{}': {}",
                        path.display(),
                        io_reason(&error)
                    )
                })?;
                if !real.starts_with(root) || real == root {
                    return Err(format!(
                        "the output folder '{}' leads out of the workspace (to '{}'); remove \
                         the link or name a folder with -o",
                        path.display(),
                        real.display()
                    ));
                }
                if !real.is_dir() {
                    return Err(format!(
                        "the output folder '{}' is not a folder",
                        path.display()
                    ));
                }
                Ok(OutputFolder { path: real })
            }
        };
    };
    let shown = explicit.display();
    let path = absolute(explicit)
        .map_err(|error| format!("cannot use the output folder '{shown}': {error}"))?;
    if fs::symlink_metadata(&path).is_ok() && !path.is_dir() {
        return Err(format!("the output folder '{shown}' is not a folder"));
    }
    if root.starts_with(&path) {
        return Err(format!(
            "the output folder '{shown}' is the workspace root or a folder above it; name a \
             folder of its own"
        ));
    }
    if let Some(source) = sources.iter().find(|source| source.starts_with(&path)) {
        return Err(format!(
            "the output folder '{shown}' holds a source file of the workspace ('{}'); name a \
             folder of its own",
            source.display()
        ));
    }
    Ok(OutputFolder { path })
}

/// `path` made absolute: its longest existing beginning resolved (links included), the rest
/// (not yet existing folders) appended; `..` in the rest is refused.
fn absolute(path: &Path) -> Result<PathBuf, String> {
    let joined = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()
            .map_err(|error| io_reason(&error))?
            .join(path)
    };
    let mut rest = Vec::new();
    let mut existing = joined.as_path();
    loop {
        if fs::symlink_metadata(existing).is_ok() {
            break;
        }
        let (Some(parent), Some(name)) = (existing.parent(), existing.file_name()) else {
            break;
        };
        rest.push(name.to_os_string());
        existing = parent;
    }
    let mut out = fs::canonicalize(existing).map_err(|error| io_reason(&error))?;
    for name in rest.iter().rev() {
        if Path::new(name)
            .components()
            .any(|c| !matches!(c, Component::Normal(_)))
        {
            return Err("a folder that does not exist yet must not be reached through '..'".into());
        }
        out.push(name);
    }
    Ok(out)
}

/// Creates the folder (and its marker) if needed and writes `files` into it, in order. Stops
/// at the first file that cannot be written (the error names it).
pub(crate) fn write_files(
    folder: &OutputFolder,
    files: &[BuildFile],
) -> Result<Vec<Written>, String> {
    let dir = &folder.path;
    fs::create_dir_all(dir).map_err(|error| {
        format!(
            "cannot create the output folder '{}': {}",
            dir.display(),
            io_reason(&error)
        )
    })?;
    let cannot = |path: &Path, error: io::Error| {
        format!("cannot write '{}': {}", path.display(), io_reason(&error))
    };
    let marker = dir.join(OUTPUT_MARKER);
    if !same_contents(&marker, MARKER_TEXT.as_bytes()) {
        replace(dir, OUTPUT_MARKER, MARKER_TEXT.as_bytes()).map_err(|e| cannot(&marker, e))?;
    }
    let mut written = Vec::with_capacity(files.len());
    for file in files {
        if !is_plain_name(&file.name) {
            return Err(format!(
                "cannot write '{}': not a plain file name (a bug in the generator)",
                file.name
            ));
        }
        let path = dir.join(&file.name);
        let changed = !same_contents(&path, &file.bytes);
        if changed {
            replace(dir, &file.name, &file.bytes).map_err(|e| cannot(&path, e))?;
        }
        written.push(Written {
            name: file.name.clone(),
            path,
            changed,
        });
    }
    Ok(written)
}

/// A name that stays in its folder: one component, not hidden.
fn is_plain_name(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with('.')
        && !name.contains(['/', '\\', '\0'])
        && !name.chars().any(char::is_control)
}

/// Whether `path` is a regular file (not a link) holding exactly `bytes`.
fn same_contents(path: &Path, bytes: &[u8]) -> bool {
    let Ok(metadata) = fs::symlink_metadata(path) else {
        return false;
    };
    if !metadata.is_file()
        || metadata.len() != bytes.len() as u64
        || metadata.len() > MAX_COMPARED_BYTES
    {
        return false;
    }
    let mut old = Vec::with_capacity(bytes.len());
    fs::File::open(path)
        .and_then(|file| file.take(MAX_COMPARED_BYTES + 1).read_to_end(&mut old))
        .is_ok()
        && old == bytes
}

/// Writes `bytes` to a new temporary file in `dir` and renames it over `dir/name`; the
/// permissions of a regular file replaced are kept.
fn replace(dir: &Path, name: &str, bytes: &[u8]) -> io::Result<()> {
    let target = dir.join(name);
    let permissions = fs::symlink_metadata(&target)
        .ok()
        .filter(fs::Metadata::is_file)
        .map(|m| m.permissions());
    let pid = std::process::id();
    let mut n = 0u32;
    let (temporary, mut file) = loop {
        let temporary = dir.join(format!(".{name}.{pid}.{n}.build-tmp"));
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)
        {
            Ok(file) => break (temporary, file),
            Err(error) if error.kind() == io::ErrorKind::AlreadyExists && n < 1000 => n += 1,
            Err(error) => return Err(error),
        }
    };
    let result = file
        .write_all(bytes)
        .and_then(|()| file.sync_all())
        .and_then(|()| match permissions {
            Some(permissions) => fs::set_permissions(&temporary, permissions),
            None => Ok(()),
        })
        .and_then(|()| fs::rename(&temporary, &target));
    if result.is_err() {
        let _ = fs::remove_file(&temporary);
    }
    result
}

pub(crate) fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("{n} {word}")
    } else {
        format!("{n} {word}s")
    }
}

/// `2 groups and 1 chart`, `1 group`, `3 charts`.
pub(crate) fn items_text(groups: usize, charts: usize) -> String {
    match (groups, charts) {
        (g, 0) => plural(g, "group"),
        (0, c) => plural(c, "chart"),
        (g, c) => format!("{} and {}", plural(g, "group"), plural(c, "chart")),
    }
}

/// What a build covered, for "errors in ... to build": `the group`, `the 2 groups and the
/// chart`.
pub(crate) fn items_to_build(groups: usize, charts: usize) -> String {
    let one = |n: usize, word: &str| match n {
        1 => format!("the {word}"),
        n => format!("the {n} {word}s"),
    };
    match (groups, charts) {
        (g, 0) => one(g, "group"),
        (0, c) => one(c, "chart"),
        (g, c) => format!("{} and {}", one(g, "group"), one(c, "chart")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_are_counted_in_words() {
        assert_eq!(items_text(1, 0), "1 group");
        assert_eq!(items_text(0, 3), "3 charts");
        assert_eq!(items_text(2, 1), "2 groups and 1 chart");
        assert_eq!(items_to_build(1, 0), "the group");
        assert_eq!(items_to_build(2, 1), "the 2 groups and the chart");
    }

    #[test]
    fn plain_names_stay_in_the_folder() {
        assert!(is_plain_name("Bohrmaschine.awl"));
        assert!(!is_plain_name("../x.awl"));
        assert!(!is_plain_name("a/b.awl"));
        assert!(!is_plain_name(".hidden"));
        assert!(!is_plain_name(""));
    }

    #[test]
    fn unchanged_files_are_not_rewritten_and_others_are_left_alone() {
        let dir = tempfile::tempdir().expect("temporary folder");
        let folder = OutputFolder {
            path: dir.path().join("out"),
        };
        let file = |name: &str, bytes: &[u8]| BuildFile {
            name: name.to_owned(),
            bytes: bytes.to_vec(),
        };
        fs::create_dir_all(&folder.path).expect("folder");
        fs::write(folder.path.join("notes.txt"), "mine").expect("write");
        let first = write_files(&folder, &[file("a.awl", b"A"), file("b.awl", b"B")]).expect("ok");
        assert!(first.iter().all(|w| w.changed));
        let second = write_files(&folder, &[file("a.awl", b"A"), file("b.awl", b"C")]).expect("ok");
        assert_eq!(
            second.iter().map(|w| w.changed).collect::<Vec<_>>(),
            [false, true]
        );
        assert_eq!(fs::read(folder.path.join("b.awl")).expect("read"), b"C");
        assert_eq!(
            fs::read(folder.path.join("notes.txt")).expect("read"),
            b"mine"
        );
        assert!(folder.path.join(OUTPUT_MARKER).is_file());
        let leftovers = fs::read_dir(&folder.path)
            .expect("list")
            .filter(|e| {
                e.as_ref()
                    .is_ok_and(|e| e.file_name().to_string_lossy().ends_with("build-tmp"))
            })
            .count();
        assert_eq!(leftovers, 0);
    }

    #[test]
    fn an_explicit_folder_must_not_hold_the_workspace() {
        let dir = tempfile::tempdir().expect("temporary folder");
        let root = fs::canonicalize(dir.path()).expect("canonical");
        let source = root.join("src/a.higraph");
        fs::create_dir_all(root.join("src")).expect("folder");
        assert!(output_folder(&root, Some(&root), &[]).is_err());
        assert!(
            output_folder(
                &root,
                Some(&root.join("src")),
                std::slice::from_ref(&source)
            )
            .is_err()
        );
        let out = output_folder(&root, Some(&root.join("new/out")), &[source]).expect("ok");
        assert_eq!(out.path, root.join("new/out"));
        assert!(!out.path.exists(), "nothing is created before the write");
    }
}
