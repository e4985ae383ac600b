//! Graph groups: HG3103, HG3104, HG5xxx, HG8xxx.

use higraph_syntax::ast;

use super::Ctx;
use crate::{db::Workspace, diag::Diag};

pub(crate) fn check(_ctx: &mut Ctx<'_>, _group: &ast::Group) {}

/// Workspace-wide group rules (HG8004).
pub(crate) fn check_workspace(_db: &dyn salsa::Database, _ws: Workspace, _out: &mut Vec<Diag>) {}
