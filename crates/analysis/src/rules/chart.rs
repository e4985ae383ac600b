//! Sequence charts: HG7xxx, and the chart side of HG1xxx, HG3xxx and HG4101.

use higraph_syntax::ast;

use super::Ctx;

pub(crate) fn check(_ctx: &mut Ctx<'_>, _chart: &ast::Chart) {}
