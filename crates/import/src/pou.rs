//! One POU with an SFC body → one chart text.
//!
//! The SFC network is a graph: every element names its predecessors in
//! `connectionPointIn/connection refLocalId`. [`Walker`] turns it into the language's nested
//! sequence from the initial step: a step, then its transition, a selection divergence becomes
//! `alt` (each outgoing transition begins a branch, the branches end at the selection
//! convergence they share, or in a jump), a simultaneous divergence becomes `parallel`, a
//! transition into a jump step (or into a step already written) becomes `jump NAME -> TARGET`.
//! A selection without a convergence whose first branch continues and whose other branches
//! each are a single jump is the shape `build --target plcopen` writes for jumps after a step,
//! and becomes `jump`s after the step. Each element is written at most once (a `visited`
//! flag), so cycles in the connections end the walk instead of looping; branches recurse at
//! most [`MAX_BRANCH_DEPTH`] deep.

use std::collections::HashMap;
use std::fmt::Write as _;

use roxmltree::Node;

use crate::names::{self, NameSet};
use crate::network::{Net, NetState, Translator};
use crate::st::{self, Names};
use crate::xml::{self, Lines, attr, child, children, first_element};
use crate::{Chart, Import, Problem};

/// Deepest nesting of divergences that is imported.
pub const MAX_BRANCH_DEPTH: usize = 64;

/// The one sequencer of an imported chart.
pub const SEQUENCER: &str = "Main";

const STANDARD_FBS: &[&str] = &[
    "TON", "TOF", "TP", "R_TRIG", "F_TRIG", "CTU", "CTD", "CTUD", "SR", "RS",
];

const ELEMENTARY: &[&str] = &[
    "BOOL",
    "BYTE",
    "WORD",
    "DWORD",
    "INT",
    "DINT",
    "REAL",
    "TIME",
    "DATE",
    "TOD",
    "DT",
    "TIME_OF_DAY",
    "DATE_AND_TIME",
    "CHAR",
];

const QUALIFIERS: &[&str] = &[
    "N", "R", "S", "P", "P1", "P0", "L", "D", "SD", "DS", "SL", "DL",
];
const TIMED: &[&str] = &["L", "D", "SD", "DS", "SL", "DL"];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Section {
    In,
    Out,
    InOut,
    Stat,
}

struct Var {
    section: Section,
    name: String,
    ty: String,
    init: Option<String>,
    doc: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Step,
    Macro,
    Trans,
    Jump,
    SelDiv,
    SelConv,
    SimDiv,
    SimConv,
}

impl Kind {
    fn describe(self) -> &'static str {
        match self {
            Kind::Step => "a step",
            Kind::Macro => "a macro step",
            Kind::Trans => "a transition",
            Kind::Jump => "a jump step",
            Kind::SelDiv => "a selection divergence",
            Kind::SelConv => "a selection convergence",
            Kind::SimDiv => "a simultaneous divergence",
            Kind::SimConv => "a simultaneous convergence",
        }
    }
}

struct GNode<'a, 'i> {
    kind: Kind,
    node: Node<'a, 'i>,
    succ: Vec<usize>,
    /// Output name (steps, transitions).
    name: String,
    /// Sort key among the successors of one element: priority, x position, document order.
    key: (u64, i64, usize),
}

enum El {
    Step {
        name: String,
        doc: Option<String>,
        lines: Vec<String>,
    },
    Trans(Trans),
    Jump(Trans, String),
    Alt(Vec<Vec<El>>),
    Par(Vec<Vec<El>>),
}

struct Trans {
    name: String,
    doc: Option<String>,
    cond: String,
    comment: Option<String>,
}

enum Stop {
    End,
    Conv(usize),
}

enum Flow {
    Next(usize),
    Stop(Stop),
}

struct Action {
    name: String,
    doc: Option<String>,
    /// The body in the language, indented for the chart (two levels), or a comment.
    body: String,
}

struct Ctx<'a> {
    lines: &'a Lines,
    pou: String,
    problems: Vec<Problem>,
}

impl Ctx<'_> {
    fn problem(&mut self, node: Node<'_, '_>, element: Option<String>, message: impl Into<String>) {
        self.problems.push(Problem {
            line: self.lines.line(node.range().start),
            pou: Some(self.pou.clone()),
            element,
            message: message.into(),
        });
    }
}

pub fn import_pou(
    node: Node<'_, '_>,
    globals: &ConstantGlobals<'_, '_>,
    lines: &Lines,
    chart_names: &mut NameSet,
    out: &mut Import,
) {
    let pou_name = attr(node, "name").unwrap_or("").to_owned();
    let Some(sfc) = child(node, "body").and_then(|b| child(b, "SFC")) else {
        out.skipped.push(pou_name);
        return;
    };
    let mut ctx = Ctx {
        lines,
        pou: if pou_name.is_empty() {
            "(unnamed)".to_owned()
        } else {
            pou_name.clone()
        },
        problems: Vec::new(),
    };
    let pou_type = attr(node, "pouType").unwrap_or("program");
    if pou_type == "function" {
        ctx.problem(
            node,
            None,
            "a function cannot have an SFC body in IEC 61131-3; not imported",
        );
        out.problems.append(&mut ctx.problems);
        return;
    }
    let mut name = if names::is_valid(&pou_name) {
        pou_name.clone()
    } else {
        let n = names::sanitize(&pou_name, "Chart");
        ctx.problem(
            node,
            None,
            format!("the name `{pou_name}` is not a valid chart name; renamed to {n}"),
        );
        n
    };
    let unique = chart_names.unique(&name);
    if unique != name {
        ctx.problem(
            node,
            None,
            format!("a second POU named {name}; its chart is named {unique}"),
        );
        name = unique;
    }

    let mut st_names = Names::default();
    let mut var_names = NameSet::default();
    let vars = interface(&mut ctx, node, globals, &mut st_names, &mut var_names);

    let fb_types: HashMap<String, String> = vars
        .iter()
        .filter(|v| STANDARD_FBS.contains(&v.ty.as_str()))
        .map(|v| (v.name.to_ascii_uppercase(), v.ty.clone()))
        .collect();
    let mut walker = Walker::new(&mut ctx, sfc, st_names, var_names, fb_types);
    walker.build_graph();
    walker.name_elements();
    walker.named_actions(node);
    walker.named_transitions(node);
    let body = walker.walk();
    let actions = std::mem::take(&mut walker.actions);
    let pre = std::mem::take(&mut walker.pre_calls);
    drop(walker);

    let mut text = String::new();
    let kind = if pou_type == "functionBlock" {
        "function block"
    } else {
        "program"
    };
    let _ = writeln!(
        text,
        "// Imported from the PLCopen {kind} {} by higraph-lsp import.",
        one_line(&ctx.pou)
    );
    let doc = xml::documentation(node);
    write_header(&mut text, 0, &format!("chart {name}"), doc.as_deref());
    text.push_str(" <\n  profile iec;\n");
    for (section, keyword) in [
        (Section::In, "in"),
        (Section::Out, "out"),
        (Section::InOut, "in_out"),
        (Section::Stat, "stat"),
    ] {
        let decls: Vec<&Var> = vars.iter().filter(|v| v.section == section).collect();
        if decls.is_empty() {
            continue;
        }
        let decls: Vec<String> = decls
            .iter()
            .map(|v| {
                let mut d = format!("{} : {}", v.name, v.ty);
                if let Some(init) = &v.init {
                    let _ = write!(d, " := {init}");
                }
                if let Some(c) = v.doc.as_deref().and_then(string_comment) {
                    let _ = write!(d, " \"{c}\"");
                }
                d.push(';');
                d
            })
            .collect();
        // As `fmt` lays it out: one line when it fits in 100 columns.
        let one_line = format!("  {keyword} < {} >", decls.join(" "));
        if one_line.chars().count() <= 100 {
            text.push_str(&one_line);
            text.push('\n');
        } else {
            let _ = writeln!(text, "  {keyword} <");
            for d in decls {
                let _ = writeln!(text, "    {d}");
            }
            text.push_str("  >\n");
        }
    }
    let _ = writeln!(text, "  sequencer {SEQUENCER} <");
    match pre.as_slice() {
        [] => {}
        [only] if only.len() + 12 <= 100 => {
            let _ = writeln!(text, "    pre < {only} >");
        }
        calls => {
            text.push_str("    pre <\n");
            for c in calls {
                let _ = writeln!(text, "      {c}");
            }
            text.push_str("    >\n");
        }
    }
    write_elements(&mut text, &body, 2);
    text.push_str("  >\n");
    for a in &actions {
        write_header(
            &mut text,
            1,
            &format!("action {}", a.name),
            a.doc.as_deref(),
        );
        let only = a.body.trim();
        if a.body.is_empty() {
            text.push_str(" < >\n");
        } else if a.body.lines().count() == 1 && !only.starts_with("//") {
            // One statement stays on the header's line, as `fmt` lays it out.
            let _ = writeln!(text, " < {only} >");
        } else {
            text.push_str(" <\n");
            text.push_str(&a.body);
            text.push_str("  >\n");
        }
    }
    text.push_str(">\n");
    out.charts.push(Chart {
        pou: pou_name,
        name,
        text,
    });
    out.problems.append(&mut ctx.problems);
}

/// A documentation text as a `"comment"` after a header, if it is one short line the
/// language can carry (no `"`, no line break).
fn string_comment(doc: &str) -> Option<String> {
    let doc = doc.trim();
    (!doc.is_empty()
        && !doc.contains(['"', '\n', '\r'])
        && doc.chars().count() <= 80
        && doc.chars().all(|c| !c.is_control()))
    .then(|| doc.to_owned())
}

/// `not x` for a name, `not (...)` for anything longer.
fn negate(text: &str) -> String {
    if text
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
    {
        format!("not {text}")
    } else {
        format!("not ({text})")
    }
}

/// The `attribute` of CODESYS's SFC vendor data that names a step's active action.
const CODESYS_STEP_ACTION: &str = "700a583f-b4d4-43e4-8c14-629c7cd3bec8";
/// The `attribute` of CODESYS's SFC vendor data that holds an element's comment.
const CODESYS_COMMENT: &str = "7d894980-aeea-405c-a0f6-e2b26429c58f";

fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

fn pad(out: &mut String, indent: usize) {
    for _ in 0..indent {
        out.push_str("  ");
    }
}

/// `header "doc"` or, for a longer documentation, `//` lines and then `header`.
fn write_header(out: &mut String, indent: usize, header: &str, doc: Option<&str>) {
    match doc {
        Some(d) => match string_comment(d) {
            Some(c) => {
                pad(out, indent);
                let _ = write!(out, "{header} \"{c}\"");
            }
            None => {
                for line in d.lines() {
                    pad(out, indent);
                    let line = one_line(line.trim_end());
                    if line.is_empty() {
                        out.push_str("//\n");
                    } else {
                        let _ = writeln!(out, "// {line}");
                    }
                }
                pad(out, indent);
                out.push_str(header);
            }
        },
        None => {
            pad(out, indent);
            out.push_str(header);
        }
    }
}

fn write_trans(out: &mut String, keyword: &str, t: &Trans, target: Option<&str>, indent: usize) {
    let header = match target {
        Some(target) => format!("{keyword} {}->{target}", t.name),
        None => format!("{keyword} {}", t.name),
    };
    write_header(out, indent, &header, t.doc.as_deref());
    match &t.comment {
        None => {
            let _ = writeln!(out, " < {}; >", t.cond);
        }
        Some(comment) => {
            out.push_str(" <\n");
            pad(out, indent + 1);
            let _ = writeln!(out, "// {}", one_line(comment));
            pad(out, indent + 1);
            let _ = writeln!(out, "{};", t.cond);
            pad(out, indent);
            out.push_str(">\n");
        }
    }
}

/// Whether a branch ends in a jump: a `jump`, or an `alt` each of whose branches ends in one
/// (nesting is bounded by the walk's depth limit).
fn ends_in_jump(els: &[El]) -> bool {
    match els.last() {
        Some(El::Jump(..)) => true,
        Some(El::Alt(branches)) => branches.iter().all(|b| ends_in_jump(b)),
        _ => false,
    }
}

/// Writes elements; nesting is bounded by the walk's depth limit.
fn write_elements(out: &mut String, els: &[El], indent: usize) {
    for el in els {
        match el {
            El::Step { name, doc, lines } => {
                write_header(out, indent, &format!("step {name}"), doc.as_deref());
                if lines.is_empty() {
                    out.push_str(" < >\n");
                } else if let [only] = lines.as_slice()
                    && !only.starts_with("//")
                {
                    // One statement stays on the header's line, as `fmt` lays it out.
                    let _ = writeln!(out, " < {only} >");
                } else {
                    out.push_str(" <\n");
                    for l in lines {
                        pad(out, indent + 1);
                        out.push_str(l);
                        out.push('\n');
                    }
                    pad(out, indent);
                    out.push_str(">\n");
                }
            }
            El::Trans(t) => write_trans(out, "trans", t, None, indent),
            El::Jump(t, target) => write_trans(out, "jump", t, Some(target), indent),
            El::Alt(branches) | El::Par(branches) => {
                pad(out, indent);
                out.push_str(if matches!(el, El::Alt(_)) {
                    "alt <\n"
                } else {
                    "parallel <\n"
                });
                for b in branches {
                    pad(out, indent + 1);
                    out.push_str("branch <\n");
                    write_elements(out, b, indent + 2);
                    pad(out, indent + 1);
                    out.push_str(">\n");
                }
                pad(out, indent);
                out.push_str(">\n");
            }
        }
    }
}

// ------------------------------------------------------------------------------------ interface

fn interface<'a, 'i>(
    ctx: &mut Ctx<'_>,
    pou: Node<'a, 'i>,
    globals: &ConstantGlobals<'a, 'i>,
    st_names: &mut Names,
    var_names: &mut NameSet,
) -> Vec<Var> {
    let mut vars = Vec::new();
    let Some(interface) = child(pou, "interface") else {
        return vars;
    };
    for list in interface.children().filter(|c| c.is_element()) {
        let (section, external) = match xml::local(list) {
            "inputVars" => (Section::In, false),
            "outputVars" => (Section::Out, false),
            "inOutVars" => (Section::InOut, false),
            "localVars" | "tempVars" => (Section::Stat, false),
            "externalVars" => (Section::Stat, true),
            "returnType" | "addData" | "documentation" => continue,
            other => {
                ctx.problem(
                    list,
                    None,
                    format!("the variable section <{other}> is not supported; its variables are not imported"),
                );
                continue;
            }
        };
        for v in children(list, "variable") {
            let Some(iec_name) = attr(v, "name") else {
                ctx.problem(v, None, "a variable without a name; not imported");
                continue;
            };
            let element = Some(format!("variable {iec_name}"));
            let ty = match child(v, "type").and_then(first_element) {
                Some(t) => var_type(t),
                None => Err("it has no type".to_owned()),
            };
            let (ty, is_fb) = match ty {
                Ok((ty, is_fb, note)) => {
                    if let Some(note) = note {
                        ctx.problem(v, element.clone(), note);
                    }
                    (ty, is_fb)
                }
                Err(reason) => {
                    ctx.problem(v, element.clone(), format!("not imported: {reason}"));
                    continue;
                }
            };
            let mut name = if names::is_valid(iec_name) {
                iec_name.to_owned()
            } else {
                let n = names::sanitize(iec_name, "V");
                ctx.problem(
                    v,
                    element.clone(),
                    format!("`{iec_name}` is not a valid name; renamed to {n}"),
                );
                n
            };
            let unique = var_names.unique(&name);
            if unique != name {
                ctx.problem(
                    v,
                    element.clone(),
                    format!("declared twice; the second is renamed to {unique}"),
                );
                name = unique;
            }
            if name != iec_name {
                st_names
                    .renamed
                    .entry(iec_name.to_ascii_uppercase())
                    .or_insert_with(|| name.clone());
            }
            let mut section = section;
            // A constant global keeps its meaning as a stat variable with the global's value.
            let constant_global = (external && attr(list, "constant") == Some("true"))
                .then(|| globals.get(&iec_name.to_ascii_uppercase()).copied())
                .flatten();
            if external && constant_global.is_none() {
                ctx.problem(
                    v,
                    element.clone(),
                    "an external (global) variable; imported as a stat variable of the chart",
                );
            }
            if is_fb {
                if section != Section::Stat {
                    ctx.problem(
                        v,
                        element.clone(),
                        "a function block instance outside the local variables; imported as a stat variable",
                    );
                }
                section = Section::Stat;
                st_names.fb_instances.insert(name.to_ascii_uppercase(), ());
            } else {
                st_names.elementary.insert(name.to_ascii_uppercase(), ());
            }
            let mut init = None;
            if let Some(iv) = child(constant_global.unwrap_or(v), "initialValue") {
                match first_element(iv) {
                    Some(sv) if xml::local(sv) == "simpleValue" && !is_fb => {
                        let raw = attr(sv, "value").unwrap_or("");
                        let raw = match (ty.as_str(), raw.trim()) {
                            ("BOOL", "1") => "TRUE",
                            ("BOOL", "0") => "FALSE",
                            (_, raw) => raw,
                        };
                        match st::literal(raw) {
                            Ok(lit) => init = Some(lit),
                            Err(e) => ctx.problem(
                                v,
                                element.clone(),
                                format!("initial value not imported: {}", e.reason),
                            ),
                        }
                    }
                    Some(other) => ctx.problem(
                        v,
                        element.clone(),
                        format!(
                            "initial value not imported: <{}> is not supported",
                            xml::local(other)
                        ),
                    ),
                    None => {}
                }
            }
            vars.push(Var {
                section,
                name,
                ty,
                init,
                doc: xml::documentation(v),
            });
        }
    }
    vars
}

/// Upper-cased name → the variable of a constant `globalVars` list of the document (a
/// configuration's or a resource's) that has an initial value; the first one of a name.
pub type ConstantGlobals<'a, 'i> = HashMap<String, Node<'a, 'i>>;

pub fn constant_globals<'a, 'i>(doc: &'a roxmltree::Document<'i>) -> ConstantGlobals<'a, 'i> {
    let mut map = HashMap::new();
    for list in doc.descendants().filter(|d| {
        d.is_element() && xml::local(*d) == "globalVars" && attr(*d, "constant") == Some("true")
    }) {
        for v in children(list, "variable") {
            if let Some(n) = attr(v, "name")
                && child(v, "initialValue").is_some()
            {
                map.entry(n.to_ascii_uppercase()).or_insert(v);
            }
        }
    }
    map
}

/// The type in the language, whether it is a standard function block, and a note when it
/// was mapped to the nearest type the language has.
fn var_type(t: Node<'_, '_>) -> Result<(String, bool, Option<String>), String> {
    let local = xml::local(t);
    let upper = local.to_ascii_uppercase();
    if ELEMENTARY.contains(&upper.as_str()) {
        return Ok((upper, false, None));
    }
    let nearest = match upper.as_str() {
        "SINT" | "USINT" => Some("INT"),
        "UINT" | "UDINT" | "LINT" | "ULINT" => Some("DINT"),
        "LREAL" => Some("REAL"),
        "LWORD" => Some("DWORD"),
        "LTIME" => Some("TIME"),
        _ => None,
    };
    if let Some(n) = nearest {
        return Ok((
            n.to_owned(),
            false,
            Some(format!(
                "the type {upper} is imported as {n} (the language has no {upper}; the range differs)"
            )),
        ));
    }
    match local {
        "string" => Ok((
            match attr(t, "length").and_then(|l| l.parse::<u16>().ok()) {
                Some(n) if n <= 254 => format!("STRING[{n}]"),
                _ => "STRING".to_owned(),
            },
            false,
            None,
        )),
        "derived" => {
            let name = attr(t, "name").unwrap_or("");
            let upper = name.to_ascii_uppercase();
            if STANDARD_FBS.contains(&upper.as_str()) {
                Ok((upper, true, None))
            } else if ELEMENTARY.contains(&upper.as_str()) {
                Ok((upper, false, None))
            } else {
                Err(format!(
                    "its type {name} is a user-defined type or function block (not supported)"
                ))
            }
        }
        "array" => Err("ARRAY types are not supported".to_owned()),
        "pointer" => Err("POINTER types are not supported".to_owned()),
        "struct" => Err("STRUCT types are not supported".to_owned()),
        "enum" => Err("enumerated types are not supported".to_owned()),
        "wstring" => Err("WSTRING is not supported".to_owned()),
        other => Err(format!("the type <{other}> is not supported")),
    }
}

// ------------------------------------------------------------------------------------ walker

struct Walker<'c, 'l, 'a, 'i> {
    ctx: &'c mut Ctx<'l>,
    sfc: Node<'a, 'i>,
    g: Vec<GNode<'a, 'i>>,
    visited: Vec<bool>,
    /// localId → index in `g`.
    ids: HashMap<u64, usize>,
    /// localId → other elements (inVariable, block, ...), for FBD conditions.
    others: HashMap<u64, Node<'a, 'i>>,
    /// Step index → its action blocks.
    step_actions: HashMap<usize, Vec<Node<'a, 'i>>>,
    /// Step index → output variables wired to its action output (the standard's example).
    step_outputs: HashMap<usize, Vec<Node<'a, 'i>>>,
    st: Names,
    /// Variables and actions (one name space: a qualifier's operand names either).
    var_names: NameSet,
    /// Upper-cased IEC action name → output name.
    named_actions: HashMap<String, String>,
    /// Upper-cased IEC transition name → its <transition> element.
    named_transitions: HashMap<String, Node<'a, 'i>>,
    /// Upper-cased IEC step name → output name.
    step_names: HashMap<String, String>,
    actions: Vec<Action>,
    /// Upper-cased output name of a standard function block instance → its type.
    fb_types: HashMap<String, String>,
    /// The FBD/LD elements of the SFC body, read by conditions given as connections.
    sfc_net: Net<'a, 'i>,
    sfc_state: NetState,
    /// Upper-cased IEC name of a named transition with an FBD/LD body → its condition.
    network_conditions: HashMap<String, Result<String, String>>,
    /// Calls of the function block instances of condition networks (the sequencer's `pre`).
    pre_calls: Vec<String>,
}

impl<'c, 'l, 'a, 'i> Walker<'c, 'l, 'a, 'i> {
    fn new(
        ctx: &'c mut Ctx<'l>,
        sfc: Node<'a, 'i>,
        st: Names,
        var_names: NameSet,
        fb_types: HashMap<String, String>,
    ) -> Walker<'c, 'l, 'a, 'i> {
        Walker {
            fb_types,
            sfc_net: Net::new(sfc.children()),
            sfc_state: NetState::default(),
            network_conditions: HashMap::new(),
            pre_calls: Vec::new(),
            ctx,
            sfc,
            g: Vec::new(),
            visited: Vec::new(),
            ids: HashMap::new(),
            others: HashMap::new(),
            step_actions: HashMap::new(),
            step_outputs: HashMap::new(),
            st,
            var_names,
            named_actions: HashMap::new(),
            named_transitions: HashMap::new(),
            step_names: HashMap::new(),
            actions: Vec::new(),
        }
    }

    fn build_graph(&mut self) {
        let mut blocks = Vec::new();
        for (index, e) in self.sfc.children().filter(|c| c.is_element()).enumerate() {
            let kind = match xml::local(e) {
                "step" => Some(Kind::Step),
                "macroStep" => Some(Kind::Macro),
                "transition" => Some(Kind::Trans),
                "jumpStep" => Some(Kind::Jump),
                "selectionDivergence" => Some(Kind::SelDiv),
                "selectionConvergence" => Some(Kind::SelConv),
                "simultaneousDivergence" => Some(Kind::SimDiv),
                "simultaneousConvergence" => Some(Kind::SimConv),
                _ => None,
            };
            let id = attr(e, "localId").and_then(|v| v.trim().parse::<u64>().ok());
            if xml::local(e) == "actionBlock" {
                blocks.push(e);
                continue;
            }
            let Some(id) = id else {
                if kind.is_some() {
                    self.ctx.problem(
                        e,
                        None,
                        format!("<{}> without a valid localId; not imported", xml::local(e)),
                    );
                }
                continue;
            };
            let Some(kind) = kind else {
                self.others.insert(id, e);
                continue;
            };
            if self.ids.contains_key(&id) || self.others.contains_key(&id) {
                self.ctx.problem(
                    e,
                    None,
                    format!("localId {id} is used twice; the second element is not imported"),
                );
                continue;
            }
            let priority = attr(e, "priority")
                .and_then(|p| p.trim().parse::<u64>().ok())
                .unwrap_or(u64::MAX);
            let x = child(e, "position")
                .and_then(|p| attr(p, "x"))
                .and_then(|x| x.trim().parse::<f64>().ok())
                .map_or(0, |x| x as i64);
            self.ids.insert(id, self.g.len());
            self.g.push(GNode {
                kind,
                node: e,
                succ: Vec::new(),
                name: String::new(),
                key: (priority, x, index),
            });
        }
        self.visited = vec![false; self.g.len()];
        // The output pins of each divergence, when they are told apart by formalParameter
        // (the standard's own example): a connection naming one gives its branch's place.
        let pins: Vec<Vec<&str>> = self
            .g
            .iter()
            .map(|n| {
                let pins: Vec<&str> = children(n.node, "connectionPointOut")
                    .filter_map(|o| attr(o, "formalParameter"))
                    .collect();
                let mut sorted = pins.clone();
                sorted.sort_unstable();
                sorted.dedup();
                let distinct = sorted.len() == pins.len() && !pins.iter().any(|p| p.is_empty());
                if distinct && pins.len() > 1 {
                    pins
                } else {
                    Vec::new()
                }
            })
            .collect();
        let mut edges: Vec<(usize, usize, usize)> = Vec::new();
        // Edges from the connections.
        for i in 0..self.g.len() {
            let node = self.g[i].node;
            for cpi in children(node, "connectionPointIn") {
                for c in children(cpi, "connection") {
                    let Some(r) = attr(c, "refLocalId").and_then(|v| v.trim().parse::<u64>().ok())
                    else {
                        self.ctx
                            .problem(c, None, "a connection without a valid refLocalId");
                        continue;
                    };
                    match self.ids.get(&r) {
                        Some(&p) if p != i => {
                            let pin = attr(c, "formalParameter")
                                .and_then(|f| pins[p].iter().position(|q| *q == f))
                                .unwrap_or(usize::MAX);
                            edges.push((p, i, pin));
                        }
                        Some(_) => self.ctx.problem(c, None, "an element connected to itself"),
                        None => self.ctx.problem(
                            c,
                            None,
                            format!("a connection to localId {r}, which is not an SFC element of this POU"),
                        ),
                    }
                }
            }
        }
        edges.sort_by_key(|&(p, i, pin)| (p, pin, self.g[i].key));
        edges.dedup_by_key(|e| (e.0, e.1));
        for (p, i, _) in edges {
            self.g[p].succ.push(i);
        }
        let mut outs: Vec<Node<'a, 'i>> = self
            .others
            .values()
            .copied()
            .filter(|o| xml::local(*o) == "outVariable")
            .collect();
        outs.sort_by_key(|o| o.range().start);
        for o in outs {
            let step = child(o, "connectionPointIn")
                .and_then(|cpi| child(cpi, "connection"))
                .and_then(|c| attr(c, "refLocalId"))
                .and_then(|v| v.trim().parse::<u64>().ok())
                .and_then(|r| self.ids.get(&r).copied())
                .filter(|&s| matches!(self.g[s].kind, Kind::Step | Kind::Macro));
            if let Some(s) = step {
                self.step_outputs.entry(s).or_default().push(o);
            }
        }
        for b in blocks {
            let step = child(b, "connectionPointIn")
                .and_then(|cpi| child(cpi, "connection"))
                .and_then(|c| attr(c, "refLocalId"))
                .and_then(|v| v.trim().parse::<u64>().ok())
                .and_then(|r| self.ids.get(&r).copied())
                .filter(|&s| matches!(self.g[s].kind, Kind::Step | Kind::Macro));
            match step {
                Some(s) => self.step_actions.entry(s).or_default().push(b),
                None => self.ctx.problem(
                    b,
                    None,
                    "an action block that is not connected to a step; not imported",
                ),
            }
        }
    }

    /// Steps keep their names (renamed only when the language cannot take them or they repeat);
    /// transitions take the name of their named transition or inline body, or `T<n>`.
    fn name_elements(&mut self) {
        let mut steps = NameSet::default();
        for i in 0..self.g.len() {
            if !matches!(self.g[i].kind, Kind::Step | Kind::Macro) {
                continue;
            }
            let node = self.g[i].node;
            let iec = attr(node, "name").unwrap_or("").to_owned();
            let mut name = if names::is_valid(&iec) {
                iec.clone()
            } else {
                let n = names::sanitize(&iec, "Step");
                self.ctx.problem(
                    node,
                    Some(format!("step {iec}")),
                    format!("`{iec}` is not a valid step name; renamed to {n}"),
                );
                n
            };
            let unique = steps.unique(&name);
            if unique != name {
                self.ctx.problem(
                    node,
                    Some(format!("step {iec}")),
                    format!("a second step named {name}; renamed to {unique}"),
                );
                name = unique;
            }
            let key = iec.to_ascii_uppercase();
            if name != iec {
                self.st
                    .renamed
                    .entry(key.clone())
                    .or_insert_with(|| name.clone());
            }
            self.step_names.entry(key).or_insert_with(|| name.clone());
            self.g[i].name = name;
        }
        // Transition names: explicit ones first, so that generated ones avoid them.
        let mut trans = NameSet::default();
        let mut explicit = vec![None; self.g.len()];
        for (i, slot) in explicit.iter_mut().enumerate() {
            if self.g[i].kind != Kind::Trans {
                continue;
            }
            let node = self.g[i].node;
            let cond = child(node, "condition").and_then(first_element);
            let given = attr(node, "name")
                .or_else(|| cond.and_then(|c| attr(c, "name")))
                .map(str::trim)
                .filter(|n| !n.is_empty());
            if let Some(given) = given {
                let mut name = if names::is_valid(given) {
                    given.to_owned()
                } else {
                    names::sanitize(given, "T")
                };
                let unique = trans.unique(&name);
                if unique != name && cond.is_none_or(|c| xml::local(c) != "reference") {
                    self.ctx.problem(
                        node,
                        Some(format!("transition {given}")),
                        format!("a second transition named {name}; renamed to {unique}"),
                    );
                }
                name = unique;
                *slot = Some(name);
            }
        }
        let mut counter = 0usize;
        for (i, slot) in explicit.into_iter().enumerate() {
            if self.g[i].kind != Kind::Trans {
                continue;
            }
            self.g[i].name = match slot {
                Some(n) => n,
                None => loop {
                    counter += 1;
                    let candidate = format!("T{counter}");
                    if trans.insert(&candidate) {
                        break candidate;
                    }
                },
            };
        }
    }

    /// `<actions><action name><body>` of the POU → chart actions.
    fn named_actions(&mut self, pou: Node<'a, 'i>) {
        let Some(list) = child(pou, "actions") else {
            return;
        };
        let mut pending = Vec::new();
        for a in children(list, "action") {
            let Some(iec) = attr(a, "name") else {
                self.ctx
                    .problem(a, None, "an action without a name; not imported");
                continue;
            };
            let element = Some(format!("action {iec}"));
            let mut name = if names::is_valid(iec) {
                iec.to_owned()
            } else {
                let n = names::sanitize(iec, "A");
                self.ctx.problem(
                    a,
                    element.clone(),
                    format!("`{iec}` is not a valid action name; renamed to {n}"),
                );
                n
            };
            let unique = self.var_names.unique(&name);
            if unique != name {
                self.ctx.problem(
                    a,
                    element.clone(),
                    format!("the name {name} is already a variable or action; renamed to {unique}"),
                );
                name = unique;
            }
            if name != iec {
                self.st
                    .renamed
                    .entry(iec.to_ascii_uppercase())
                    .or_insert_with(|| name.clone());
            }
            self.named_actions
                .insert(iec.to_ascii_uppercase(), name.clone());
            pending.push((a, name));
        }
        // Bodies after all names are known (an action may call nothing, but may name steps).
        for (a, name) in pending {
            let body = self.action_body(a, child(a, "body"), &name);
            self.actions.push(Action {
                name,
                doc: xml::documentation(a),
                body,
            });
        }
    }

    fn named_transitions(&mut self, pou: Node<'a, 'i>) {
        let Some(list) = child(pou, "transitions") else {
            return;
        };
        for t in children(list, "transition") {
            match attr(t, "name") {
                Some(n) => {
                    self.named_transitions.insert(n.to_ascii_uppercase(), t);
                }
                None => self
                    .ctx
                    .problem(t, None, "a transition without a name; not imported"),
            }
        }
    }

    /// The body of an action (`body` holds one language element), in the language, or an
    /// empty body with a comment; problems reported against `at`.
    fn action_body(&mut self, at: Node<'_, '_>, body: Option<Node<'_, '_>>, name: &str) -> String {
        let element = Some(format!("action {name}"));
        let Some(lang) = body.and_then(first_element) else {
            self.ctx
                .problem(at, element, "the action has no body; imported empty");
            return "    // not imported: the action has no body\n".to_owned();
        };
        let reason = match xml::local(lang) {
            "ST" => match st::statements(&xml::text(lang), &self.st, 2) {
                Ok(text) => return text,
                Err(e) => format!("line {} of its ST text: {}", e.line, e.reason),
            },
            "IL" => "IL bodies are not supported".to_owned(),
            "FBD" => "FBD bodies are not supported".to_owned(),
            "LD" => "LD bodies are not supported".to_owned(),
            "SFC" => "SFC bodies of actions are not supported".to_owned(),
            other => format!("<{other}> bodies are not supported"),
        };
        self.ctx.problem(
            at,
            element,
            format!("body not imported ({reason}); the action is empty"),
        );
        format!("    // not imported: {}\n", one_line(&reason))
    }

    // ---- the walk

    fn walk(&mut self) -> Vec<El> {
        let steps: Vec<usize> = (0..self.g.len())
            .filter(|&i| matches!(self.g[i].kind, Kind::Step | Kind::Macro))
            .collect();
        let initial: Vec<usize> = steps
            .iter()
            .copied()
            .filter(|&i| attr(self.g[i].node, "initialStep") == Some("true"))
            .collect();
        let start = match initial.as_slice() {
            [] => {
                let Some(&first) = steps.first() else {
                    self.ctx.problem(
                        self.sfc,
                        None,
                        "the SFC body has no step; the chart is empty",
                    );
                    return Vec::new();
                };
                self.ctx.problem(
                    self.g[first].node,
                    None,
                    format!(
                        "no step is marked initialStep; {} (the first step) is the initial step",
                        self.g[first].name
                    ),
                );
                first
            }
            [first, rest @ ..] => {
                for &r in rest {
                    self.ctx.problem(
                        self.g[r].node,
                        Some(format!("step {}", self.g[r].name)),
                        "a second initial step (an IEC chart has one); imported as an ordinary step",
                    );
                }
                *first
            }
        };
        let (els, _) = self.seq(start, 0);
        for i in 0..self.g.len() {
            if !self.visited[i] && matches!(self.g[i].kind, Kind::Step | Kind::Macro) {
                let name = self.g[i].name.clone();
                self.ctx.problem(
                    self.g[i].node,
                    Some(format!("step {name}")),
                    "not reachable from the initial step along the connections; not imported",
                );
            }
        }
        els
    }

    fn unexpected(&mut self, from: usize, to: usize) {
        let (f, t) = (self.g[from].kind, self.g[to].kind);
        let element = self.element(from);
        self.ctx.problem(
            self.g[from].node,
            element,
            format!(
                "{} is followed by {}, which SFC does not allow; the sequence ends here",
                f.describe(),
                t.describe()
            ),
        );
    }

    fn element(&self, i: usize) -> Option<String> {
        match self.g[i].kind {
            Kind::Step | Kind::Macro => Some(format!("step {}", self.g[i].name)),
            Kind::Trans => Some(format!("transition {}", self.g[i].name)),
            _ => None,
        }
    }

    /// One sequence from `start` until it ends or reaches a convergence.
    fn seq(&mut self, start: usize, depth: usize) -> (Vec<El>, Stop) {
        let mut els = Vec::new();
        if depth > MAX_BRANCH_DEPTH {
            self.ctx.problem(
                self.g[start].node,
                None,
                format!("divergences nested deeper than {MAX_BRANCH_DEPTH} levels; the rest is not imported"),
            );
            return (els, Stop::End);
        }
        let mut cur = start;
        loop {
            let kind = self.g[cur].kind;
            if matches!(kind, Kind::SelConv | Kind::SimConv) {
                return (els, Stop::Conv(cur));
            }
            if self.visited[cur] {
                let element = self.element(cur);
                self.ctx.problem(
                    self.g[cur].node,
                    element,
                    format!(
                        "{} reached a second time along the connections; this path ends here",
                        kind.describe()
                    ),
                );
                return (els, Stop::End);
            }
            self.visited[cur] = true;
            let succ = self.g[cur].succ.clone();
            match kind {
                Kind::Step | Kind::Macro => {
                    els.push(self.step(cur));
                    let flow = match succ.as_slice() {
                        [] => Flow::Stop(Stop::End),
                        [n] => match self.g[*n].kind {
                            Kind::Trans | Kind::SelDiv => Flow::Next(*n),
                            Kind::SimConv | Kind::SelConv => Flow::Stop(Stop::Conv(*n)),
                            _ => {
                                self.unexpected(cur, *n);
                                Flow::Stop(Stop::End)
                            }
                        },
                        // Several transitions straight after a step: a selection.
                        _ => self.selection(&succ, &mut els, depth),
                    };
                    match flow {
                        Flow::Next(n) => cur = n,
                        Flow::Stop(s) => return (els, s),
                    }
                }
                Kind::Trans => {
                    let t = self.transition(cur);
                    if succ.len() > 1 {
                        let element = self.element(cur);
                        self.ctx.problem(
                            self.g[cur].node,
                            element,
                            "the transition is connected to several elements without a divergence; only the first is followed",
                        );
                    }
                    let Some(&n) = succ.first() else {
                        let element = self.element(cur);
                        self.ctx
                            .problem(self.g[cur].node, element, "the transition leads nowhere");
                        els.push(El::Trans(t));
                        return (els, Stop::End);
                    };
                    match self.g[n].kind {
                        Kind::Jump => {
                            let target = self.jump_target(n);
                            els.push(El::Jump(t, target));
                            return (els, Stop::End);
                        }
                        Kind::Step | Kind::Macro if self.visited[n] => {
                            let target = self.g[n].name.clone();
                            els.push(El::Jump(t, target));
                            return (els, Stop::End);
                        }
                        Kind::Step | Kind::Macro | Kind::SimDiv => {
                            els.push(El::Trans(t));
                            cur = n;
                        }
                        Kind::SelConv => {
                            if let Some(j) = self.jump_after(n) {
                                // The branches converge only to jump: each one is the jump.
                                self.visited[n] = true;
                                let target = self.jump_target(j);
                                els.push(El::Jump(t, target));
                                return (els, Stop::End);
                            }
                            els.push(El::Trans(t));
                            return (els, Stop::Conv(n));
                        }
                        _ => {
                            els.push(El::Trans(t));
                            self.unexpected(cur, n);
                            return (els, Stop::End);
                        }
                    }
                }
                Kind::SelDiv => match self.selection(&succ, &mut els, depth) {
                    Flow::Next(n) => cur = n,
                    Flow::Stop(s) => return (els, s),
                },
                Kind::SimDiv => match self.parallel(cur, &succ, &mut els, depth) {
                    Flow::Next(n) => cur = n,
                    Flow::Stop(s) => return (els, s),
                },
                Kind::Jump => {
                    self.ctx.problem(
                        self.g[cur].node,
                        None,
                        "a jump step that does not follow a transition; not imported",
                    );
                    return (els, Stop::End);
                }
                Kind::SelConv | Kind::SimConv => return (els, Stop::Conv(cur)),
            }
        }
    }

    /// The convergence of `kind` that at least two branches reach, if any.
    fn common_convergence(&self, stops: &[&Stop], kind: Kind) -> Option<usize> {
        let mut count: HashMap<usize, usize> = HashMap::new();
        for s in stops {
            if let Stop::Conv(c) = s
                && self.g[*c].kind == kind
            {
                *count.entry(*c).or_default() += 1;
            }
        }
        let best = count
            .into_iter()
            .max_by_key(|&(c, n)| (n, usize::MAX - c))?;
        (best.1 >= 2 || stops.len() == 1).then_some(best.0)
    }

    /// After passing convergence `c`: where the sequence goes on.
    fn after_convergence(&mut self, c: usize) -> Flow {
        if self.visited[c] {
            self.ctx.problem(
                self.g[c].node,
                None,
                "a convergence reached from two divergences; this path ends here",
            );
            return Flow::Stop(Stop::End);
        }
        self.visited[c] = true;
        match self.g[c].succ.first() {
            None => Flow::Stop(Stop::End),
            Some(&n) => Flow::Next(n),
        }
    }

    fn selection(&mut self, succ: &[usize], els: &mut Vec<El>, depth: usize) -> Flow {
        let mut branches: Vec<(Vec<El>, Stop)> = Vec::with_capacity(succ.len());
        for &b in succ {
            branches.push(self.seq(b, depth + 1));
        }
        let stops: Vec<&Stop> = branches.iter().map(|(_, s)| s).collect();
        let jumped = |b: &(Vec<El>, Stop)| matches!(b.1, Stop::End) && ends_in_jump(&b.0);
        if let Some(c) = self.common_convergence(&stops, Kind::SelConv) {
            for (k, b) in branches.iter().enumerate() {
                if !jumped(b) && !matches!(b.1, Stop::Conv(x) if x == c) {
                    self.ctx.problem(
                        self.g[succ[k]].node,
                        None,
                        format!("branch {} of a selection neither reaches its convergence nor ends in a jump", k + 1),
                    );
                }
            }
            els.push(El::Alt(branches.into_iter().map(|(e, _)| e).collect()));
            return self.after_convergence(c);
        }
        let open: Vec<usize> = (0..branches.len())
            .filter(|&k| !jumped(&branches[k]))
            .collect();
        let Some(&k) = open.first() else {
            if matches!(els.last(), Some(El::Step { .. }))
                && branches
                    .iter()
                    .all(|(b, _)| b.len() == 1 && matches!(b[0], El::Jump(..)))
            {
                // Only jumps after a step: `step S; jump A ...; jump B ...` (text order).
                for (b, _) in branches {
                    els.extend(b);
                }
                return Flow::Stop(Stop::End);
            }
            // Every branch ends in a jump. The longest one that goes on after its first
            // transition continues the sequence after the `alt` (the same chart without
            // nesting the rest of the sequence in it, as Beremiz draws a sequence with a
            // jump back as an alternative at each step): when it is longer than the others,
            // or when a branch would end in an `alt` (a branch ends in a step and its jumps).
            let mut all: Vec<Vec<El>> = branches.into_iter().map(|(e, _)| e).collect();
            let longest = (0..all.len())
                .filter(|&i| all[i].len() > 1 && matches!(all[i][0], El::Trans(_)))
                .max_by_key(|&i| (all[i].len(), usize::MAX - i));
            let nested = all.iter().any(|b| matches!(b.last(), Some(El::Alt(_))));
            let tail = match longest {
                Some(i)
                    if all.len() > 1
                        && (nested
                            || all
                                .iter()
                                .enumerate()
                                .all(|(j, b)| j == i || b.len() < all[i].len())) =>
                {
                    all[i].split_off(1)
                }
                _ => Vec::new(),
            };
            els.push(El::Alt(all));
            els.extend(tail);
            return Flow::Stop(Stop::End);
        };
        for &other in &open[1..] {
            self.ctx.problem(
                self.g[succ[other]].node,
                None,
                format!(
                    "branch {} of a selection neither rejoins the others nor ends in a jump",
                    other + 1
                ),
            );
        }
        // Branch k continues the sequence: its first transition stays in the alternative,
        // the rest follows it.
        let mut all: Vec<(Vec<El>, Stop)> = branches;
        let (mut cont, stop) = std::mem::replace(&mut all[k], (Vec::new(), Stop::End));
        let tail = if cont.len() > 1 {
            cont.split_off(1)
        } else {
            Vec::new()
        };
        let after_step = matches!(els.last(), Some(El::Step { .. }));
        let single_jump = |b: &[El]| b.len() == 1 && matches!(b[0], El::Jump(..));
        let only_jumps = all
            .iter()
            .enumerate()
            .all(|(i, (b, _))| i == k || single_jump(b));
        if k == 0 && after_step && only_jumps && matches!(cont.first(), Some(El::Trans(_))) {
            // `step S; jump ...; trans T; ...`: the normal successor is tried first.
            for (b, _) in all.into_iter().skip(1) {
                els.extend(b);
            }
            els.extend(cont);
        } else {
            all[k].0 = cont;
            els.push(El::Alt(all.into_iter().map(|(e, _)| e).collect()));
        }
        els.extend(tail);
        Flow::Stop(stop)
    }

    fn parallel(&mut self, div: usize, succ: &[usize], els: &mut Vec<El>, depth: usize) -> Flow {
        let mut branches = Vec::with_capacity(succ.len());
        for &b in succ {
            branches.push(self.seq(b, depth + 1));
        }
        let stops: Vec<&Stop> = branches.iter().map(|(_, s)| s).collect();
        let conv = self.common_convergence(&stops, Kind::SimConv);
        for (k, (_, s)) in branches.iter().enumerate() {
            let ok = match (s, conv) {
                (Stop::Conv(x), Some(c)) => *x == c,
                (Stop::End, _) => true,
                (Stop::Conv(_), None) => false,
            };
            if !ok {
                self.ctx.problem(
                    self.g[succ[k]].node,
                    None,
                    format!(
                        "branch {} of a simultaneous divergence does not reach its convergence",
                        k + 1
                    ),
                );
            }
        }
        if succ.len() < 2 {
            self.ctx.problem(
                self.g[div].node,
                None,
                "a simultaneous divergence with fewer than two branches",
            );
        }
        els.push(El::Par(branches.into_iter().map(|(e, _)| e).collect()));
        match conv {
            Some(c) => self.after_convergence(c),
            None => Flow::Stop(Stop::End),
        }
    }

    /// The jump step that is the only successor of selection convergence `c`, if it is one.
    fn jump_after(&self, c: usize) -> Option<usize> {
        match self.g[c].succ.as_slice() {
            [j] if self.g[*j].kind == Kind::Jump => Some(*j),
            _ => None,
        }
    }

    /// The target of jump step `j` (marked visited; a problem only the first time).
    fn jump_target(&mut self, j: usize) -> String {
        let node = self.g[j].node;
        let first = !self.visited[j];
        self.visited[j] = true;
        let target = attr(node, "targetName").unwrap_or("").trim().to_owned();
        if let Some(name) = self.step_names.get(&target.to_ascii_uppercase()) {
            return name.clone();
        }
        let fallback = names::sanitize(&target, "Step");
        if !first {
            return fallback;
        }
        self.ctx.problem(
            node,
            Some(format!("jump step to {target}")),
            "the target is not a step of this POU",
        );
        fallback
    }

    // ---- elements

    fn step(&mut self, i: usize) -> El {
        let node = self.g[i].node;
        let name = self.g[i].name.clone();
        let element = Some(format!("step {name}"));
        let mut lines = Vec::new();
        if self.g[i].kind == Kind::Macro {
            self.ctx.problem(
                node,
                element.clone(),
                "macro steps are not supported; imported as an empty step",
            );
            lines.push("// macro step: its body was not imported".to_owned());
        }
        let blocks = self.step_actions.remove(&i).unwrap_or_default();
        let mut inline_count: HashMap<String, usize> = HashMap::new();
        for b in blocks {
            for a in children(b, "action") {
                let q_raw = attr(a, "qualifier")
                    .unwrap_or("N")
                    .trim()
                    .to_ascii_uppercase();
                let q_raw = if q_raw.is_empty() {
                    "N".to_owned()
                } else {
                    q_raw
                };
                let mut q = q_raw.clone();
                if !QUALIFIERS.contains(&q.as_str()) {
                    self.ctx.problem(
                        a,
                        element.clone(),
                        format!("unknown qualifier {q_raw}; imported as N"),
                    );
                    q = "N".to_owned();
                }
                let duration = attr(a, "duration").map(str::trim).filter(|d| !d.is_empty());
                let mut time = None;
                if TIMED.contains(&q.as_str()) {
                    // A time literal or a variable, nothing longer.
                    let simple = |t: &String| !t.contains([' ', '(']);
                    match duration.map(|d| (d, st::condition(d, &self.st))) {
                        Some((_, Ok(t))) if simple(&t) => time = Some(t),
                        Some((d, _)) => {
                            self.ctx.problem(
                                a,
                                element.clone(),
                                format!(
                                    "the duration `{d}` is not a time; qualifier {q} imported as N"
                                ),
                            );
                            q = "N".to_owned();
                        }
                        None => {
                            self.ctx.problem(
                                a,
                                element.clone(),
                                format!("qualifier {q} without a duration; imported as N"),
                            );
                            q = "N".to_owned();
                        }
                    }
                } else if let Some(d) = duration {
                    self.ctx.problem(
                        a,
                        element.clone(),
                        format!("qualifier {q} takes no duration; `{d}` is ignored"),
                    );
                }
                let operand = if let Some(r) = child(a, "reference") {
                    let iec = attr(r, "name").unwrap_or("").trim();
                    let upper = iec.to_ascii_uppercase();
                    if let Some(n) = self.named_actions.get(&upper) {
                        n.clone()
                    } else if self.st.elementary.contains_key(&upper)
                        || self.st.renamed.contains_key(&upper)
                    {
                        self.st
                            .renamed
                            .get(&upper)
                            .cloned()
                            .unwrap_or_else(|| iec.to_owned())
                    } else {
                        self.ctx.problem(
                            a,
                            element.clone(),
                            format!("`{iec}` is neither an action nor a variable of the POU"),
                        );
                        names::sanitize(iec, "A")
                    }
                } else if let Some(inline) = child(a, "inline") {
                    let n = inline_count.entry(q.clone()).or_insert(0);
                    *n += 1;
                    let base = if *n == 1 {
                        format!("{name}_{q}")
                    } else {
                        format!("{name}_{q}{n}")
                    };
                    let action = self.var_names.unique(&base);
                    let body = self.action_body(a, Some(inline), &action);
                    self.actions.push(Action {
                        name: action.clone(),
                        doc: xml::documentation(a),
                        body,
                    });
                    action
                } else {
                    self.ctx.problem(
                        a,
                        element.clone(),
                        "an action without a reference or inline body; not imported",
                    );
                    continue;
                };
                lines.push(match time {
                    Some(t) => format!("{q} {operand}, {t};"),
                    None => format!("{q} {operand};"),
                });
            }
        }
        // A variable wired to the step's action output is on while the step is active.
        for o in self.step_outputs.remove(&i).unwrap_or_default() {
            let expr = child(o, "expression").map(xml::text).unwrap_or_default();
            let expr = expr.trim();
            let path = st::condition(expr, &self.st).ok().filter(|p| {
                p.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
            });
            match path {
                Some(p) if attr(o, "negated") != Some("true") => lines.push(format!("N {p};")),
                _ => self.ctx.problem(
                    o,
                    element.clone(),
                    format!("the output variable `{expr}` wired to the step is not supported (only a plain, not negated variable is)"),
                ),
            }
        }
        let mut doc = xml::documentation(node);
        // CODESYS keeps a step's comment and its own actions in its vendor data.
        if let Some(add) = child(node, "addData") {
            for a in add
                .descendants()
                .filter(|d| d.is_element() && xml::local(*d) == "attribute")
            {
                let value = xml::text(a);
                let value = value.trim();
                let upper = value.to_ascii_uppercase();
                let named = self.named_actions.get(&upper).cloned();
                if attr(a, "guid") == Some(CODESYS_COMMENT) {
                    if doc.is_none() && !value.is_empty() {
                        doc = Some(value.to_owned());
                    }
                } else if attr(a, "guid") == Some(CODESYS_STEP_ACTION) && !value.is_empty() {
                    match named {
                        Some(n) => lines.push(format!("N {n};")),
                        None => self.ctx.problem(
                            a,
                            element.clone(),
                            format!("the step action {value} (CODESYS vendor data) is not an action of the POU"),
                        ),
                    }
                } else if named.is_some() {
                    self.ctx.problem(
                        a,
                        element.clone(),
                        format!("the step's entry or exit action {value} (CODESYS vendor data) is not imported"),
                    );
                }
            }
        }
        El::Step { name, doc, lines }
    }

    fn transition(&mut self, i: usize) -> Trans {
        let node = self.g[i].node;
        let name = self.g[i].name.clone();
        let result = self.condition(node);
        let (cond, comment) = match result {
            Ok(c) => (c, None),
            Err(reason) => {
                self.ctx.problem(
                    node,
                    Some(format!("transition {name}")),
                    format!("condition not imported ({reason}); imported as FALSE"),
                );
                (
                    "FALSE".to_owned(),
                    Some(format!("condition not imported: {reason}")),
                )
            }
        };
        Trans {
            name,
            doc: xml::documentation(node),
            cond,
            comment,
        }
    }

    fn condition(&mut self, node: Node<'_, '_>) -> Result<String, String> {
        let Some(cond) = child(node, "condition") else {
            return Err("the transition has no condition".to_owned());
        };
        let negated = attr(cond, "negated") == Some("true");
        let Some(inner) = first_element(cond) else {
            return Err("the condition is empty".to_owned());
        };
        let text = match xml::local(inner) {
            "inline" => {
                let name = attr(inner, "name").unwrap_or("").trim().to_owned();
                self.body_condition(first_element(inner), &name)?
            }
            "reference" => {
                let n = attr(inner, "name").unwrap_or("").trim();
                let upper = n.to_ascii_uppercase();
                let Some(t) = self.named_transitions.get(&upper).copied() else {
                    return Err(format!("the named transition {n} is not in the POU"));
                };
                if let Some(done) = self.network_conditions.get(&upper) {
                    // A network is translated once: its calls are in `pre` already.
                    done.clone()?
                } else {
                    let body = child(t, "body").and_then(first_element);
                    let result = self.body_condition(body, n);
                    if body.is_some_and(|b| matches!(xml::local(b), "FBD" | "LD")) {
                        self.network_conditions.insert(upper, result.clone());
                    }
                    result?
                }
            }
            "connectionPointIn" => {
                let mut tr = Translator {
                    names: &self.st,
                    fb_types: &self.fb_types,
                    calls: Vec::new(),
                };
                let text = tr.condition(&self.sfc_net, &mut self.sfc_state, inner);
                self.pre_calls.append(&mut tr.calls);
                text?
            }
            other => return Err(format!("<{other}> conditions are not supported")),
        };
        Ok(if negated { negate(&text) } else { text })
    }

    /// The condition in a body (`inline` or a named transition's): ST text, or an FBD/LD
    /// network whose output variable or coil named `name` (or only one) gives the value.
    fn body_condition(&mut self, lang: Option<Node<'_, '_>>, name: &str) -> Result<String, String> {
        let Some(lang) = lang else {
            return Err("the condition has no body".to_owned());
        };
        match xml::local(lang) {
            "ST" => st::condition(&xml::text(lang), &self.st)
                .map_err(|e| format!("line {} of its ST text: {}", e.line, e.reason)),
            l @ ("FBD" | "LD") => {
                let net = Net::new(lang.children());
                let result = net.result(name).map_err(|e| format!("{l} body: {e}"))?;
                let mut tr = Translator {
                    names: &self.st,
                    fb_types: &self.fb_types,
                    calls: Vec::new(),
                };
                let text = tr
                    .condition(&net, &mut NetState::default(), result)
                    .map_err(|e| format!("{l} body: {e}"))?;
                self.pre_calls.append(&mut tr.calls);
                Ok(text)
            }
            other => Err(format!("{other} conditions are not supported")),
        }
    }
}
