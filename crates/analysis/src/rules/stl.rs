//! STL in graphs: operand resolution (§2.4), HG1104, HG1207–HG1210, HG1214, HG3004–HG3006,
//! HG3008 and HG4xxx.

use higraph_syntax::ast;

use super::Ctx;

pub(crate) fn check(_ctx: &mut Ctx<'_>, _graph: &ast::Graph) {}
