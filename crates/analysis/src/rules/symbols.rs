//! Global symbols and the workspace namespace: HG6001–HG6007, HG4309, HG4310, HG1301.

use higraph_syntax::ast;

use super::Ctx;
use crate::{db::Workspace, diag::Diag};

pub(crate) fn check_table(_ctx: &mut Ctx<'_>, _table: &ast::Symbols) {}
pub(crate) fn check_block_interface(_ctx: &mut Ctx<'_>, _interface: &ast::BlockInterface) {}

/// Workspace-wide rules: HG1301, HG6002, HG6003, HG6004, HG4310.
pub(crate) fn check_workspace(_db: &dyn salsa::Database, _ws: Workspace, _out: &mut Vec<Diag>) {}
