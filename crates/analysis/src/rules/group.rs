//! Graph groups (`diagnostics.md` §3.3, §3.5, §3.8):
//!
//! * instances and actual parameters — HG5001–HG5003, HG5101–HG5105 ([`instances`]);
//! * messages — HG5201–HG5207 ([`messages`]);
//! * operating modes — HG3103, HG3104 ([`modes`]);
//! * actual values — HG4101 (`'{name}' is not a global symbol`), HG4102, HG4103, HG4009–HG4012
//!   and HG1104 for symbols ([`actuals`]); HG1104 also for graph, formal and message names;
//! * options — HG8001, HG8006–HG8009 ([`options`]);
//! * generated blocks — HG8002, HG8003, HG8005 per group, and workspace-wide HG8004, HG8010,
//!   HG8011 ([`blocks`]).
//!
//! The formals of an instantiated graph come from the salsa query
//! [`interface::graph_interface`], which holds no positions: editing a graph's states leaves it
//! equal, so the groups are not checked again.

pub(crate) mod actuals;
pub(crate) mod blocks;
mod instances;
pub(crate) mod interface;
mod messages;
mod modes;
mod options;

use higraph_syntax::ast;

use super::Ctx;
use crate::{db::Workspace, diag::Diag};

/// The rules of one group item.
pub(crate) fn check(ctx: &mut Ctx<'_>, group: &ast::Group) {
    let name = group.name().map(|n| n.text()).unwrap_or_default();
    options::check(ctx, group);
    blocks::check_clauses(ctx, group, &name);
    instances::check(ctx, group, &name);
}

/// Workspace-wide group rules: HG8004, HG8010, HG8011.
pub(crate) fn check_workspace(db: &dyn salsa::Database, ws: Workspace, out: &mut Vec<Diag>) {
    blocks::check_workspace(db, ws, out);
}
