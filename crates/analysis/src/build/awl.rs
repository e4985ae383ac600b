//! One group → its STEP 7 source: lowered like a test's run list, then written by
//! `higraph_export::awl`.

use super::BuildOptions;
use crate::db::{File, Workspace};

/// A group's generated source.
#[derive(Debug, Clone)]
#[allow(dead_code)] // read by the orchestrator (being written)
pub(super) struct GroupSource {
    /// The file name (`<group>.awl`).
    pub file_name: String,
    /// Windows-1252, CR LF.
    pub bytes: Vec<u8>,
    /// The symbols the source uses (its FC and DB included), for `symbols.sdf`.
    pub symbols: Vec<higraph_export::sdf::Symbol>,
}

/// The source of the group `item` of `file`. `None` when the group cannot be lowered (the
/// orchestrator refuses builds with errors first, so this is a bug guard).
pub(super) fn group_source(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    item: u32,
    options: &BuildOptions,
) -> Option<GroupSource> {
    let _ = (db, ws, file, item, options);
    todo!("group_source")
}
