//! HG81xx: what `build` needs beyond `check` (export contract).

use super::Target;
use crate::Diagnostic;
use crate::db::{File, Workspace};

/// The build-only diagnostics of the groups and charts `(file, item)` for `target`.
pub(super) fn diagnostics(
    db: &dyn salsa::Database,
    ws: Workspace,
    groups: &[(File, u32)],
    charts: &[(File, u32)],
    target: Target,
) -> Vec<(File, Diagnostic)> {
    let _ = (db, ws, groups, charts, target);
    todo!("build rules")
}
