//! Charts as one PLCopen TC6 XML 2.01 document (`charts.xml`, `export.md` §4).
//!
//! The analysis collects each chart into the plain data model below ([`Project`], [`Pou`],
//! [`Element`]); [`write`] lays it out top-down and writes the XML. The model is structural
//! (sequences, divergences with their branches), not a graph: `localId`s, the
//! `connectionPointIn/connection refLocalId` wiring, `priority` attributes and positions all
//! follow from the structure, so they cannot disagree with it.
//!
//! Output rules:
//!
//! * Deterministic: no clock, no paths; `creationDateTime` (required by the schema) is the fixed
//!   value [`CREATION_DATE_TIME`].
//! * Text is escaped (`&`, `<`, `>`, `"`, and control characters other than tab and line feed
//!   are dropped, since XML 1.0 cannot carry them).
//! * `localId`s are numbered from 1 in document order, unique in the document.
//! * Layout: one column per branch, branches side by side left to right in priority order,
//!   each element in its own row; action blocks to the right of their step.

use std::fmt::Write as _;

/// The namespace of TC6 XML 2.01.
pub const NAMESPACE: &str = "http://www.plcopen.org/xml/tc6_0201";
/// The fixed `creationDateTime` of the file header (the schema requires one; a clock would
/// break byte-identical builds).
pub const CREATION_DATE_TIME: &str = "1970-01-01T00:00:00";

/// The whole document: the charts' function blocks and the global variables they share.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Project {
    pub pous: Vec<Pou>,
    /// Global variables (the symbols the charts use, with their direct addresses), written into
    /// one configuration `Charts`; none → no configuration.
    pub globals: Vec<Variable>,
}

/// One chart as a function block with an SFC body.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Pou {
    pub name: String,
    pub inputs: Vec<Variable>,
    pub outputs: Vec<Variable>,
    pub in_outs: Vec<Variable>,
    pub locals: Vec<Variable>,
    /// Global variables the body uses (`VAR_EXTERNAL`).
    pub externals: Vec<Variable>,
    /// Named actions (`<actions>`), referenced by name from action associations.
    pub actions: Vec<NamedAction>,
    /// The SFC network: a sequence starting with the initial step.
    pub body: Vec<Element>,
    /// What the POU's documentation says; empty → no documentation element.
    pub documentation: String,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variable {
    pub name: String,
    pub ty: IecType,
    /// A direct address (`%IX1.0`), for global variables.
    pub address: Option<String>,
    /// An initial value as an IEC literal.
    pub initial: Option<String>,
    pub documentation: Option<String>,
}

/// A named action of the POU with an ST body.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NamedAction {
    pub name: String,
    /// The body in ST, one statement a line.
    pub body: String,
    pub documentation: Option<String>,
}

/// The IEC types a chart variable can have.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum IecType {
    Bool,
    Byte,
    Word,
    Dword,
    Int,
    Dint,
    Real,
    Time,
    Date,
    Tod,
    Dt,
    /// `STRING[n]`.
    String(u16),
    /// A function block type by name (`<derived name="TON"/>`): the standard function blocks.
    Derived(String),
}

/// One element of an SFC sequence.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Element {
    Step(Step),
    Transition(Transition),
    /// A jump step: the sequence continues at the named step. Ends its branch.
    Jump(String),
    /// A simultaneous divergence; every branch is a sequence beginning and ending with a step;
    /// the branches are joined by a simultaneous convergence.
    Simultaneous(Vec<Vec<Element>>),
    /// A selection divergence; its branches, left to right, are the alternatives in priority
    /// order (each begins with a transition, which gets `priority` = its position, from 1). A
    /// branch that ends with a [`Element::Jump`] ends there; the other ("open") branches are
    /// joined by a selection convergence when there are two or more, and a single open branch
    /// continues the sequence without one.
    Selection(Vec<Vec<Element>>),
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Step {
    pub name: String,
    pub initial: bool,
    /// The action associations, in order: one action block.
    pub actions: Vec<ActionAssoc>,
    pub documentation: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Transition {
    /// Names the inline condition body.
    pub name: String,
    /// The condition in ST.
    pub condition: String,
    pub documentation: Option<String>,
}

/// An action qualifier of IEC 61131-3 (`P1`/`P0`: on entering / leaving the step).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Qualifier {
    N,
    R,
    S,
    L,
    D,
    P,
    P1,
    P0,
    Sd,
    Ds,
    Sl,
    /// Delayed and limited (IEC charts).
    Dl,
}

impl Qualifier {
    pub fn as_str(self) -> &'static str {
        match self {
            Qualifier::N => "N",
            Qualifier::R => "R",
            Qualifier::S => "S",
            Qualifier::L => "L",
            Qualifier::D => "D",
            Qualifier::P => "P",
            Qualifier::P1 => "P1",
            Qualifier::P0 => "P0",
            Qualifier::Sd => "SD",
            Qualifier::Ds => "DS",
            Qualifier::Sl => "SL",
            Qualifier::Dl => "DL",
        }
    }
}

/// What an action association runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ActionBody {
    /// A BOOL variable (or a named action).
    Reference(String),
    /// ST statements.
    Inline(String),
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ActionAssoc {
    pub qualifier: Qualifier,
    /// An IEC duration (`T#5S`) or a TIME variable, for `L D SD DS SL`.
    pub duration: Option<String>,
    pub body: ActionBody,
}

// ------------------------------------------------------------------------------------ layout

/// Width of a column (a step, its action block and some air).
const COL_W: i64 = 340;
/// Height of a row.
const ROW_H: i64 = 50;
const MARGIN: i64 = 20;
const STEP_H: i64 = 30;
const TRANS_W: i64 = 20;
const TRANS_H: i64 = 2;
const JUMP_W: i64 = 20;
const JUMP_H: i64 = 13;
const ACTION_H: i64 = 30;
const ACTION_W: i64 = 200;
const ACTION_GAP: i64 = 30;
/// Deeper nesting than this is not laid out (the parser's nesting limit is far below it).
const MAX_DEPTH: usize = 200;

/// An output pin: the element it belongs to and its absolute position.
#[derive(Debug, Clone, Copy)]
struct Pin {
    id: u64,
    x: i64,
    y: i64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Branching {
    Selection,
    Simultaneous,
}

/// One laid-out element, in document order.
enum Node<'a> {
    Step {
        id: u64,
        step: &'a Step,
        x: i64,
        y: i64,
        w: i64,
        input: Option<Pin>,
    },
    Actions {
        id: u64,
        first_action: u64,
        step: Pin,
        x: i64,
        y: i64,
        actions: &'a [ActionAssoc],
    },
    Transition {
        id: u64,
        t: &'a Transition,
        x: i64,
        y: i64,
        input: Option<Pin>,
        priority: Option<usize>,
    },
    Jump {
        id: u64,
        target: &'a str,
        x: i64,
        y: i64,
        input: Option<Pin>,
    },
    Divergence {
        id: u64,
        kind: Branching,
        x: i64,
        y: i64,
        w: i64,
        input: Option<Pin>,
        /// Output pins, relative x.
        outputs: Vec<i64>,
    },
    Convergence {
        id: u64,
        kind: Branching,
        x: i64,
        y: i64,
        w: i64,
        inputs: Vec<Pin>,
    },
}

fn center(col: i64) -> i64 {
    MARGIN + col * COL_W + 60
}

fn row_y(row: i64) -> i64 {
    MARGIN + row * ROW_H
}

fn step_width(name: &str) -> i64 {
    (name.chars().count() as i64 * 8 + 20).clamp(80, 200)
}

/// Columns a sequence needs.
fn width(elems: &[Element], depth: usize) -> i64 {
    if depth > MAX_DEPTH {
        return 1;
    }
    elems
        .iter()
        .map(|e| match e {
            Element::Simultaneous(b) | Element::Selection(b) => {
                b.iter().map(|s| width(s, depth + 1)).sum::<i64>().max(1)
            }
            _ => 1,
        })
        .max()
        .unwrap_or(1)
}

struct Layout<'a> {
    nodes: Vec<Node<'a>>,
    next_id: u64,
}

impl<'a> Layout<'a> {
    fn id(&mut self) -> u64 {
        self.next_id += 1;
        self.next_id
    }

    /// Lays out a sequence from `row` in column `col` after `input`; returns the open tail
    /// (`None` when the sequence ended with a jump or is empty without input) and the first
    /// free row.
    fn sequence(
        &mut self,
        elems: &'a [Element],
        col: i64,
        mut row: i64,
        mut input: Option<Pin>,
        depth: usize,
        priority: Option<usize>,
    ) -> (Option<Pin>, i64) {
        let cx = center(col);
        let mut open = true;
        for (i, elem) in elems.iter().enumerate() {
            if !open || depth > MAX_DEPTH {
                break;
            }
            match elem {
                Element::Step(step) => {
                    let id = self.id();
                    let w = step_width(&step.name);
                    let (x, y) = (cx - w / 2, row_y(row));
                    self.nodes.push(Node::Step {
                        id,
                        step,
                        x,
                        y,
                        w,
                        input,
                    });
                    let mut span = 1;
                    if !step.actions.is_empty() {
                        let block = self.id();
                        let first_action = self.next_id + 1;
                        self.next_id += step.actions.len() as u64;
                        self.nodes.push(Node::Actions {
                            id: block,
                            first_action,
                            step: Pin {
                                id,
                                x: x + w,
                                y: y + STEP_H / 2,
                            },
                            x: x + w + ACTION_GAP,
                            y,
                            actions: &step.actions,
                        });
                        let h = ACTION_H * step.actions.len() as i64;
                        span = (h + 10 + ROW_H - 1) / ROW_H;
                    }
                    input = Some(Pin {
                        id,
                        x: cx,
                        y: y + STEP_H,
                    });
                    row += span.max(1);
                }
                Element::Transition(t) => {
                    let id = self.id();
                    let (x, y) = (cx - TRANS_W / 2, row_y(row) + ROW_H / 2);
                    self.nodes.push(Node::Transition {
                        id,
                        t,
                        x,
                        y,
                        input,
                        priority: if i == 0 { priority } else { None },
                    });
                    input = Some(Pin {
                        id,
                        x: cx,
                        y: y + TRANS_H,
                    });
                    row += 1;
                }
                Element::Jump(target) => {
                    let id = self.id();
                    self.nodes.push(Node::Jump {
                        id,
                        target,
                        x: cx - JUMP_W / 2,
                        y: row_y(row),
                        input,
                    });
                    row += 1;
                    input = None;
                    open = false;
                }
                Element::Simultaneous(branches) | Element::Selection(branches) => {
                    let kind = if matches!(elem, Element::Selection(_)) {
                        Branching::Selection
                    } else {
                        Branching::Simultaneous
                    };
                    let (tail, next_row) =
                        self.branching(kind, branches, col, row, input, depth + 1);
                    row = next_row;
                    input = tail;
                    open = tail.is_some();
                }
            }
        }
        (if open { input } else { None }, row)
    }

    fn branching(
        &mut self,
        kind: Branching,
        branches: &'a [Vec<Element>],
        col: i64,
        row: i64,
        input: Option<Pin>,
        depth: usize,
    ) -> (Option<Pin>, i64) {
        let h = if kind == Branching::Selection { 1 } else { 3 };
        let mut cols = Vec::with_capacity(branches.len());
        let mut c = col;
        for b in branches {
            cols.push(c);
            c += width(b, depth + 1);
        }
        let left = center(col);
        let right = cols.last().map_or(left, |&c| center(c));
        let div = self.id();
        let y = row_y(row) + ROW_H / 2;
        self.nodes.push(Node::Divergence {
            id: div,
            kind,
            x: left,
            y,
            w: (right - left).max(1),
            input,
            outputs: cols.iter().map(|&c| center(c) - left).collect(),
        });
        let mut tails = Vec::new();
        let mut end = row + 1;
        for (i, (b, &bc)) in branches.iter().zip(&cols).enumerate() {
            let pin = Pin {
                id: div,
                x: center(bc),
                y: y + h,
            };
            let priority = (kind == Branching::Selection).then_some(i + 1);
            let (tail, r) = self.sequence(b, bc, row + 1, Some(pin), depth + 1, priority);
            end = end.max(r);
            tails.extend(tail);
        }
        if tails.len() < 2 && kind == Branching::Selection {
            return (tails.first().copied(), end);
        }
        if tails.is_empty() {
            return (None, end);
        }
        let conv = self.id();
        let cy = row_y(end) + ROW_H / 2;
        let cl = tails.iter().map(|p| p.x).min().unwrap_or(left);
        let cr = tails.iter().map(|p| p.x).max().unwrap_or(left);
        self.nodes.push(Node::Convergence {
            id: conv,
            kind,
            x: cl,
            y: cy,
            w: (cr - cl).max(1),
            inputs: tails,
        });
        (
            Some(Pin {
                id: conv,
                x: left,
                y: cy + h,
            }),
            end + 1,
        )
    }
}

// ------------------------------------------------------------------------------------ writer

/// Escapes text for an attribute value or element content.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\t' | '\n' => out.push(c),
            '\r' => {}
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => {}
            c => out.push(c),
        }
    }
    out
}

struct Writer {
    out: String,
}

impl Writer {
    fn line(&mut self, indent: usize, text: &str) {
        for _ in 0..indent {
            self.out.push_str("  ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn text_element(&mut self, indent: usize, element: &str, text: &str) {
        self.line(
            indent,
            &format!("<{element}><xhtml:p>{}</xhtml:p></{element}>", escape(text)),
        );
    }

    fn ty(&mut self, indent: usize, ty: &IecType) {
        let inner = match ty {
            IecType::Bool => "<BOOL/>".to_owned(),
            IecType::Byte => "<BYTE/>".to_owned(),
            IecType::Word => "<WORD/>".to_owned(),
            IecType::Dword => "<DWORD/>".to_owned(),
            IecType::Int => "<INT/>".to_owned(),
            IecType::Dint => "<DINT/>".to_owned(),
            IecType::Real => "<REAL/>".to_owned(),
            IecType::Time => "<TIME/>".to_owned(),
            IecType::Date => "<DATE/>".to_owned(),
            IecType::Tod => "<TOD/>".to_owned(),
            IecType::Dt => "<DT/>".to_owned(),
            IecType::String(n) => format!("<string length=\"{n}\"/>"),
            IecType::Derived(name) => format!("<derived name=\"{}\"/>", escape(name)),
        };
        self.line(indent, &format!("<type>{inner}</type>"));
    }

    fn variables(&mut self, indent: usize, list: &str, vars: &[Variable]) {
        if vars.is_empty() {
            return;
        }
        self.line(indent, &format!("<{list}>"));
        for v in vars {
            let mut open = format!("<variable name=\"{}\"", escape(&v.name));
            if let Some(a) = &v.address {
                let _ = write!(open, " address=\"{}\"", escape(a));
            }
            open.push('>');
            self.line(indent + 1, &open);
            self.ty(indent + 2, &v.ty);
            if let Some(init) = &v.initial {
                self.line(
                    indent + 2,
                    &format!(
                        "<initialValue><simpleValue value=\"{}\"/></initialValue>",
                        escape(init)
                    ),
                );
            }
            if let Some(doc) = &v.documentation {
                self.text_element(indent + 2, "documentation", doc);
            }
            self.line(indent + 1, "</variable>");
        }
        self.line(indent, &format!("</{list}>"));
    }

    /// `<connectionPointIn>` with its relative pin and the connection to `from`.
    fn input(&mut self, indent: usize, rel: (i64, i64), abs: (i64, i64), from: Option<Pin>) {
        self.line(indent, "<connectionPointIn>");
        self.line(
            indent + 1,
            &format!("<relPosition x=\"{}\" y=\"{}\"/>", rel.0, rel.1),
        );
        if let Some(p) = from {
            self.line(indent + 1, &format!("<connection refLocalId=\"{}\">", p.id));
            self.line(
                indent + 2,
                &format!("<position x=\"{}\" y=\"{}\"/>", abs.0, abs.1),
            );
            self.line(
                indent + 2,
                &format!("<position x=\"{}\" y=\"{}\"/>", p.x, p.y),
            );
            self.line(indent + 1, "</connection>");
        }
        self.line(indent, "</connectionPointIn>");
    }

    fn output(&mut self, indent: usize, element: &str, rel: (i64, i64), formal: bool) {
        let formal = if formal { " formalParameter=\"\"" } else { "" };
        self.line(indent, &format!("<{element}{formal}>"));
        self.line(
            indent + 1,
            &format!("<relPosition x=\"{}\" y=\"{}\"/>", rel.0, rel.1),
        );
        self.line(indent, &format!("</{element}>"));
    }

    fn st_body(&mut self, indent: usize, text: &str) {
        self.line(
            indent,
            &format!("<ST><xhtml:p>{}</xhtml:p></ST>", escape(text)),
        );
    }

    fn node(&mut self, n: &Node<'_>) {
        let i = 6;
        match n {
            Node::Step {
                id,
                step,
                x,
                y,
                w,
                input,
            } => {
                let initial = if step.initial {
                    " initialStep=\"true\""
                } else {
                    ""
                };
                self.line(
                    i,
                    &format!(
                        "<step localId=\"{id}\" height=\"{STEP_H}\" width=\"{w}\" name=\"{}\"{initial}>",
                        escape(&step.name)
                    ),
                );
                self.line(i + 1, &format!("<position x=\"{x}\" y=\"{y}\"/>"));
                if input.is_some() {
                    self.input(i + 1, (w / 2, 0), (x + w / 2, *y), *input);
                }
                self.output(i + 1, "connectionPointOut", (w / 2, STEP_H), true);
                if !step.actions.is_empty() {
                    self.output(i + 1, "connectionPointOutAction", (*w, STEP_H / 2), true);
                }
                if let Some(doc) = &step.documentation {
                    self.text_element(i + 1, "documentation", doc);
                }
                self.line(i, "</step>");
            }
            Node::Actions {
                id,
                first_action,
                step,
                x,
                y,
                actions,
            } => {
                let h = ACTION_H * actions.len() as i64;
                self.line(
                    i,
                    &format!("<actionBlock localId=\"{id}\" width=\"{ACTION_W}\" height=\"{h}\">"),
                );
                self.line(i + 1, &format!("<position x=\"{x}\" y=\"{y}\"/>"));
                self.input(i + 1, (0, STEP_H / 2), (*x, y + STEP_H / 2), Some(*step));
                for (k, a) in actions.iter().enumerate() {
                    let aid = first_action + k as u64;
                    let mut open = format!(
                        "<action localId=\"{aid}\" qualifier=\"{}\"",
                        a.qualifier.as_str()
                    );
                    if let Some(d) = &a.duration {
                        let _ = write!(open, " duration=\"{}\"", escape(d));
                    }
                    open.push('>');
                    self.line(i + 1, &open);
                    self.line(
                        i + 2,
                        &format!("<relPosition x=\"0\" y=\"{}\"/>", ACTION_H * k as i64),
                    );
                    match &a.body {
                        ActionBody::Reference(name) => {
                            self.line(i + 2, &format!("<reference name=\"{}\"/>", escape(name)))
                        }
                        ActionBody::Inline(st) => {
                            self.line(i + 2, "<inline>");
                            self.st_body(i + 3, st);
                            self.line(i + 2, "</inline>");
                        }
                    }
                    self.line(i + 1, "</action>");
                }
                self.line(i, "</actionBlock>");
            }
            Node::Transition {
                id,
                t,
                x,
                y,
                input,
                priority,
            } => {
                let prio = priority.map_or(String::new(), |p| format!(" priority=\"{p}\""));
                self.line(
                    i,
                    &format!(
                        "<transition localId=\"{id}\" height=\"{TRANS_H}\" width=\"{TRANS_W}\"{prio}>"
                    ),
                );
                self.line(i + 1, &format!("<position x=\"{x}\" y=\"{y}\"/>"));
                self.input(i + 1, (TRANS_W / 2, 0), (x + TRANS_W / 2, *y), *input);
                self.output(i + 1, "connectionPointOut", (TRANS_W / 2, TRANS_H), false);
                self.line(i + 1, "<condition>");
                self.line(i + 2, &format!("<inline name=\"{}\">", escape(&t.name)));
                self.st_body(i + 3, &t.condition);
                self.line(i + 2, "</inline>");
                self.line(i + 1, "</condition>");
                if let Some(doc) = &t.documentation {
                    self.text_element(i + 1, "documentation", doc);
                }
                self.line(i, "</transition>");
            }
            Node::Jump {
                id,
                target,
                x,
                y,
                input,
            } => {
                self.line(
                    i,
                    &format!(
                        "<jumpStep localId=\"{id}\" height=\"{JUMP_H}\" width=\"{JUMP_W}\" targetName=\"{}\">",
                        escape(target)
                    ),
                );
                self.line(i + 1, &format!("<position x=\"{x}\" y=\"{y}\"/>"));
                self.input(i + 1, (JUMP_W / 2, 0), (x + JUMP_W / 2, *y), *input);
                self.line(i, "</jumpStep>");
            }
            Node::Divergence {
                id,
                kind,
                x,
                y,
                w,
                input,
                outputs,
            } => {
                let (name, h) = match kind {
                    Branching::Selection => ("selectionDivergence", 1),
                    Branching::Simultaneous => ("simultaneousDivergence", 3),
                };
                self.line(
                    i,
                    &format!("<{name} localId=\"{id}\" height=\"{h}\" width=\"{w}\">"),
                );
                self.line(i + 1, &format!("<position x=\"{x}\" y=\"{y}\"/>"));
                self.input(i + 1, (0, 0), (*x, *y), *input);
                for &o in outputs {
                    self.output(i + 1, "connectionPointOut", (o, h), true);
                }
                self.line(i, &format!("</{name}>"));
            }
            Node::Convergence {
                id,
                kind,
                x,
                y,
                w,
                inputs,
            } => {
                let (name, h) = match kind {
                    Branching::Selection => ("selectionConvergence", 1),
                    Branching::Simultaneous => ("simultaneousConvergence", 3),
                };
                self.line(
                    i,
                    &format!("<{name} localId=\"{id}\" height=\"{h}\" width=\"{w}\">"),
                );
                self.line(i + 1, &format!("<position x=\"{x}\" y=\"{y}\"/>"));
                for p in inputs {
                    self.input(i + 1, (p.x - x, 0), (p.x, *y), Some(*p));
                }
                self.output(i + 1, "connectionPointOut", (0, h), false);
                self.line(i, &format!("</{name}>"));
            }
        }
    }
}

/// The document, UTF-8.
pub fn write(project: &Project) -> Vec<u8> {
    let mut w = Writer { out: String::new() };
    w.line(0, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    w.line(
        0,
        &format!("<project xmlns=\"{NAMESPACE}\" xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">"),
    );
    w.line(
        1,
        &format!(
            "<fileHeader companyName=\"higraph\" productName=\"higraph-lsp\" productVersion=\"{}\" creationDateTime=\"{CREATION_DATE_TIME}\" contentDescription=\"HiGraph sequence charts\"/>",
            env!("CARGO_PKG_VERSION")
        ),
    );
    w.line(1, "<contentHeader name=\"charts\">");
    w.line(2, "<coordinateInfo>");
    for lang in ["fbd", "ld", "sfc"] {
        w.line(3, &format!("<{lang}><scaling x=\"1\" y=\"1\"/></{lang}>"));
    }
    w.line(2, "</coordinateInfo>");
    w.line(1, "</contentHeader>");
    w.line(1, "<types>");
    w.line(2, "<dataTypes/>");
    if project.pous.is_empty() {
        w.line(2, "<pous/>");
    } else {
        w.line(2, "<pous>");
        let mut next_id = 0;
        for pou in &project.pous {
            next_id = pou_xml(&mut w, pou, next_id);
        }
        w.line(2, "</pous>");
    }
    w.line(1, "</types>");
    w.line(1, "<instances>");
    if project.globals.is_empty() {
        w.line(2, "<configurations/>");
    } else {
        w.line(2, "<configurations>");
        w.line(3, "<configuration name=\"Charts\">");
        w.variables(4, "globalVars", &project.globals);
        w.line(3, "</configuration>");
        w.line(2, "</configurations>");
    }
    w.line(1, "</instances>");
    w.line(0, "</project>");
    w.out.into_bytes()
}

/// Writes one POU; `localId`s continue after `next_id` (unique in the document). Returns the
/// last one used.
fn pou_xml(w: &mut Writer, pou: &Pou, next_id: u64) -> u64 {
    w.line(
        3,
        &format!(
            "<pou name=\"{}\" pouType=\"functionBlock\">",
            escape(&pou.name)
        ),
    );
    w.line(4, "<interface>");
    w.variables(5, "inputVars", &pou.inputs);
    w.variables(5, "outputVars", &pou.outputs);
    w.variables(5, "inOutVars", &pou.in_outs);
    w.variables(5, "localVars", &pou.locals);
    w.variables(5, "externalVars", &pou.externals);
    w.line(4, "</interface>");
    if !pou.actions.is_empty() {
        w.line(4, "<actions>");
        for a in &pou.actions {
            w.line(5, &format!("<action name=\"{}\">", escape(&a.name)));
            w.line(6, "<body>");
            w.st_body(7, &a.body);
            w.line(6, "</body>");
            if let Some(doc) = &a.documentation {
                w.text_element(6, "documentation", doc);
            }
            w.line(5, "</action>");
        }
        w.line(4, "</actions>");
    }
    let mut layout = Layout {
        nodes: Vec::new(),
        next_id,
    };
    layout.sequence(&pou.body, 0, 0, None, 0, None);
    w.line(4, "<body>");
    w.line(5, "<SFC>");
    for n in &layout.nodes {
        w.node(n);
    }
    w.line(5, "</SFC>");
    w.line(4, "</body>");
    if !pou.documentation.is_empty() {
        w.text_element(4, "documentation", &pou.documentation);
    }
    w.line(3, "</pou>");
    layout.next_id
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(name: &str, initial: bool) -> Element {
        Element::Step(Step {
            name: name.to_owned(),
            initial,
            actions: vec![ActionAssoc {
                qualifier: Qualifier::L,
                duration: Some("T#5S".to_owned()),
                body: ActionBody::Reference("Q".to_owned()),
            }],
            documentation: None,
        })
    }

    fn trans(name: &str, condition: &str) -> Element {
        Element::Transition(Transition {
            name: name.to_owned(),
            condition: condition.to_owned(),
            documentation: None,
        })
    }

    fn values(xml: &str, attr: &str) -> Vec<u64> {
        let needle = format!(" {attr}=\"");
        xml.match_indices(&needle)
            .filter_map(|(i, _)| {
                let rest = &xml[i + needle.len()..];
                rest[..rest.find('"')?].parse().ok()
            })
            .collect()
    }

    /// Two POUs: a selection with a jump branch inside a simultaneous branching.
    fn project() -> Project {
        let body = vec![
            step("S0", true),
            trans("T0", "a AND b"),
            Element::Simultaneous(vec![
                vec![
                    step("P1", false),
                    Element::Selection(vec![
                        vec![trans("T1", "x < 1")],
                        vec![trans("J", "y"), Element::Jump("S0".to_owned())],
                    ]),
                    step("P2", false),
                ],
                vec![step("P3", false)],
            ]),
            trans("T2", "TRUE"),
            step("S9", false),
        ];
        let pou = Pou {
            name: "A".to_owned(),
            body,
            documentation: "x & y".to_owned(),
            ..Pou::default()
        };
        Project {
            pous: vec![
                pou.clone(),
                Pou {
                    name: "B".to_owned(),
                    ..pou
                },
            ],
            globals: vec![Variable {
                name: "G".to_owned(),
                ty: IecType::Bool,
                address: Some("%IX0.0".to_owned()),
                initial: None,
                documentation: None,
            }],
        }
    }

    #[test]
    fn ids_are_unique_in_the_document_and_every_reference_resolves() {
        let xml = String::from_utf8(write(&project())).unwrap_or_default();
        let ids = values(&xml, "localId");
        let unique: std::collections::HashSet<_> = ids.iter().collect();
        assert_eq!(unique.len(), ids.len());
        for r in values(&xml, "refLocalId") {
            assert!(unique.contains(&r), "{r}");
        }
        // A selection with one open branch continues without a convergence.
        assert_eq!(xml.matches("<selectionConvergence").count(), 0);
        assert_eq!(xml.matches("<simultaneousConvergence").count(), 2);
        assert_eq!(values(&xml, "priority"), vec![1, 2, 1, 2]);
        assert!(xml.contains("qualifier=\"L\" duration=\"T#5S\""));
        assert!(xml.contains("a AND b"));
        assert!(xml.contains("x &lt; 1"));
        assert!(xml.contains("<xhtml:p>x &amp; y</xhtml:p>"));
        assert!(xml.contains("<variable name=\"G\" address=\"%IX0.0\">"));
        assert_eq!(write(&project()), write(&project()));
    }

    #[test]
    fn branches_stand_side_by_side_and_below_their_divergence() {
        let xml = String::from_utf8(write(&project())).unwrap_or_default();
        let position = |name: &str| -> (i64, i64) {
            let at = xml.find(&format!("name=\"{name}\"")).unwrap_or(0);
            let rest = &xml[at..];
            let p = rest.find("<position x=\"").unwrap_or(0) + 13;
            let nums: Vec<i64> = rest[p..]
                .split('"')
                .filter_map(|t| t.parse().ok())
                .take(2)
                .collect();
            (nums[0], nums[1])
        };
        let (p1, p3, p2, s9) = (
            position("P1"),
            position("P3"),
            position("P2"),
            position("S9"),
        );
        assert_eq!(p1.1, p3.1, "parallel branches start on one row");
        assert!(p1.0 < p3.0, "left to right");
        assert!(p2.1 > p1.1 && s9.1 > p2.1, "top-down");
    }

    #[test]
    fn named_actions_and_derived_types() {
        let pou = Pou {
            name: "A".to_owned(),
            locals: vec![Variable {
                name: "Timer".to_owned(),
                ty: IecType::Derived("TON".to_owned()),
                address: None,
                initial: None,
                documentation: None,
            }],
            actions: vec![NamedAction {
                name: "Count".to_owned(),
                body: "IF a < b THEN\n  n := n + 1;\nEND_IF;".to_owned(),
                documentation: Some("one more".to_owned()),
            }],
            body: vec![Element::Step(Step {
                name: "S".to_owned(),
                initial: true,
                actions: vec![ActionAssoc {
                    qualifier: Qualifier::Dl,
                    duration: Some("T#1s".to_owned()),
                    body: ActionBody::Reference("Count".to_owned()),
                }],
                documentation: None,
            })],
            ..Pou::default()
        };
        let xml = String::from_utf8(write(&Project {
            pous: vec![pou],
            globals: Vec::new(),
        }))
        .unwrap_or_default();
        assert!(xml.contains("<type><derived name=\"TON\"/></type>"));
        let actions = xml.find("<actions>").unwrap_or(0);
        let body = xml.find("<SFC>").unwrap_or(0);
        assert!(0 < actions && actions < body, "actions before the body");
        assert!(xml.contains("<action name=\"Count\">"));
        assert!(xml.contains("IF a &lt; b THEN\n  n := n + 1;\nEND_IF;"));
        assert!(xml.contains("qualifier=\"DL\" duration=\"T#1s\""));
    }

    #[test]
    fn empty_project() {
        let xml = String::from_utf8(write(&Project::default())).unwrap_or_default();
        assert!(xml.contains("<pous/>"));
        assert!(xml.contains("<configurations/>"));
        assert!(xml.contains(&format!("creationDateTime=\"{CREATION_DATE_TIME}\"")));
    }

    #[test]
    fn escapes_markup_and_drops_control_characters() {
        assert_eq!(
            escape("a<b & \"c\">\u{1}"),
            "a&lt;b &amp; &quot;c&quot;&gt;"
        );
    }
}
