//! HG1101–HG1103: the name rules of the original declaration editor, for every declared name
//! (§2.2): graphs, groups, charts, variables, instances, sequencers, steps, chart transitions,
//! jumps, loops, and symbols written as a NAME.

use higraph_syntax::ast;

use super::Ctx;

pub(crate) fn check_graph(_ctx: &mut Ctx<'_>, _graph: &ast::Graph) {}
pub(crate) fn check_group(_ctx: &mut Ctx<'_>, _group: &ast::Group) {}
pub(crate) fn check_chart(_ctx: &mut Ctx<'_>, _chart: &ast::Chart) {}
pub(crate) fn check_symbols(_ctx: &mut Ctx<'_>, _table: &ast::Symbols) {}
pub(crate) fn check_block_interface(_ctx: &mut Ctx<'_>, _interface: &ast::BlockInterface) {}
