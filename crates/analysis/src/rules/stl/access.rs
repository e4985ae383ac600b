//! Access rules (Appendix E): HG1209 (writing a read-only predefined variable), HG1214
//! (reading an internal one), HG4401 (writing an input) and HG4403 (a global operand used
//! directly, off by default).

use super::Ctx;
use crate::{
    lang::{Section, Type},
    resolve::{GraphScope, Resolved, Target},
};

/// The access kinds of Appendix E.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Access {
    Read,
    Write,
    ReadWrite,
    /// A CALL actual whose callee's interface is unknown, or the operand of `S`/`R` of a type
    /// they do not take: a use, never reported by HG1209 or HG4401.
    Unknown,
}

impl Access {
    fn writes(self) -> bool {
        matches!(self, Access::Write | Access::ReadWrite)
    }
}

/// Checks the access rules for one resolved operand. `op` is the operation as written, for
/// HG4401's message (`None` for time values, which only read).
pub(crate) fn check(
    ctx: &mut Ctx<'_>,
    scope: &GraphScope,
    operand: &Resolved<'_>,
    access: Access,
    op: Option<&str>,
) {
    match &operand.target {
        Some(Target::Predefined(p)) => {
            if access.writes() && !p.writable {
                let message = format!(
                    "'{}' is read-only; the graph runtime sets it",
                    reference_text(operand)
                );
                let diag = ctx.diag("HG1209", operand.range, message);
                ctx.push(diag);
            }
            if access == Access::Read && p.internal {
                let message = format!(
                    "'{}' is for internal use of the generated code; do not rely on it",
                    reference_text(operand)
                );
                let diag = ctx.diag("HG1214", operand.range, message);
                ctx.push(diag);
            }
            if access.writes() && p.section == Section::In {
                input_written(ctx, operand, op);
            }
        }
        Some(Target::Var(var)) => {
            let is_input = scope
                .vars
                .get(*var)
                .is_some_and(|v| v.section == Section::In);
            if access.writes() && is_input {
                input_written(ctx, operand, op);
            }
        }
        Some(Target::Symbol(_) | Target::Address(_)) => {
            let message = format!(
                "graph {} uses the global operand {} directly; a formal parameter keeps the graph reusable",
                scope.name, operand.text
            );
            let diag = ctx.diag("HG4403", operand.range, message);
            ctx.push(diag);
        }
        Some(Target::Constant(_)) | None => {}
    }
}

/// HG4401: a write to an input parameter (TIMER and COUNTER operands are exempt).
fn input_written(ctx: &mut Ctx<'_>, operand: &Resolved<'_>, op: Option<&str>) {
    if matches!(operand.ty, Some(Type::Timer | Type::Counter)) {
        return;
    }
    let op = op.unwrap_or_default();
    let message = format!(
        "'{op}' writes the input parameter '{}'",
        reference_text(operand)
    );
    let diag = ctx.diag("HG4401", operand.range, message);
    ctx.push(diag);
}

/// The operand's name without `#` or quotes.
fn reference_text(operand: &Resolved<'_>) -> String {
    operand
        .text
        .trim_start_matches('#')
        .trim_matches('"')
        .to_owned()
}
