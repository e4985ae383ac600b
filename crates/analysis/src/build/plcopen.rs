//! The charts of a build → one PLCopen TC6 XML 2.01 document (`charts.xml`).

use crate::db::{File, Workspace};

/// The document for the charts `(file, item)`, in the given order. UTF-8 XML.
pub(super) fn charts_xml(
    db: &dyn salsa::Database,
    ws: Workspace,
    charts: &[(File, u32)],
) -> Vec<u8> {
    let _ = (db, ws, charts);
    todo!("charts_xml")
}
