//! Graph declarations and structure: HG1201–HG1206, HG1211–HG1213, HG1215, HG2xxx,
//! HG3001–HG3003, HG3007, HG3101, HG3102.

use higraph_syntax::ast;

use super::Ctx;

pub(crate) fn check(_ctx: &mut Ctx<'_>, _graph: &ast::Graph) {}

/// Declaration rules inside `block` interfaces (HG1201, HG1203, HG1205, HG1206, HG1213,
/// HG1215).
pub(crate) fn check_block_interface(_ctx: &mut Ctx<'_>, _interface: &ast::BlockInterface) {}
