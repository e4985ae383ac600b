//! Signature help (`tooling.md` §4): what the parameter list being written at the cursor
//! expects.
//!
//! * **Inside an instance block** of a group (`instance A : Ventil < ... >`): the formal
//!   parameters of the graph (`in`, `out`, `in_out` variables in declaration order, then the
//!   predefined inputs the graph does not declare) with section, type, message kind and
//!   comment. The active parameter is the formal whose actual is being written at the cursor;
//!   while the formal's name is typed, the first formal it is a prefix of; between actuals,
//!   the first formal not yet wired in this instance.
//! * **Inside the parameter list of a CALL** (`CALL FC 10 (…)`, `CALL FB 10, DB 3 (…)`): the
//!   declared interface of the callee (the first `block` item naming it, matched like the CALL
//!   rules do), active parameter chosen the same way. A callee without a declared interface
//!   gets no signature.
//! * **After a qualifier in a chart step** (`L Pump, T#5S;`): the qualifier's meaning and
//!   whether it needs a time; the active parameter is the operand, or the time after the comma.
//!
//! Elsewhere there is no signature. Only the cursor's neighbourhood in the syntax tree and the
//! (cached) declaration of the graph or block are read, so the cost does not grow with the
//! size of the file.

use higraph_syntax::{
    SyntaxKind, SyntaxNode, SyntaxToken, TextRange, TextSize,
    ast::{self, AstNode},
};

use super::{FilePosition, defs::interface_target};
use crate::{
    Analysis, Cancellable,
    address::Address,
    db::{self, File, ItemLoc, Workspace},
    index::{self, GlobalIndex},
    lang::{self, Mnemonic, Section},
    resolve,
    rules::group::interface::PREDEFINED_FORMALS,
};

/// The signature of the parameter list at the cursor.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SignatureHelp {
    /// What the signature belongs to.
    pub kind: SignatureKind,
    /// The signature as shown, e.g. `Ventil < in Oben : BOOL; out Auf : BOOL >`.
    pub label: String,
    /// Markdown about the whole signature (the graph's or block's comment, the qualifier's
    /// meaning).
    pub documentation: Option<String>,
    pub parameters: Vec<SignatureParameter>,
    /// The index of the parameter being written, if any.
    pub active_parameter: Option<u32>,
}

/// What a signature belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SignatureKind {
    /// The formal parameters of an instance's graph.
    Instance,
    /// The declared interface of a CALL's block.
    Call,
    /// A chart step's action qualifier.
    Qualifier,
    /// A call of a standard function block instance (IEC charts).
    FbCall,
}

/// One parameter of a signature.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SignatureParameter {
    /// Where the parameter stands in the signature's label (byte offsets into the label).
    pub range: TextRange,
    /// Markdown about the parameter.
    pub documentation: Option<String>,
}

impl Analysis {
    /// The signature help at the position, if the cursor is inside an instance block, a CALL's
    /// parameter list or a chart step's qualifier action.
    pub fn signature_help(&self, pos: &FilePosition) -> Cancellable<Option<SignatureHelp>> {
        self.with_db(|db, ws| {
            let file = self.file(&pos.path)?;
            signature_help(db, ws, file, pos.offset)
        })
    }
}

fn signature_help(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Option<SignatureHelp> {
    let root = db::parse(db, file).syntax_node();
    if offset > root.text_range().end() {
        return None;
    }
    let token = root.token_at_offset(offset).left_biased()?;
    if matches!(token.kind(), SyntaxKind::COMMENT | SyntaxKind::STRING)
        && token_inside(&token, offset)
    {
        return None;
    }
    for node in token.parent_ancestors() {
        match node.kind() {
            SyntaxKind::PARAM_LIST => return call(db, ws, file, &node, offset),
            SyntaxKind::FB_CALL => {
                return ast::FbCall::cast(node).and_then(|c| fb_call(&c, offset));
            }
            SyntaxKind::QUALIFIER_ACTION => {
                return ast::QualifierAction::cast(node).and_then(|a| qualifier(&a, offset));
            }
            SyntaxKind::BODY => {
                if let Some(instance) = node.parent().and_then(ast::Instance::cast) {
                    return instance_help(db, ws, &instance, offset);
                }
            }
            // Items and members that hold none of the three contexts end the search.
            SyntaxKind::STATE
            | SyntaxKind::TRANS
            | SyntaxKind::STEP
            | SyntaxKind::VAR_SECTION
            | SyntaxKind::SOURCE_FILE => return None,
            _ => {}
        }
    }
    None
}

/// Is the offset strictly inside the token (not at its edges)?
fn token_inside(token: &SyntaxToken, offset: TextSize) -> bool {
    let range = token.text_range();
    range.start() < offset && offset < range.end()
}

/// Builds a label from parts, recording each parameter's range.
#[derive(Default)]
struct Builder {
    label: String,
    parameters: Vec<SignatureParameter>,
}

impl Builder {
    fn text(&mut self, text: &str) {
        self.label.push_str(text);
    }

    fn parameter(&mut self, text: &str, documentation: Option<String>) {
        let start = TextSize::of(self.label.as_str());
        self.label.push_str(text);
        self.parameters.push(SignatureParameter {
            range: TextRange::at(start, TextSize::of(text)),
            documentation,
        });
    }
}

/// A formal parameter as shown.
struct Formal {
    name: String,
    /// `in Oben : BOOL msg out`.
    text: String,
    documentation: Option<String>,
}

/// White space collapsed to single spaces.
fn collapsed(node: &SyntaxNode) -> String {
    node.text()
        .to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// The declared parameters of variable sections (`stat` left out; a later duplicate is left
/// out), each with its section, type, message kind and comment.
fn formals(sections: impl Iterator<Item = ast::VarSection>, messages: bool) -> Vec<Formal> {
    let mut out: Vec<Formal> = Vec::new();
    for section in sections {
        let Some(kind) = section
            .keyword()
            .and_then(|k| Section::from_keyword(k.text()))
            .filter(|s| s.is_formal())
        else {
            continue;
        };
        for decl in section.decls() {
            let Some(name) = decl.name().map(|n| n.text()) else {
                continue;
            };
            if out.iter().any(|f| f.name.eq_ignore_ascii_case(&name)) {
                continue;
            }
            let mut text = format!("{} {name}", kind.as_str());
            if let Some(ty) = decl.ty() {
                text.push_str(" : ");
                text.push_str(&collapsed(ty.syntax()));
            }
            let mut notes = Vec::new();
            if let Some(msg) = decl.msg_kind().filter(|_| messages) {
                text.push(' ');
                text.push_str(&collapsed(msg.syntax()));
                if kind == Section::InOut {
                    notes.push(if msg.is_incoming() {
                        "incoming message: leave it unwired (the sender names it) or wire it \
                         to a global bit"
                    } else {
                        "outgoing message: wire it to an incoming message of another \
                         instance (`Inst.IM_x`) or to a global bit"
                    });
                }
            }
            let mut documentation = notes.join("\n\n");
            if let Some(comment) = decl.comment().map(|c| c.value()).filter(|c| !c.is_empty()) {
                if !documentation.is_empty() {
                    documentation.push_str("\n\n");
                }
                documentation.push_str(&comment);
            }
            out.push(Formal {
                name,
                text,
                documentation: (!documentation.is_empty()).then_some(documentation),
            });
        }
    }
    out
}

/// The index of the active formal: the one named by the parameter at the cursor (exactly, or
/// by prefix while its name is typed), else, when the cursor is between parameters, the first
/// formal not yet wired.
fn active(formals: &[Formal], at_cursor: Option<(String, bool)>, wired: &[String]) -> Option<u32> {
    let index = match at_cursor {
        Some((written, typing)) => formals
            .iter()
            .position(|f| f.name.eq_ignore_ascii_case(&written))
            .or_else(|| {
                let written = written.to_ascii_lowercase();
                typing
                    .then(|| {
                        formals
                            .iter()
                            .position(|f| f.name.to_ascii_lowercase().starts_with(&written))
                    })
                    .flatten()
            }),
        None => formals
            .iter()
            .position(|f| !wired.iter().any(|w| w.eq_ignore_ascii_case(&f.name))),
    }?;
    u32::try_from(index).ok()
}

/// The formal written in a parameter or actual at the cursor, and whether the cursor is in or
/// right after that name (it is still being typed).
fn written_formal(formal: Option<ast::NameRef>, offset: TextSize) -> Option<(String, bool)> {
    let formal = formal?;
    let range = formal.syntax().text_range();
    Some((formal.text(), range.contains_inclusive(offset)))
}

// ---------------------------------------------------------------------------- instances

fn instance_help(
    db: &dyn salsa::Database,
    ws: Workspace,
    instance: &ast::Instance,
    offset: TextSize,
) -> Option<SignatureHelp> {
    let body = instance.body()?;
    let l_angle = body.l_angle()?;
    if offset < l_angle.text_range().end()
        || body
            .r_angle()
            .is_some_and(|r| offset > r.text_range().start())
    {
        return None;
    }
    let index = db::global_index(db, ws);
    let graph_ref = instance.graph()?;
    let entry = index.graph(&graph_ref.text())?;
    let graph =
        db::item_root(db, ItemLoc::new(db, entry.file, entry.item)).and_then(ast::Graph::cast)?;
    let mut formals = formals(graph.var_sections(), true);
    for name in PREDEFINED_FORMALS {
        if formals.iter().any(|f| f.name.eq_ignore_ascii_case(name)) {
            continue;
        }
        let meaning = lang::predefined(name).map(|p| p.meaning);
        formals.push(Formal {
            name: name.to_owned(),
            text: format!("in {name} : BOOL"),
            documentation: Some(match meaning {
                Some(meaning) => format!("predefined formal of every graph: {meaning}"),
                None => "predefined formal of every graph".to_owned(),
            }),
        });
    }
    let mut at_cursor = None;
    let mut wired = Vec::new();
    for actual in instance.actuals() {
        let range = actual.syntax().text_range();
        let ended = actual
            .syntax()
            .last_token()
            .is_some_and(|t| t.kind() == SyntaxKind::SEMI && t.text_range().end() <= offset);
        if range.contains_inclusive(offset) && !ended {
            at_cursor = written_formal(actual.formal(), offset);
        } else if let Some(formal) = actual.formal() {
            wired.push(formal.text());
        }
    }
    let name = graph.name().map(|n| n.text()).unwrap_or(graph_ref.text());
    let mut builder = Builder::default();
    builder.text(&name);
    builder.text(" < ");
    for formal in &formals {
        builder.parameter(&formal.text, formal.documentation.clone());
        builder.text("; ");
    }
    builder.text(">");
    let documentation = graph
        .comment()
        .map(|c| c.value())
        .filter(|c| !c.is_empty())
        .map(|c| format!("graph `{name}`: {c}"));
    Some(SignatureHelp {
        kind: SignatureKind::Instance,
        label: builder.label,
        documentation,
        active_parameter: active(&formals, at_cursor, &wired),
        parameters: builder.parameters,
    })
}

// ---------------------------------------------------------------------------------- CALL

fn call(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    list: &SyntaxNode,
    offset: TextSize,
) -> Option<SignatureHelp> {
    let open = list
        .children_with_tokens()
        .find(|e| e.kind() == SyntaxKind::L_PAREN)?;
    if offset < open.text_range().end() {
        return None;
    }
    let close = list
        .children_with_tokens()
        .find(|e| e.kind() == SyntaxKind::R_PAREN);
    if close.is_some_and(|c| offset > c.text_range().start()) {
        return None;
    }
    let args = list.parent().and_then(ast::CallArgs::cast)?;
    let callee = args.blocks().next()?;
    let index = db::global_index(db, ws);
    let mnemonic = db::file_mnemonic(db, ws, file);
    let interface = interface_of(db, index, mnemonic, &callee)?;
    let formals = formals(interface.var_sections(), false);
    let mut at_cursor = None;
    let mut wired = Vec::new();
    for param in args.params() {
        if param.syntax().text_range().contains_inclusive(offset) {
            at_cursor = written_formal(param.formal(), offset);
        } else if let Some(formal) = param.formal() {
            wired.push(formal.text());
        }
    }
    let reference = interface
        .block()
        .map_or_else(|| collapsed(callee.syntax()), |b| collapsed(b.syntax()));
    let mut builder = Builder::default();
    builder.text("CALL ");
    builder.text(&reference);
    builder.text(" (");
    for (i, formal) in formals.iter().enumerate() {
        if i > 0 {
            builder.text(", ");
        }
        builder.parameter(&formal.text, formal.documentation.clone());
    }
    builder.text(")");
    let documentation = interface
        .comment()
        .map(|c| c.value())
        .filter(|c| !c.is_empty())
        .map(|c| format!("block `{reference}`: {c}"));
    Some(SignatureHelp {
        kind: SignatureKind::Call,
        label: builder.label,
        documentation,
        active_parameter: active(&formals, at_cursor, &wired),
        parameters: builder.parameters,
    })
}

/// The declared interface of a callee: the first `block` item naming it, by block address,
/// else by symbol name (as the CALL rules match them).
fn interface_of(
    db: &dyn salsa::Database,
    index: &GlobalIndex,
    mnemonic: Mnemonic,
    callee: &ast::BlockRef,
) -> Option<ast::BlockInterface> {
    let (address, name): (Option<Address>, Option<String>) = if let Some(address) = callee.address()
    {
        (index::read_address(&address.compact_text(), mnemonic), None)
    } else if let Some(name_ref) = callee.name_ref() {
        let text = name_ref.text();
        match resolve::address_without_space(&text, mnemonic) {
            Some(read) => (read.address.ok(), None),
            None => (
                index.symbol(&text).and_then(|s| s.address.clone()),
                Some(text),
            ),
        }
    } else {
        let name = callee.symbol_ref()?.name();
        (
            index.symbol(&name).and_then(|s| s.address.clone()),
            Some(name),
        )
    };
    let entry = index.block_interfaces.iter().find(|entry| {
        let (a, n) = interface_target(index, mnemonic, &entry.reference);
        match (&address, a) {
            (Some(a), Some(b)) => *a == b,
            _ => matches!((&name, n), (Some(x), Some(y)) if x.eq_ignore_ascii_case(&y)),
        }
    })?;
    db::item_root(db, ItemLoc::new(db, entry.file, entry.item)).and_then(ast::BlockInterface::cast)
}

// ----------------------------------------------------------------------------- qualifiers

/// The IEC action qualifiers: name, meaning, needs a time.
const QUALIFIERS: &[(&str, &str, bool)] = &[
    (
        "N",
        "non-stored: the action is 1 while the step is active",
        false,
    ),
    (
        "S",
        "set (stored): the action stays 1 until an `R` of it resets it",
        false,
    ),
    (
        "R",
        "reset: ends a stored (`S`, `SD`, `DS`, `SL`) action",
        false,
    ),
    (
        "P",
        "pulse: the action is 1 for one cycle when the step becomes active",
        false,
    ),
    (
        "P1",
        "pulse (IEC charts): the action runs once when the step becomes active",
        false,
    ),
    (
        "P0",
        "pulse (IEC charts): the action runs once when the step becomes inactive",
        false,
    ),
    (
        "DL",
        "delayed and limited (IEC charts): 1 from the time after activation until twice the time, while the step is active",
        true,
    ),
    (
        "L",
        "time limited: the action is 1 while the step is active, at most for the time",
        true,
    ),
    (
        "D",
        "time delayed: the action becomes 1 when the step has been active for the time",
        true,
    ),
    (
        "SD",
        "stored and time delayed: set by the step, 1 after the time, until reset",
        true,
    ),
    (
        "DS",
        "delayed and stored: set if the step is still active after the time, until reset",
        true,
    ),
    (
        "SL",
        "stored and time limited: set by the step, 1 for the time or until reset",
        true,
    ),
];

fn qualifier(action: &ast::QualifierAction, offset: TextSize) -> Option<SignatureHelp> {
    let token = action.qualifier()?;
    if offset <= token.text_range().end() {
        return None;
    }
    let ended = action
        .syntax()
        .children_with_tokens()
        .find(|e| e.kind() == SyntaxKind::SEMI)
        .is_some_and(|semi| semi.text_range().end() <= offset);
    if ended {
        return None;
    }
    let &(name, meaning, timed) = QUALIFIERS
        .iter()
        .find(|(q, _, _)| q.eq_ignore_ascii_case(token.text()))?;
    let commas = action
        .syntax()
        .children_with_tokens()
        .filter(|e| e.kind() == SyntaxKind::COMMA && e.text_range().end() <= offset)
        .count();
    let mut builder = Builder::default();
    builder.text(name);
    builder.text(" ");
    builder.parameter(
        "operand",
        Some("the BOOL variable, symbol or address the action drives".to_owned()),
    );
    if timed {
        builder.text(", ");
        builder.parameter(
            "time",
            Some("a TIME constant (`T#5S`) or a TIME operand, read at each evaluation".to_owned()),
        );
    }
    let needs = if timed {
        format!("needs a time: `{name} Pump, T#5S;`")
    } else {
        format!("takes no time: `{name} Pump;`")
    };
    let active = match commas {
        0 => Some(0),
        1 if timed => Some(1),
        _ => None,
    };
    Some(SignatureHelp {
        kind: SignatureKind::Qualifier,
        label: builder.label,
        documentation: Some(format!("`{name}` — {meaning}\n\n{needs}")),
        parameters: builder.parameters,
        active_parameter: active,
    })
}

/// Inside the parentheses of a function block call (`Uhr(IN := Start, |)`): the block's
/// inputs (`:=`) and outputs (`=>`); the active parameter is the formal of the argument at the
/// cursor, else the first not given yet.
fn fb_call(call: &ast::FbCall, offset: TextSize) -> Option<SignatureHelp> {
    use crate::iec::{Direction, FbType};
    let open = call
        .syntax()
        .children_with_tokens()
        .find(|e| e.kind() == SyntaxKind::L_PAREN)?;
    if offset < open.text_range().end() {
        return None;
    }
    let close = call
        .syntax()
        .children_with_tokens()
        .find(|e| e.kind() == SyntaxKind::R_PAREN);
    if close.is_some_and(|c| c.text_range().start() < offset) {
        return None;
    }
    let instance = call.callee()?.text();
    let chart = call.syntax().ancestors().find_map(ast::Chart::cast)?;
    let fb = chart
        .var_sections()
        .flat_map(|s| s.decls())
        .find(|d| {
            d.name()
                .is_some_and(|n| n.text().eq_ignore_ascii_case(&instance))
        })
        .and_then(|d| d.ty())
        .and_then(|t| t.name())
        .and_then(|t| FbType::from_name(t.text()))?;
    let mut builder = Builder::default();
    builder.text(&format!("{instance}("));
    for (i, member) in fb.members().iter().enumerate() {
        if i > 0 {
            builder.text(", ");
        }
        let (arrow, direction) = match member.direction {
            Direction::Input => (":=", "input"),
            Direction::Output => ("=>", "output"),
        };
        builder.parameter(
            &format!("{} {arrow} {}", member.name, member.ty),
            Some(format!("{direction} · {}", member.doc)),
        );
    }
    builder.text(")");
    let args: Vec<ast::FbArg> = call.args().collect();
    let at_cursor = args
        .iter()
        .find(|a| a.syntax().text_range().contains_inclusive(offset))
        .and_then(|a| a.formal())
        .map(|f| f.text());
    let index_of = |name: &str| {
        fb.members()
            .iter()
            .position(|m| m.name.eq_ignore_ascii_case(name))
    };
    let active = match at_cursor {
        Some(name) => index_of(&name),
        None => fb.members().iter().position(|m| {
            !args.iter().any(|a| {
                a.formal()
                    .is_some_and(|f| f.text().eq_ignore_ascii_case(m.name))
            })
        }),
    };
    Some(SignatureHelp {
        kind: SignatureKind::FbCall,
        label: builder.label,
        documentation: Some(format!(
            "`{instance}` : {} — {}; inputs with `:=`, outputs read with `=>`",
            fb.name(),
            fb.doc()
        )),
        parameters: builder.parameters,
        active_parameter: active.and_then(|a| u32::try_from(a).ok()),
    })
}

#[cfg(test)]
mod tests {
    use crate::ide::fixture;

    /// The signature at the cursor: its kind and label, the active parameter between `[` `]`
    /// on a second line, then the documentation of the signature and of each parameter.
    fn check(text: &str) -> String {
        let f = fixture::load(text);
        let help = f
            .host
            .analysis()
            .signature_help(&f.position)
            .expect("not cancelled");
        let Some(help) = help else {
            return "none".to_owned();
        };
        let mut out = format!("{:?}: {}\n", help.kind, help.label);
        let active = help
            .active_parameter
            .and_then(|i| help.parameters.get(i as usize));
        match active {
            Some(p) => {
                let range = std::ops::Range::<usize>::from(p.range);
                out.push_str(&format!("active: [{}]\n", &help.label[range]));
            }
            None => out.push_str("active: none\n"),
        }
        if let Some(doc) = &help.documentation {
            out.push_str(&format!("doc: {doc}\n"));
        }
        for p in &help.parameters {
            let range = std::ops::Range::<usize>::from(p.range);
            if let Some(doc) = &p.documentation {
                out.push_str(&format!(
                    "  {}: {}\n",
                    &help.label[range],
                    doc.replace('\n', " ")
                ));
            }
        }
        out
    }

    const GRAPHS: &str = r#"//- graphs.higraph
graph Ventil "valve with two end positions" <
  in < Oben : BOOL "at the top"; Zeit : TIME; >
  out < Auf : BOOL; Text : STRING[10]; >
  in_out < OM_Oben : BOOL msg out "tell the driller"; IM_Ab : BOOL msg in; >
  stat < Merker : BOOL; >
  state 0 < CALL FC 10 (Menge := MW 2, Start := E 1.0); >
>
"#;

    fn group(body: &str) -> String {
        check(&format!(
            "{GRAPHS}//- group.higraph\ngroup G <\n  instance A : Ventil <\n{body}\n  >\n  instance B : Ventil < >\n>\n"
        ))
    }

    #[test]
    fn instance_formals_with_the_active_actual() {
        insta::assert_snapshot!(group("    Oben := E 0.0;\n    Zeit := T#$05S;"), @r#"
            Instance: Ventil < in Oben : BOOL; in Zeit : TIME; out Auf : BOOL; out Text : STRING[10]; in_out OM_Oben : BOOL msg out; in_out IM_Ab : BOOL msg in; in ManualMode : BOOL; in AutomaticMode : BOOL; in UsrMsgQuit : BOOL; >
            active: [in Zeit : TIME]
            doc: graph `Ventil`: valve with two end positions
              in Oben : BOOL: at the top
              in_out OM_Oben : BOOL msg out: outgoing message: wire it to an incoming message of another instance (`Inst.IM_x`) or to a global bit  tell the driller
              in_out IM_Ab : BOOL msg in: incoming message: leave it unwired (the sender names it) or wire it to a global bit
              in ManualMode : BOOL: predefined formal of every graph: manual operating mode: transitions marked 'manual' fire only while it is 1
              in AutomaticMode : BOOL: predefined formal of every graph: automatic operating mode: transitions marked 'auto' fire only while it is 1
              in UsrMsgQuit : BOOL: predefined formal of every graph: acknowledges a user message
        "#);
    }

    #[test]
    fn instance_formal_being_typed_and_the_next_unwired_one() {
        // While the name is typed, the first formal it begins.
        insta::assert_snapshot!(group("    Oben := E 0.0;\n    om_$0"), @r#"
            Instance: Ventil < in Oben : BOOL; in Zeit : TIME; out Auf : BOOL; out Text : STRING[10]; in_out OM_Oben : BOOL msg out; in_out IM_Ab : BOOL msg in; in ManualMode : BOOL; in AutomaticMode : BOOL; in UsrMsgQuit : BOOL; >
            active: [in_out OM_Oben : BOOL msg out]
            doc: graph `Ventil`: valve with two end positions
              in Oben : BOOL: at the top
              in_out OM_Oben : BOOL msg out: outgoing message: wire it to an incoming message of another instance (`Inst.IM_x`) or to a global bit  tell the driller
              in_out IM_Ab : BOOL msg in: incoming message: leave it unwired (the sender names it) or wire it to a global bit
              in ManualMode : BOOL: predefined formal of every graph: manual operating mode: transitions marked 'manual' fire only while it is 1
              in AutomaticMode : BOOL: predefined formal of every graph: automatic operating mode: transitions marked 'auto' fire only while it is 1
              in UsrMsgQuit : BOOL: predefined formal of every graph: acknowledges a user message
        "#);
        // Between actuals: the first formal not yet wired.
        insta::assert_snapshot!(group("    Oben := E 0.0;$0\n    Auf := A 1.0;"), @r#"
            Instance: Ventil < in Oben : BOOL; in Zeit : TIME; out Auf : BOOL; out Text : STRING[10]; in_out OM_Oben : BOOL msg out; in_out IM_Ab : BOOL msg in; in ManualMode : BOOL; in AutomaticMode : BOOL; in UsrMsgQuit : BOOL; >
            active: [in Zeit : TIME]
            doc: graph `Ventil`: valve with two end positions
              in Oben : BOOL: at the top
              in_out OM_Oben : BOOL msg out: outgoing message: wire it to an incoming message of another instance (`Inst.IM_x`) or to a global bit  tell the driller
              in_out IM_Ab : BOOL msg in: incoming message: leave it unwired (the sender names it) or wire it to a global bit
              in ManualMode : BOOL: predefined formal of every graph: manual operating mode: transitions marked 'manual' fire only while it is 1
              in AutomaticMode : BOOL: predefined formal of every graph: automatic operating mode: transitions marked 'auto' fire only while it is 1
              in UsrMsgQuit : BOOL: predefined formal of every graph: acknowledges a user message
        "#);
        // Right after the opening `<` of an empty instance.
        insta::assert_snapshot!(check(&format!("{GRAPHS}//- g.higraph\ngroup G < instance A : Ventil <$0 > >\n")), @r#"
            Instance: Ventil < in Oben : BOOL; in Zeit : TIME; out Auf : BOOL; out Text : STRING[10]; in_out OM_Oben : BOOL msg out; in_out IM_Ab : BOOL msg in; in ManualMode : BOOL; in AutomaticMode : BOOL; in UsrMsgQuit : BOOL; >
            active: [in Oben : BOOL]
            doc: graph `Ventil`: valve with two end positions
              in Oben : BOOL: at the top
              in_out OM_Oben : BOOL msg out: outgoing message: wire it to an incoming message of another instance (`Inst.IM_x`) or to a global bit  tell the driller
              in_out IM_Ab : BOOL msg in: incoming message: leave it unwired (the sender names it) or wire it to a global bit
              in ManualMode : BOOL: predefined formal of every graph: manual operating mode: transitions marked 'manual' fire only while it is 1
              in AutomaticMode : BOOL: predefined formal of every graph: automatic operating mode: transitions marked 'auto' fire only while it is 1
              in UsrMsgQuit : BOOL: predefined formal of every graph: acknowledges a user message
        "#);
    }

    #[test]
    fn no_instance_signature_outside_the_block_or_for_unknown_graphs() {
        assert_eq!(group("    Oben := E 0.0;\n  >$0"), "none");
        let header = format!("{GRAPHS}//- g.higraph\ngroup G < instance A : Vent$0il < > >\n");
        assert_eq!(check(&header), "none");
        let after = format!("{GRAPHS}//- g.higraph\ngroup G < instance A : Ventil < >$0 >\n");
        assert_eq!(check(&after), "none");
        assert_eq!(
            check("group G < instance A : Nirgends < X := E 0.0;$0 > >"),
            "none"
        );
    }

    const BLOCKS: &str = r#"//- blocks.higraph
symbols < Dosieren : FC 10 "dose"; Regler : FB 20; >
block FC 10 "Dosieren" < in < Menge : INT "litres"; Start : BOOL; > out < Fertig : BOOL; > in_out < Stand : WORD; > stat < X : INT; > >
block Regler < in < Soll : REAL; > out < Stell : REAL "the output"; > >
"#;

    fn state(stmt: &str) -> String {
        check(&format!(
            "{BLOCKS}//- g.higraph\ngraph G <\n  state 0 <\n    {stmt}\n  >\n>\n"
        ))
    }

    #[test]
    fn call_shows_the_block_interface() {
        insta::assert_snapshot!(state("CALL FC 10 (Menge := MW 2, Start := $0E 1.0);"), @r#"
            Call: CALL FC 10 (in Menge : INT, in Start : BOOL, out Fertig : BOOL, in_out Stand : WORD)
            active: [in Start : BOOL]
            doc: block `FC 10`: Dosieren
              in Menge : INT: litres
        "#);
        // By symbol, with an instance DB; the list is not closed yet.
        insta::assert_snapshot!(state("CALL Regler, DB 3 (Soll := MD 4, $0"), @r#"
            Call: CALL Regler (in Soll : REAL, out Stell : REAL)
            active: [out Stell : REAL]
              out Stell : REAL: the output
        "#);
        // The symbol of FC 10 finds the interface declared by address.
        insta::assert_snapshot!(state("CALL Dosieren ($0)"), @r#"
            Call: CALL FC 10 (in Menge : INT, in Start : BOOL, out Fertig : BOOL, in_out Stand : WORD)
            active: [in Menge : INT]
            doc: block `FC 10`: Dosieren
              in Menge : INT: litres
        "#);
    }

    #[test]
    fn no_call_signature_outside_the_list_or_without_an_interface() {
        assert_eq!(state("CALL FC 10 $0(Menge := MW 2);"), "none");
        assert_eq!(state("CALL FC 10 (Menge := MW 2)$0;"), "none");
        assert_eq!(state("CALL FC 11 (Menge := MW 2$0);"), "none");
        assert_eq!(state("U E 1.0$0;"), "none");
    }

    fn step(item: &str) -> String {
        check(&format!(
            "chart C <\n  sequencer S <\n    start < TRUE; >\n    step X <\n      {item}\n    >\n  >\n>\n"
        ))
    }

    #[test]
    fn qualifiers_and_their_time() {
        insta::assert_snapshot!(step("L Pump, $0"), @r#"
            Qualifier: L operand, time
            active: [time]
            doc: `L` — time limited: the action is 1 while the step is active, at most for the time

            needs a time: `L Pump, T#5S;`
              operand: the BOOL variable, symbol or address the action drives
              time: a TIME constant (`T#5S`) or a TIME operand, read at each evaluation
        "#);
        insta::assert_snapshot!(step("N $0Pump;"), @r#"
            Qualifier: N operand
            active: [operand]
            doc: `N` — non-stored: the action is 1 while the step is active

            takes no time: `N Pump;`
              operand: the BOOL variable, symbol or address the action drives
        "#);
        insta::assert_snapshot!(step("sd M 1.0$0, T#2S;"), @r#"
            Qualifier: SD operand, time
            active: [operand]
            doc: `SD` — stored and time delayed: set by the step, 1 after the time, until reset

            needs a time: `SD Pump, T#5S;`
              operand: the BOOL variable, symbol or address the action drives
              time: a TIME constant (`T#5S`) or a TIME operand, read at each evaluation
        "#);
    }

    #[test]
    fn no_qualifier_signature_before_it_or_after_the_action() {
        assert_eq!(step("L$0 Pump, T#5S;"), "none");
        assert_eq!(step("N Pump;$0"), "none");
        assert_eq!(step("min $0T#5S;"), "none");
        assert_eq!(step("run < Pump := $0TRUE; >"), "none");
    }

    #[test]
    fn nothing_elsewhere() {
        assert_eq!(check("$0"), "none");
        assert_eq!(check("graph G < in < A : BOOL$0; > >"), "none");
        assert_eq!(check("group G < option reserve $04; >"), "none");
        assert_eq!(group("    Oben := E 0.0; // a comment$0 here"), "none");
    }

    #[test]
    fn every_offset_of_broken_text_is_safe() {
        let texts = [
            format!(
                "{GRAPHS}//- g.higraph\n$0group G < instance A : Ventil < Oben := ; Zeit : instance B : Ventil < OM_Oben := A. >"
            ),
            format!(
                "{BLOCKS}//- g.higraph\n$0graph G < state 0 < CALL FC 10 (Menge := , , Start := CALL ( ) ; CALL Regler, ( > >"
            ),
            "$0chart C < sequencer S < step X < L , ; SD Pump T#1S; N; D Pump, T#1S, T#2S > >"
                .to_owned(),
        ];
        for text in texts {
            let f = fixture::load(&text);
            let analysis = f.host.analysis();
            let len = f.text(&f.position.path).len() as u32;
            for offset in 0..=len + 1 {
                let position = crate::ide::FilePosition {
                    path: f.position.path.clone(),
                    offset: offset.into(),
                };
                let help = analysis.signature_help(&position).expect("not cancelled");
                if let Some(help) = help {
                    for p in &help.parameters {
                        assert!(
                            help.label
                                .get(std::ops::Range::<usize>::from(p.range))
                                .is_some()
                        );
                    }
                    if let Some(active) = help.active_parameter {
                        assert!((active as usize) < help.parameters.len());
                    }
                }
            }
        }
    }

    #[test]
    fn function_block_calls_in_iec_charts() {
        let chart = |call: &str| {
            format!(
                "chart Ampel <\n  profile iec;\n  stat < Uhr : TON; Start : BOOL; >\n  sequencer S <\n    step Rot < run < {call} > >\n  >\n>\n"
            )
        };
        insta::assert_snapshot!(check(&chart("Uhr(IN := Start, $0);")), @r#"
            FbCall: Uhr(IN := BOOL, PT := TIME, Q => BOOL, ET => TIME)
            active: [PT := TIME]
            doc: `Uhr` : TON — on-delay timer: Q follows IN after PT; inputs with `:=`, outputs read with `=>`
              IN := BOOL: input · the input the timer watches
              PT := TIME: input · the preset time
              Q => BOOL: output · the timer's output
              ET => TIME: output · the elapsed time
        "#);
        let on_output = check(&chart("Uhr(IN := Start, Q => St$0art);"));
        assert!(on_output.contains("active: [Q => BOOL]"), "{on_output}");
        assert_eq!(check(&chart("Uhr(IN := Start);$0")), "none");
    }
}
