//! Reading files safely: only regular files, at most a size limit, and (through [`Fence`])
//! only inside the workspace. Every file the binary reads goes through [`read_regular`].
//!
//! * A FIFO, device, socket or folder is refused before it is opened, and checked again on
//!   the opened handle (a file replaced meanwhile cannot make a read block: on Unix the file
//!   is opened with `O_NONBLOCK`, which also keeps `open` itself from waiting for a FIFO's
//!   writer).
//! * A file larger than its limit is refused; the read itself stops after `limit + 1` bytes, so
//!   a file that grows meanwhile (or claims size 0, as `/proc` files do) cannot exhaust memory.
//! * A path is inside the workspace when its canonical form (every link and `..` resolved) is
//!   below the workspace root (or below a PATH outside the root that the user named on the
//!   command line). A link out of it, a dangling link and a link loop are refused with a
//!   reason.

use std::fs;
use std::io::{self, Read as _};
use std::path::{Path, PathBuf};

use super::io_reason;

/// The largest source file (`.higraph`) or symbol table read: 32 MiB.
pub(crate) const MAX_SOURCE_BYTES: u64 = 32 * 1024 * 1024;
/// The largest configuration file (`higraph.toml`, `--config`) read: 1 MiB.
pub(crate) const MAX_CONFIG_BYTES: u64 = 1024 * 1024;

/// Reads a regular file of at most `limit` bytes (following links). The error is a reason
/// for a message: `it is a FIFO, not a regular file`, `it is larger than 32 MiB`, or the
/// operating system's reason.
pub(crate) fn read_regular(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    read_opened(open(path, limit, Links::Follow)?, limit)
}

/// Reads what [`open`] opened, at most `limit` bytes.
fn read_opened((file, length): (fs::File, u64), limit: u64) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::with_capacity(usize::try_from(length).unwrap_or(0));
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|error| io_reason(&error))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(limit));
    }
    Ok(bytes)
}

/// Opens a regular file of at most `limit` bytes for reading, without blocking; returns it
/// with its length. The error is a reason as for [`read_regular`].
pub(crate) fn open_regular(path: &Path, limit: u64) -> Result<(fs::File, u64), String> {
    open(path, limit, Links::Follow)
}

/// Whether the last component of a path may be a link.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Links {
    Follow,
    /// For a path already resolved: a link put there meanwhile is refused (Unix).
    Refuse,
}

fn open(path: &Path, limit: u64, links: Links) -> Result<(fs::File, u64), String> {
    let metadata = fs::metadata(path).map_err(|error| reason(path, &error))?;
    check_metadata(&metadata, limit)?;
    let mut options = fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        let no_follow = match links {
            Links::Follow => 0,
            Links::Refuse => libc::O_NOFOLLOW,
        };
        options.custom_flags(libc::O_NONBLOCK | no_follow);
    }
    #[cfg(not(unix))]
    let _ = links;
    let file = options.open(path).map_err(|error| reason(path, &error))?;
    // The file may have been replaced since `metadata`: look at what was opened.
    let metadata = file.metadata().map_err(|error| io_reason(&error))?;
    check_metadata(&metadata, limit)?;
    Ok((file, metadata.len()))
}

/// Refuses anything but a regular file of at most `limit` bytes.
fn check_metadata(metadata: &fs::Metadata, limit: u64) -> Result<(), String> {
    if !metadata.is_file() {
        return Err(format!("it is {}, not a regular file", kind(metadata)));
    }
    if metadata.len() > limit {
        return Err(too_large(limit));
    }
    Ok(())
}

fn too_large(limit: u64) -> String {
    format!("it is larger than the limit of {}", size_text(limit))
}

/// `32 MiB`, `1 MiB`, `512 KiB`.
pub(crate) fn size_text(bytes: u64) -> String {
    const MIB: u64 = 1024 * 1024;
    if bytes.is_multiple_of(MIB) {
        format!("{} MiB", bytes / MIB)
    } else if bytes.is_multiple_of(1024) {
        format!("{} KiB", bytes / 1024)
    } else {
        format!("{bytes} bytes")
    }
}

/// What kind of file system entry this is, for a message.
fn kind(metadata: &fs::Metadata) -> &'static str {
    let file_type = metadata.file_type();
    if file_type.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_socket() {
            return "a socket";
        }
        if file_type.is_block_device() || file_type.is_char_device() {
            return "a device";
        }
    }
    "a special file"
}

/// The reason an operation on `path` failed; a link that leads nowhere says so.
fn reason(path: &Path, error: &io::Error) -> String {
    let is_link = fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
    if is_link && error.kind() == io::ErrorKind::NotFound {
        return "it is a link to a path that does not exist".to_owned();
    }
    io_reason(error)
}

/// The folders whose files may be read: the workspace root, and each PATH outside it that the
/// user named on the command line.
#[derive(Debug, Clone, Default)]
pub(crate) struct Fence {
    /// Canonical folders (or, for a PATH naming a file, that file's location).
    areas: Vec<PathBuf>,
}

impl Fence {
    /// A fence around `root` (canonical).
    pub(crate) fn new(root: PathBuf) -> Fence {
        Fence { areas: vec![root] }
    }

    /// Also admits what is under `area` (canonical).
    pub(crate) fn admit(&mut self, area: PathBuf) {
        if !self.contains(&area) {
            self.areas.push(area);
        }
    }

    /// Whether `path` (canonical) is inside.
    pub(crate) fn contains(&self, path: &Path) -> bool {
        self.areas.iter().any(|area| path.starts_with(area))
    }

    /// Where `path` really is (canonical), if that is inside the fence; otherwise why it may
    /// not be read.
    pub(crate) fn resolve(&self, path: &Path) -> Result<PathBuf, String> {
        let canonical = fs::canonicalize(path).map_err(|error| reason(path, &error))?;
        if self.contains(&canonical) {
            Ok(canonical)
        } else {
            Err(outside(path))
        }
    }

    /// Reads a file that is inside the fence (see [`read_regular`]).
    pub(crate) fn read(&self, path: &Path, limit: u64) -> Result<Vec<u8>, String> {
        let real = self.resolve(path)?;
        read_opened(open(&real, limit, Links::Refuse)?, limit)
    }
}

/// Why a path outside the workspace is not read.
fn outside(path: &Path) -> String {
    let is_link = fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
    if is_link {
        "it is a link to a path outside the workspace".to_owned()
    } else {
        "it is outside the workspace".to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_well() {
        assert_eq!(size_text(MAX_SOURCE_BYTES), "32 MiB");
        assert_eq!(size_text(MAX_CONFIG_BYTES), "1 MiB");
        assert_eq!(size_text(2048), "2 KiB");
        assert_eq!(size_text(100), "100 bytes");
    }

    #[test]
    fn a_fence_contains_its_areas() {
        let mut fence = Fence::new(PathBuf::from("/ws"));
        assert!(fence.contains(Path::new("/ws/a.higraph")));
        assert!(!fence.contains(Path::new("/wsx/a.higraph")));
        assert!(!fence.contains(Path::new("/other/b.higraph")));
        fence.admit(PathBuf::from("/other"));
        assert!(fence.contains(Path::new("/other/b.higraph")));
    }

    #[cfg(unix)]
    #[test]
    fn special_and_large_files_are_refused() {
        let dir = std::env::temp_dir().join(format!("higraph-read-{}", std::process::id()));
        let _ = fs::create_dir_all(&dir);
        let big = dir.join("big");
        fs::write(&big, vec![b'x'; 2049]).expect("write");
        assert_eq!(
            read_regular(&big, 2048),
            Err("it is larger than the limit of 2 KiB".to_owned())
        );
        assert_eq!(read_regular(&big, 4096).map(|b| b.len()), Ok(2049));
        assert_eq!(
            read_regular(Path::new("/dev/zero"), 2048),
            Err("it is a device, not a regular file".to_owned())
        );
        assert_eq!(
            read_regular(&dir, 2048),
            Err("it is a folder, not a regular file".to_owned())
        );
        let link = dir.join("dangling");
        let _ = std::os::unix::fs::symlink(dir.join("nothing"), &link);
        assert_eq!(
            read_regular(&link, 2048),
            Err("it is a link to a path that does not exist".to_owned())
        );
        let _ = fs::remove_dir_all(&dir);
    }
}
