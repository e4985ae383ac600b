//! Context-aware completion (`tooling.md` §4).
//!
//! The user is typing, so the text at the cursor is usually incomplete and the parser has
//! recovered around it. Completion therefore does not ask which node the cursor is in; it
//! looks at two tokens:
//!
//! * the **word** being typed: an identifier, keyword, number or unclosed string that ends at
//!   (or contains) the cursor. It is what a proposal replaces, and what the list is filtered by;
//! * the **previous significant token** before that word. Either it *closes* something (a `;`
//!   ends a statement, a `>` closes a body, a `<` opens one, a block label's `:`) and the
//!   cursor stands at the start of a new element of the enclosing list (an item, a graph
//!   member, a statement, an actual, a step item, ...), or it belongs to an unfinished
//!   construct whose next part is wanted (the operand after an opcode, the graph after
//!   `instance X :`, the message after `Inst.`, a transition endpoint after `trans` or `->`).
//!
//! The data comes from salsa queries that are cached per item ([`graph_members`],
//! [`graph_interface`], the global index), so a completion with a warm database costs a
//! token lookup and the list itself, whatever the size of the workspace.
//!
//! Proposals whose label does not contain the typed word as a case-insensitive subsequence
//! are left out (clients filter again; this only keeps large symbol tables off the wire).
//! `sort_text` orders the list: the most likely kind of proposal first, then in declaration
//! or table order.

use std::collections::HashSet;

use higraph_syntax::{
    SyntaxKind::{self, *},
    SyntaxNode, SyntaxToken, TextRange, TextSize,
    ast::{self, AstNode},
    rowan::NodeOrToken,
};

use super::FilePosition;
use crate::iec::{Direction, FbType};
use crate::lower::RunScope;
use crate::rules::graph::facts::MemberFacts;
use crate::{
    Analysis, Cancellable,
    db::{self, File, ItemKind, ItemLoc, Workspace},
    index::{self, GlobalIndex},
    lang::{self, Mnemonic, Predefined, Section, Type},
    resolve,
    rules::group::interface::{GraphInterface, InterfaceVar, MsgDir, graph_interface},
};
use higraph_runtime::program::OpState;

// ------------------------------------------------------------------------------ public API

/// One completion proposal.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CompletionItem {
    /// What the list shows and what the client filters by.
    pub label: String,
    /// What it is (for the icon).
    pub kind: CompletionKind,
    /// One line beside the label: a variable's section and type, an opcode's meaning, ...
    pub detail: Option<String>,
    /// Longer text (plain text): a predefined variable's meaning, a symbol's comment, ...
    pub documentation: Option<String>,
    /// The text to insert when it is not the label; LSP snippet syntax when `is_snippet`.
    pub insert_text: Option<String>,
    /// What a client filters by when the inserted text is not the label: the text the user
    /// types for this proposal in the replaced range. That is the label: `Ab` for a variable
    /// inserted as `#Ab` (a `#` the user typed is not part of the replaced word), `Not Aus`
    /// for a symbol inserted as `"Not Aus"`, `Start` for a formal inserted as `Start := `. A
    /// client that filters by the inserted text would drop these proposals otherwise.
    pub filter_text: Option<String>,
    /// `insert_text` uses snippet syntax (`${1:name}`, `$0`).
    pub is_snippet: bool,
    /// The text the proposal replaces: the word being typed, or an empty range at the cursor.
    pub replace_range: TextRange,
    /// Orders the list (compared as strings by the client).
    pub sort_text: Option<String>,
}

/// What a completion proposal is (for icons).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CompletionKind {
    /// A keyword of the language (`state`, `prio`, `msg in`, a chart qualifier, ...).
    Keyword,
    /// A multi-line template (`graph`, `state`, `trans`, `group`, `instance`, `chart`, `step`).
    Snippet,
    /// An STL operation.
    Opcode,
    /// A block label (`E:`, `C:`, `?:`, ...).
    Label,
    /// A declared variable.
    Variable,
    /// A message variable (`msg in` / `msg out`).
    Message,
    /// A predefined variable of every graph.
    PredefinedVariable,
    /// A global symbol.
    Symbol,
    /// A graph name.
    Graph,
    /// A state number.
    State,
    /// A chart step.
    Step,
    /// An instance of a group.
    Instance,
    /// A formal parameter of an instantiated graph (`Formal := `).
    Formal,
    /// A data type.
    Type,
    /// A fixed value of a keyword (`simatic`, `cyclic_rlo0`, `T_or_B`, ...).
    Value,
}

impl Analysis {
    /// The completion proposals at a position. Empty when nothing fits (inside a comment, a
    /// name being declared, ...).
    pub fn completions(&self, position: &FilePosition) -> Cancellable<Vec<CompletionItem>> {
        self.with_db(|db, ws| {
            let Some(file) = self.file(&position.path) else {
                return Vec::new();
            };
            complete(db, ws, file, position.offset)
        })
    }
}

// ------------------------------------------------------------------------------ per-graph data

/// A state of a graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct StateInfo {
    pub number: u32,
    /// The display name (`state 1 "Oben"`).
    pub name: Option<String>,
}

/// What completion and inlay hints need of a graph besides its interface: its states and
/// its `activate` list. Position-independent, so it stays equal while bodies are edited.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct GraphMembers {
    /// States in text order (a later duplicate number included).
    pub states: Vec<StateInfo>,
    /// The names of every `activate`, as written.
    pub activated: Vec<String>,
}

impl GraphMembers {
    /// Is the predefined variable active (by default or by `activate`)?
    pub fn is_active(&self, predefined: &Predefined) -> bool {
        predefined.active_by_default
            || self
                .activated
                .iter()
                .any(|a| a.eq_ignore_ascii_case(predefined.name))
    }
}

/// The states and `activate` names of the graph at `item` (empty for other items).
#[salsa::tracked(returns(ref))]
pub(crate) fn graph_members<'db>(db: &'db dyn salsa::Database, item: ItemLoc<'db>) -> GraphMembers {
    let mut members = GraphMembers::default();
    let Some(graph) = db::item_root(db, item).and_then(ast::Graph::cast) else {
        return members;
    };
    // States from the cached member facts, so an edit does not walk the whole graph.
    for &chunk in &db::graph_layout(db, item).chunks {
        for facts in db::chunk_facts(db, chunk).iter() {
            let MemberFacts::State(state) = facts else {
                continue;
            };
            let Some(number) = state.number.as_ref().and_then(|n| n.parse::<u32>().ok()) else {
                continue;
            };
            let name = state.display_name.clone();
            members.states.push(StateInfo { number, name });
        }
    }
    for activate in graph.activates() {
        members
            .activated
            .extend(activate.names().map(|n| n.text()).filter(|n| !n.is_empty()));
    }
    members
}

// ------------------------------------------------------------------------------ tables

/// The rank of a proposal of type `ty` at `base`: as is if the type is preferred (or nothing
/// is), three ranks later if not, and `None` (not proposed) if not and `only` preferred types
/// are wanted.
fn preference_rank(preferred: &[Type], only: bool, ty: Option<Type>, base: u8) -> Option<u8> {
    if preferred.is_empty() || ty.is_some_and(|t| preferred.contains(&t)) {
        Some(base)
    } else if only {
        None
    } else {
        Some(base + 3)
    }
}

/// What an STL operation takes as operand, for ordering operand proposals.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum OperandClass {
    /// No operand, or only a constant: nothing to propose.
    Nothing,
    /// A bit to scan; timers and counters give their status (`U UN O ON X XN`).
    Scan,
    /// A bit to write (`= FP FN`).
    Bit,
    /// `S`: a bit, or a counter (load its preset).
    Set,
    /// `R`: a bit, a timer or a counter.
    Reset,
    /// A timer (`SI SV SE SS SA`).
    Timer,
    /// A timer or counter (`FR LC`).
    TimerOrCounter,
    /// A counter (`ZV ZR`).
    Counter,
    /// A byte, word or double word, or a timer or counter value (`L`).
    Load,
    /// A byte, word or double word to write (`T`).
    Transfer,
    /// A block (`CALL CC`).
    Block,
}

impl OperandClass {
    /// The types that fit best; others are still proposed, after them.
    fn preferred(self) -> &'static [Type] {
        const WORDS: &[Type] = &[
            Type::Byte,
            Type::Word,
            Type::Dword,
            Type::Int,
            Type::Dint,
            Type::Real,
            Type::S5Time,
            Type::Time,
            Type::Date,
            Type::TimeOfDay,
            Type::Char,
        ];
        match self {
            OperandClass::Nothing | OperandClass::Block => &[],
            OperandClass::Scan | OperandClass::Reset => &[Type::Bool, Type::Timer, Type::Counter],
            OperandClass::Bit => &[Type::Bool],
            OperandClass::Set => &[Type::Bool, Type::Counter],
            OperandClass::Timer => &[Type::Timer],
            OperandClass::TimerOrCounter => &[Type::Timer, Type::Counter],
            OperandClass::Counter => &[Type::Counter],
            OperandClass::Load | OperandClass::Transfer => WORDS,
        }
    }
}

/// One STL operation of the HiGraph subset, by its SIMATIC name.
struct OpInfo {
    simatic: &'static str,
    operand: OperandClass,
    description: &'static str,
}

const fn op(simatic: &'static str, operand: OperandClass, description: &'static str) -> OpInfo {
    OpInfo {
        simatic,
        operand,
        description,
    }
}

use OperandClass as Oc;

/// The operations of the HiGraph subset (`facts-stl.md` §2.1) with a one-line description, in
/// the order they are proposed (bit logic first). SIMATIC names; [`lang::op_in_set`] spells
/// them in the file's set.
#[rustfmt::skip]
const OPERATIONS: &[OpInfo] = &[
    op("U", Oc::Scan, "AND: scan a bit and AND it with the RLO"),
    op("UN", Oc::Scan, "AND NOT: scan a bit and AND its negation"),
    op("O", Oc::Scan, "OR: scan a bit and OR it (alone: OR of AND groups)"),
    op("ON", Oc::Scan, "OR NOT: scan a bit and OR its negation"),
    op("X", Oc::Scan, "exclusive OR with a bit"),
    op("XN", Oc::Scan, "exclusive OR NOT with a bit"),
    op("U(", Oc::Nothing, "AND with nesting: open a bracket"),
    op("UN(", Oc::Nothing, "AND NOT with nesting: open a bracket"),
    op("O(", Oc::Nothing, "OR with nesting: open a bracket"),
    op("ON(", Oc::Nothing, "OR NOT with nesting: open a bracket"),
    op("X(", Oc::Nothing, "exclusive OR with nesting: open a bracket"),
    op("XN(", Oc::Nothing, "exclusive OR NOT with nesting: open a bracket"),
    op(")", Oc::Nothing, "close a bracket"),
    op("=", Oc::Bit, "assign the RLO to a bit"),
    op("S", Oc::Set, "set a bit when the RLO is 1 (counter: load the preset)"),
    op("R", Oc::Reset, "reset a bit, timer or counter when the RLO is 1"),
    op("SET", Oc::Nothing, "set the RLO to 1"),
    op("CLR", Oc::Nothing, "clear the RLO to 0"),
    op("NOT", Oc::Nothing, "negate the RLO"),
    op("FP", Oc::Bit, "rising edge of the RLO (operand: the edge memory bit)"),
    op("FN", Oc::Bit, "falling edge of the RLO (operand: the edge memory bit)"),
    op("L", Oc::Load, "load an operand or constant into ACCU 1"),
    op("T", Oc::Transfer, "transfer ACCU 1 to an operand"),
    op("LC", Oc::TimerOrCounter, "load a timer or counter value as BCD into ACCU 1"),
    op("SI", Oc::Timer, "start a timer as pulse"),
    op("SV", Oc::Timer, "start a timer as extended pulse"),
    op("SE", Oc::Timer, "start a timer as on-delay"),
    op("SS", Oc::Timer, "start a timer as retentive on-delay"),
    op("SA", Oc::Timer, "start a timer as off-delay"),
    op("FR", Oc::TimerOrCounter, "enable a timer or counter to restart"),
    op("ZV", Oc::Counter, "count up"),
    op("ZR", Oc::Counter, "count down"),
    op("==I", Oc::Nothing, "compare integers: ACCU 2 = ACCU 1"),
    op("<>I", Oc::Nothing, "compare integers: ACCU 2 <> ACCU 1"),
    op(">I", Oc::Nothing, "compare integers: ACCU 2 > ACCU 1"),
    op("<I", Oc::Nothing, "compare integers: ACCU 2 < ACCU 1"),
    op(">=I", Oc::Nothing, "compare integers: ACCU 2 >= ACCU 1"),
    op("<=I", Oc::Nothing, "compare integers: ACCU 2 <= ACCU 1"),
    op("==D", Oc::Nothing, "compare double integers: ACCU 2 = ACCU 1"),
    op("<>D", Oc::Nothing, "compare double integers: ACCU 2 <> ACCU 1"),
    op(">D", Oc::Nothing, "compare double integers: ACCU 2 > ACCU 1"),
    op("<D", Oc::Nothing, "compare double integers: ACCU 2 < ACCU 1"),
    op(">=D", Oc::Nothing, "compare double integers: ACCU 2 >= ACCU 1"),
    op("<=D", Oc::Nothing, "compare double integers: ACCU 2 <= ACCU 1"),
    op("==R", Oc::Nothing, "compare reals: ACCU 2 = ACCU 1"),
    op("<>R", Oc::Nothing, "compare reals: ACCU 2 <> ACCU 1"),
    op(">R", Oc::Nothing, "compare reals: ACCU 2 > ACCU 1"),
    op("<R", Oc::Nothing, "compare reals: ACCU 2 < ACCU 1"),
    op(">=R", Oc::Nothing, "compare reals: ACCU 2 >= ACCU 1"),
    op("<=R", Oc::Nothing, "compare reals: ACCU 2 <= ACCU 1"),
    op("+I", Oc::Nothing, "add integers: ACCU 2 + ACCU 1"),
    op("-I", Oc::Nothing, "subtract integers: ACCU 2 - ACCU 1"),
    op("*I", Oc::Nothing, "multiply integers: ACCU 2 * ACCU 1"),
    op("/I", Oc::Nothing, "divide integers: ACCU 2 / ACCU 1"),
    op("+D", Oc::Nothing, "add double integers: ACCU 2 + ACCU 1"),
    op("-D", Oc::Nothing, "subtract double integers: ACCU 2 - ACCU 1"),
    op("*D", Oc::Nothing, "multiply double integers: ACCU 2 * ACCU 1"),
    op("/D", Oc::Nothing, "divide double integers: ACCU 2 / ACCU 1"),
    op("MOD", Oc::Nothing, "remainder of a double-integer division"),
    op("+", Oc::Nothing, "add an integer constant to ACCU 1"),
    op("+R", Oc::Nothing, "add reals: ACCU 2 + ACCU 1"),
    op("-R", Oc::Nothing, "subtract reals: ACCU 2 - ACCU 1"),
    op("*R", Oc::Nothing, "multiply reals: ACCU 2 * ACCU 1"),
    op("/R", Oc::Nothing, "divide reals: ACCU 2 / ACCU 1"),
    op("ABS", Oc::Nothing, "absolute value of a real"),
    op("SQR", Oc::Nothing, "square of a real"),
    op("SQRT", Oc::Nothing, "square root of a real"),
    op("EXP", Oc::Nothing, "exponential function of a real"),
    op("LN", Oc::Nothing, "natural logarithm of a real"),
    op("SIN", Oc::Nothing, "sine of a real (radians)"),
    op("COS", Oc::Nothing, "cosine of a real (radians)"),
    op("TAN", Oc::Nothing, "tangent of a real (radians)"),
    op("ASIN", Oc::Nothing, "arc sine of a real"),
    op("ACOS", Oc::Nothing, "arc cosine of a real"),
    op("ATAN", Oc::Nothing, "arc tangent of a real"),
    op("UW", Oc::Nothing, "AND word (16 bit): ACCU 1 with ACCU 2 or a constant"),
    op("OW", Oc::Nothing, "OR word (16 bit): ACCU 1 with ACCU 2 or a constant"),
    op("XOW", Oc::Nothing, "exclusive OR word (16 bit)"),
    op("UD", Oc::Nothing, "AND double word (32 bit): ACCU 1 with ACCU 2 or a constant"),
    op("OD", Oc::Nothing, "OR double word (32 bit): ACCU 1 with ACCU 2 or a constant"),
    op("XOD", Oc::Nothing, "exclusive OR double word (32 bit)"),
    op("SLW", Oc::Nothing, "shift word left"),
    op("SRW", Oc::Nothing, "shift word right"),
    op("SLD", Oc::Nothing, "shift double word left"),
    op("SRD", Oc::Nothing, "shift double word right"),
    op("SSI", Oc::Nothing, "shift integer right with sign"),
    op("SSD", Oc::Nothing, "shift double integer right with sign"),
    op("RLD", Oc::Nothing, "rotate double word left"),
    op("RRD", Oc::Nothing, "rotate double word right"),
    op("RLDA", Oc::Nothing, "rotate ACCU 1 left through CC 1"),
    op("RRDA", Oc::Nothing, "rotate ACCU 1 right through CC 1"),
    op("INC", Oc::Nothing, "increment the low byte of ACCU 1 by a constant"),
    op("DEC", Oc::Nothing, "decrement the low byte of ACCU 1 by a constant"),
    op("TAK", Oc::Nothing, "swap ACCU 1 and ACCU 2"),
    op("PUSH", Oc::Nothing, "push: copy ACCU 1 into ACCU 2"),
    op("POP", Oc::Nothing, "pop: copy ACCU 2 into ACCU 1"),
    op("TAD", Oc::Nothing, "reverse the byte order of ACCU 1 (32 bit)"),
    op("TAW", Oc::Nothing, "reverse the byte order of ACCU 1 low word (16 bit)"),
    op("TAR", Oc::Nothing, "swap address registers 1 and 2"),
    op("TAR1", Oc::Nothing, "transfer address register 1 to ACCU 1"),
    op("TAR2", Oc::Nothing, "transfer address register 2 to ACCU 1"),
    op("BTI", Oc::Nothing, "convert BCD to integer (16 bit)"),
    op("BTD", Oc::Nothing, "convert BCD to double integer"),
    op("ITB", Oc::Nothing, "convert integer to BCD"),
    op("DTB", Oc::Nothing, "convert double integer to BCD"),
    op("ITD", Oc::Nothing, "convert integer to double integer"),
    op("DTR", Oc::Nothing, "convert double integer to real"),
    op("INVI", Oc::Nothing, "ones' complement of an integer"),
    op("INVD", Oc::Nothing, "ones' complement of a double integer"),
    op("NEGI", Oc::Nothing, "negate an integer (two's complement)"),
    op("NEGD", Oc::Nothing, "negate a double integer (two's complement)"),
    op("NEGR", Oc::Nothing, "negate a real"),
    op("RND", Oc::Nothing, "round a real to the nearest double integer"),
    op("RND+", Oc::Nothing, "round a real up to a double integer"),
    op("RND-", Oc::Nothing, "round a real down to a double integer"),
    op("TRUNC", Oc::Nothing, "truncate a real to a double integer"),
    op("CALL", Oc::Block, "call a block"),
    op("CC", Oc::Block, "call a block when the RLO is 1"),
];

fn operation(simatic: &str) -> Option<&'static OpInfo> {
    OPERATIONS
        .iter()
        .find(|op| op.simatic.eq_ignore_ascii_case(simatic))
}

/// Block labels of a state, with what they mean.
const STATE_LABELS: &[(&str, &str)] = &[
    ("E:", "entry actions: once when the state is entered"),
    (
        "C-:",
        "pre-cyclic actions: each cycle before the outgoing transitions are checked",
    ),
    (
        "C:",
        "cyclic actions: each cycle after the outgoing transitions are checked",
    ),
    ("X:", "exit actions: once when the state is left"),
];

/// Block labels of a transition.
const TRANS_LABELS: &[(&str, &str)] = &[
    ("?:", "conditions: the transition fires when they give 1"),
    ("!:", "transition actions: once when the transition fires"),
];

/// Block labels of `permanent`.
const PERMANENT_LABELS: &[(&str, &str)] = &[
    ("C-:", "permanent instructions at the start of every cycle"),
    ("C:", "permanent instructions at the end of every cycle"),
];

/// The options of a group (`language.md` §4).
const GROUP_OPTIONS: &[(&str, &str)] = &[
    (
        "cyclic_rlo0",
        "run the cyclic actions once more with RLO = 0 when leaving a state",
    ),
    (
        "any_once",
        "an any-transition does not fire when already in its target state",
    ),
    (
        "precyclic_on_entry",
        "run C- actions in the entry cycle too",
    ),
    ("restructure", "rebuild the instance DB"),
    (
        "reserve",
        "reserve N words in the DB (only with 'restructure')",
    ),
    ("refdata", "generate reference data"),
];

/// IEC action qualifiers of a step.
const QUALIFIERS: &[(&str, &str)] = &[
    ("N", "non-stored: 1 while the step is active"),
    ("S", "set (stored)"),
    ("R", "reset"),
    ("P", "pulse: 1 for one cycle when the step becomes active"),
    ("L", "time limited: 1 for the given time (needs a time)"),
    ("D", "time delayed: 1 after the given time (needs a time)"),
    ("SD", "stored and time delayed (needs a time)"),
    ("DS", "delayed and stored (needs a time)"),
    ("SL", "stored and time limited (needs a time)"),
];

/// The statements of a test body after `cycle` and `run` (`runtime.md` §5.2).
const TEST_STATEMENTS: &[(&str, &str)] = &[
    ("set", "set a path to a value now"),
    ("step", "run cycles (default 1)"),
    ("wait", "run cycles for a time"),
    ("until", "run cycles until a condition holds, within a time"),
    ("expect", "check a condition now"),
    ("command", "send a command to a chart"),
    ("confirm", "confirm a chart step"),
    ("restart", "restart the machine, cold or warm"),
];

/// The chart commands of `runtime.md` §4.2.
const TEST_COMMANDS: &[(&str, &str)] = &[
    ("start", "Ready, Completed, Aborted → Starting"),
    ("hold", "Starting, Active, Resuming → Holding"),
    ("resume", "Held → Resuming"),
    ("complete", "Active → Completing"),
    ("abort", "→ Aborting"),
    ("stop", "→ Stopping"),
    ("reset", "Completed, Aborted, Stopped → Ready"),
    ("error", "→ Error"),
];

/// Types of `block` interfaces only.
const INTERFACE_TYPES: &[&str] = &["POINTER", "ANY", "BLOCK_FC", "BLOCK_FB", "BLOCK_DB"];

// ------------------------------------------------------------------------------ the cursor

/// The tokens around the cursor.
struct Cursor {
    offset: TextSize,
    /// The word being typed.
    word: Option<SyntaxToken>,
    /// The last significant token before the word (or the cursor).
    prev: Option<SyntaxToken>,
    /// A line break stands between `prev` and the word (or the cursor).
    new_line: bool,
}

impl Cursor {
    /// `None` when the cursor is inside a comment.
    fn new(root: &SyntaxNode, offset: TextSize) -> Option<Cursor> {
        // The token that ends at or contains the cursor (the byte before it).
        let left = offset
            .checked_sub(TextSize::from(1))
            .and_then(|before| token_covering(root, before));
        // At the end of a line comment the user is still writing the comment.
        if left.as_ref().is_some_and(|t| t.kind() == COMMENT) {
            return None;
        }
        let word = left.filter(|t| is_word(t, offset));
        let start = word.as_ref().map_or(offset, |w| w.text_range().start());
        let prev = significant_before(root, start);
        let new_line = match &prev {
            Some(prev) => line_break_between(prev, start),
            None => false,
        };
        Some(Cursor {
            offset,
            word,
            prev,
            new_line,
        })
    }

    /// The range a proposal replaces.
    fn replace_range(&self) -> TextRange {
        self.word
            .as_ref()
            .map_or(TextRange::empty(self.offset), |w| w.text_range())
    }

    /// The part of the word before the cursor.
    fn typed(&self) -> String {
        let Some(word) = &self.word else {
            return String::new();
        };
        let len = usize::from(self.offset - word.text_range().start());
        word.text().get(..len).unwrap_or(word.text()).to_owned()
    }

    /// Is the word being typed a (quoted) string?
    fn quoted(&self) -> bool {
        self.word.as_ref().is_some_and(|w| w.kind() == STRING)
    }

    /// The kind of the previous token and of its parent node.
    fn prev_kinds(&self) -> (Option<SyntaxKind>, Option<SyntaxKind>) {
        let kind = self.prev.as_ref().map(|t| t.kind());
        let parent = self
            .prev
            .as_ref()
            .and_then(|t| t.parent())
            .map(|p| p.kind());
        (kind, parent)
    }
}

/// Can the token be the word being typed at `offset`?
fn is_word(token: &SyntaxToken, offset: TextSize) -> bool {
    match token.kind() {
        IDENT | NUMBER => true,
        STRING => {
            let text = token.text();
            offset < token.text_range().end() || text.len() == 1 || !text.ends_with('"')
        }
        kind => kind.is_keyword(),
    }
}

/// The token that contains the byte at `offset`, found by binary search down the tree
/// (rowan's `token_at_offset` scans the children linearly, which is slow in the body of a
/// graph with thousands of members).
fn token_covering(root: &SyntaxNode, offset: TextSize) -> Option<SyntaxToken> {
    let byte = TextRange::at(offset, TextSize::from(1));
    if !root.text_range().contains_range(byte) {
        return None;
    }
    let mut node = root.clone();
    loop {
        match node.child_or_token_at_range(byte)? {
            NodeOrToken::Node(child) => node = child,
            NodeOrToken::Token(token) => return Some(token),
        }
    }
}

/// The last token before `at` that is not trivia or a lexer error.
fn significant_before(root: &SyntaxNode, at: TextSize) -> Option<SyntaxToken> {
    let mut token = token_covering(root, at.checked_sub(TextSize::from(1))?)?;
    loop {
        let kind = token.kind();
        if !kind.is_trivia() && kind != LEX_ERROR {
            return Some(token);
        }
        token = token.prev_token()?;
    }
}

/// Is there a line break in the trivia after `token`, before `at`?
fn line_break_between(token: &SyntaxToken, at: TextSize) -> bool {
    let mut next = token.next_token();
    while let Some(t) = next {
        if t.text_range().start() >= at {
            break;
        }
        // Only the part of the white space before `at` counts.
        let before = usize::from(at - t.text_range().start());
        let text = t.text().get(..before).unwrap_or(t.text());
        if t.kind() == WHITESPACE && text.contains(['\n', '\r']) {
            return true;
        }
        next = t.next_token();
    }
    false
}

/// The first ancestor of `token` of one of `kinds`.
fn ancestor(token: &SyntaxToken, kinds: &[SyntaxKind]) -> Option<SyntaxNode> {
    token.parent_ancestors().find(|n| kinds.contains(&n.kind()))
}

// ------------------------------------------------------------------------------ contexts

/// Where the cursor stands.
#[derive(Debug, Clone)]
enum Site {
    /// The start of a top-level item; `first` when no item comes before it.
    Item { first: bool },
    /// The start of a graph member (the graph's body).
    GraphMember(SyntaxNode),
    /// The start of a statement of a state, transition or `permanent` (the owner node).
    Statement(SyntaxNode),
    /// An STL operand after an opcode (the OPCODE node and its text), a CALL actual (the
    /// PARAM node) or a time value (the WAIT_ITEM or SUPERVISE_ITEM node).
    Operand {
        node: SyntaxNode,
        opcode: Option<String>,
        time: bool,
    },
    /// After `#` in a graph.
    GraphVariable(SyntaxNode),
    /// A type after `Name :` in a declaration; `interface` in a `block` item.
    Type { interface: bool },
    /// After the type of an `in_out` declaration.
    MsgKind,
    /// After `msg`.
    MsgDirection,
    /// After `mnemonic`.
    MnemonicSet,
    /// The names of an `activate` (the ACTIVATE node).
    Activate(SyntaxNode),
    /// The attributes of a state header (the STATE node).
    StateHeader(SyntaxNode),
    /// A transition endpoint (the TRANS node); `source` before the arrow.
    Endpoint { trans: SyntaxNode, source: bool },
    /// The clauses of a transition header (the TRANS node).
    TransHeader(SyntaxNode),
    /// After a group's name.
    GroupHeader,
    /// The start of a group member.
    GroupMember,
    /// After `option`.
    OptionName,
    /// After `instance X :`.
    InstanceGraph,
    /// The start of an actual parameter (the INSTANCE node).
    Formal(SyntaxNode),
    /// The value of an actual parameter (the ACTUAL node).
    ActualValue(SyntaxNode),
    /// After `Inst.` in an actual (the ACTUAL node, the instance's name).
    Message(SyntaxNode, String),
    /// The start of a chart member.
    ChartMember,
    /// The value of `mode`, `switching` or `run` (the keyword).
    ChartProp(SyntaxKind),
    /// The start of a sequencer member.
    SequencerMember,
    /// The start of an element of a branch.
    BranchElement,
    /// Inside `parallel < >` or `alt < >`.
    Branches,
    /// The start of a step item.
    StepItem,
    /// An operand of a chart expression (the node); `negatable` where `not` may stand.
    ChartOperand { node: SyntaxNode, negatable: bool },
    /// After an operand of a chart condition.
    ChartOperator,
    /// The target of a jump or loop (the JUMP/LOOP node).
    JumpTarget(SyntaxNode),
    /// The start of a section of a `block` interface.
    InterfaceSection,
    /// The start of a statement of a test (the TEST node).
    TestStatement(SyntaxNode),
    /// A group or chart of a test's run list.
    RunEntry,
    /// The chart after `command`.
    CommandChart,
    /// The command after `command Chart`.
    Command,
    /// After `restart`.
    RestartMode,
    /// The start of a test path (the TEST node): instances, groups and charts of the run
    /// list, symbols.
    TestOperand(SyntaxNode),
    /// After `Prefix.` in a test path (the TEST node, the segments before the dot).
    TestMember(SyntaxNode, Vec<String>),
    /// After `Chart.state =` in a test: the operating states.
    OpStates,
    /// After `Name.` in a chart (the CHART node, the name): the members of a function block
    /// instance, or `X`/`T` of a step in an IEC chart.
    ChartDot(SyntaxNode, String),
    /// The formals of a function block call (the FB_CALL node).
    FbFormals(SyntaxNode),
    /// Nothing to propose.
    Nothing,
}

/// Nodes whose children form a list of elements (items, members, statements, ...).
const LISTS: &[SyntaxKind] = &[
    SOURCE_FILE,
    BODY,
    BLOCK,
    VAR_SECTION,
    SYMBOLS,
    BLOCK_INTERFACE,
];

/// Decides where the cursor stands from the tokens around it.
fn classify(root: &SyntaxNode, cursor: &Cursor) -> Site {
    let Some(prev) = &cursor.prev else {
        return Site::Item { first: true };
    };
    let Some(parent) = prev.parent() else {
        return Site::Nothing;
    };
    if let Some(site) = chart_comparison(prev, &parent, cursor) {
        return site;
    }
    if let Some(list) = list_after(prev, &parent) {
        return element_start(root, &list, cursor.offset);
    }
    let (kind, parent_kind) = cursor.prev_kinds();
    let same_line = !cursor.new_line;
    match (kind, parent_kind) {
        (Some(DOT), _) if ancestor(prev, &[TEST]).is_some() => test_member_site(prev),
        (Some(DOT), _) if ancestor(prev, &[CHART]).is_some() => chart_dot_site(prev),
        (Some(L_PAREN | COMMA), Some(FB_CALL)) => Site::FbFormals(parent),
        (Some(THEN_KW | ELSE_KW), _) if ancestor(prev, &[CHART]).is_some() => Site::ChartOperand {
            node: prev
                .parent_ancestors()
                .find(|n| n.kind() == BODY)
                .unwrap_or(parent),
            negatable: false,
        },
        (Some(EQ | L_ANGLE), _) if same_line && after_chart_state(prev) => Site::OpStates,
        (
            Some(
                SET_KW | EXPECT_KW | UNTIL_KW | CONFIRM_KW | AND_KW | OR_KW | XOR_KW | NOT_KW | EQ
                | L_ANGLE | R_ANGLE | L_PAREN | PLUS | MINUS | STAR | SLASH,
            ),
            _,
        ) if same_line && ancestor(prev, &[TEST]).is_some() => match ancestor(prev, &[TEST]) {
            Some(test) => Site::TestOperand(test),
            None => Site::Nothing,
        },
        (_, Some(OPCODE)) => {
            let Some(stmt) = parent.parent() else {
                return Site::Nothing;
            };
            if !same_line {
                return statement_site(&stmt);
            }
            let opcode = ast::Opcode::cast(parent.clone()).map(|o| o.text());
            Site::Operand {
                node: parent,
                opcode,
                time: false,
            }
        }
        (Some(HASH), _) => match ancestor(prev, &[GRAPH]) {
            Some(graph) => Site::GraphVariable(graph),
            None => Site::Nothing,
        },
        (Some(WAIT_KW | SUPERVISE_KW), _) if same_line => Site::Operand {
            node: parent,
            opcode: None,
            time: true,
        },
        (Some(EQ), Some(ASSIGN_OP)) => after_assign(&parent),
        (Some(COLON), Some(VAR_DECL)) => Site::Type {
            interface: ancestor(prev, &[BLOCK_INTERFACE]).is_some(),
        },
        (Some(COLON), Some(INSTANCE)) => Site::InstanceGraph,
        (Some(DOT), _) => message_site(prev),
        (Some(MNEMONIC_KW), _) => Site::MnemonicSet,
        (Some(MSG_KW), _) => Site::MsgDirection,
        (Some(IDENT), _) if prev.text().eq_ignore_ascii_case("msg") && same_line => {
            match ancestor(prev, &[VAR_DECL]) {
                Some(_) => Site::MsgDirection,
                None => Site::Nothing,
            }
        }
        (_, Some(TYPE_REF)) => after_type(&parent),
        (_, Some(ADDRESS)) if parent.parent().is_some_and(|p| p.kind() == SYMBOL) && same_line => {
            Site::Type { interface: false }
        }
        (Some(ACTIVATE_KW | COMMA), Some(ACTIVATE)) => Site::Activate(parent),
        (Some(OPTION_KW), _) => Site::OptionName,
        (Some(MODE_KW | SWITCHING_KW | RUN_KW | PROFILE_KW), Some(CHART_PROP)) => {
            Site::ChartProp(kind.unwrap_or(MODE_KW))
        }
        (Some(TRANS_KW), Some(TRANS)) => Site::Endpoint {
            trans: parent,
            source: true,
        },
        (Some(R_ANGLE), Some(ARROW)) => arrow_site(&parent),
        (Some(RUN_KW | COMMA), Some(TEST_RUN)) if same_line => Site::RunEntry,
        (Some(COMMAND_KW), Some(TEST_COMMAND)) if same_line => Site::CommandChart,
        (Some(IDENT), Some(NAME_REF))
            if same_line
                && parent.parent().is_some_and(|p| {
                    p.kind() == TEST_COMMAND
                        && p.children().find(|n| n.kind() == NAME_REF).as_ref() == Some(&parent)
                }) =>
        {
            Site::Command
        }
        (Some(RESTART_KW), Some(TEST_RESTART)) if same_line => Site::RestartMode,
        _ => header_or_expression(prev, &parent, same_line),
    }
}

/// `x > |` in a chart condition: with nothing after it on the line, the parser reads the `>`
/// as closing the body (`language.md` §1.3), but the user is typing a comparison. Recognised
/// when the `>` follows an operand and the cursor stands on its line.
fn chart_comparison(prev: &SyntaxToken, parent: &SyntaxNode, cursor: &Cursor) -> Option<Site> {
    if prev.kind() != R_ANGLE || parent.kind() != BODY || cursor.new_line {
        return None;
    }
    let owner = parent.parent()?;
    if !matches!(
        owner.kind(),
        START_PART | CHART_TRANS | JUMP | LOOP | STEP_PHASE | PRE_PART | POST_PART
    ) {
        return None;
    }
    let mut before = prev.prev_token()?;
    while before.kind().is_trivia() || before.kind() == LEX_ERROR {
        before = before.prev_token()?;
    }
    let after_operand = matches!(
        before.kind(),
        IDENT | NUMBER | STRING | TYPED_CONST | CHAR | R_PAREN
    ) && !line_break_between(&before, prev.text_range().start());
    after_operand.then(|| Site::ChartOperand {
        node: parent.clone(),
        negatable: true,
    })
}

/// If `prev` closes an element or opens a list, the list the cursor now stands in.
fn list_after(prev: &SyntaxToken, parent: &SyntaxNode) -> Option<SyntaxNode> {
    let closing_parents = [BODY, VAR_SECTION, SYMBOLS, BLOCK_INTERFACE, ERROR];
    let node = match prev.kind() {
        // `<` opens a list.
        L_ANGLE if LISTS.contains(&parent.kind()) => return Some(parent.clone()),
        // `;` ends an element; `>` closes the element that owns the body.
        SEMI => parent.clone(),
        R_ANGLE if closing_parents.contains(&parent.kind()) => {
            if parent.kind() == BODY {
                parent.parent()?
            } else {
                parent.clone()
            }
        }
        // A block label starts a new run of statements.
        COLON if parent.kind() == LABEL => parent.clone(),
        _ => return None,
    };
    node.ancestors().skip(1).find(|n| LISTS.contains(&n.kind()))
}

/// The site at the start of an element of `list`.
fn element_start(root: &SyntaxNode, list: &SyntaxNode, offset: TextSize) -> Site {
    match list.kind() {
        SOURCE_FILE => Site::Item {
            first: !items_before(root, offset),
        },
        BLOCK => match list.parent() {
            Some(body) => element_start(root, &body, offset),
            None => Site::Nothing,
        },
        BLOCK_INTERFACE => Site::InterfaceSection,
        BODY => {
            let Some(owner) = list.parent() else {
                return Site::Nothing;
            };
            match owner.kind() {
                GRAPH => Site::GraphMember(owner),
                STATE | TRANS | PERMANENT => Site::Statement(owner),
                GROUP => Site::GroupMember,
                INSTANCE => Site::Formal(owner),
                CHART => Site::ChartMember,
                SEQUENCER => Site::SequencerMember,
                BRANCH => Site::BranchElement,
                PARALLEL | ALT => Site::Branches,
                STEP => Site::StepItem,
                STEP_PHASE | PRE_PART | POST_PART | CHART_ACTION => Site::ChartOperand {
                    node: list.clone(),
                    negatable: false,
                },
                START_PART | CHART_TRANS | JUMP | LOOP => Site::ChartOperand {
                    node: list.clone(),
                    negatable: true,
                },
                TEST => Site::TestStatement(owner),
                _ => Site::Nothing,
            }
        }
        _ => Site::Nothing,
    }
}

/// Does an item start before `offset`?
fn items_before(root: &SyntaxNode, offset: TextSize) -> bool {
    item_nodes(root).any(|n| n.text_range().start() < offset)
}

/// The top-level item nodes of a file (as [`db::item_nodes`] numbers them).
fn item_nodes(root: &SyntaxNode) -> impl Iterator<Item = SyntaxNode> + use<> {
    root.children()
        .filter(|n| ast::Item::cast(n.clone()).is_some())
}

/// The statement site of the body that holds `node`.
fn statement_site(node: &SyntaxNode) -> Site {
    node.ancestors()
        .find(|n| matches!(n.kind(), STATE | TRANS | PERMANENT))
        .map_or(Site::Nothing, Site::Statement)
}

/// After `:=`.
fn after_assign(assign: &SyntaxNode) -> Site {
    let Some(owner) = assign.parent() else {
        return Site::Nothing;
    };
    match owner.kind() {
        ACTUAL => Site::ActualValue(owner),
        PARAM => Site::Operand {
            node: owner,
            opcode: None,
            time: false,
        },
        ASSIGNMENT | FB_ARG => Site::ChartOperand {
            node: owner,
            negatable: true,
        },
        _ => Site::Nothing,
    }
}

/// After the type of a declaration: `msg in` / `msg out` in an `in_out` section.
fn after_type(type_ref: &SyntaxNode) -> Site {
    let section = type_ref
        .ancestors()
        .find(|n| n.kind() == VAR_SECTION)
        .and_then(ast::VarSection::cast)
        .and_then(|s| s.keyword());
    match section {
        Some(keyword) if keyword.kind() == IN_OUT_KW => Site::MsgKind,
        _ => Site::Nothing,
    }
}

/// After a `.` in a test: the members of the path written before it (names and dots with
/// nothing between them, a quoted symbol first).
fn test_member_site(dot: &SyntaxToken) -> Site {
    let Some(test) = ancestor(dot, &[TEST]) else {
        return Site::Nothing;
    };
    let mut names = Vec::new();
    let mut token = dot.prev_token();
    // At most a few dozen segments: a path is short; the bound keeps the walk linear.
    for _ in 0..64 {
        let Some(name) = token.filter(|t| {
            t.kind() == STRING
                || (!t.kind().is_trivia()
                    && !t.text().is_empty()
                    && t.text()
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || c == '_'))
        }) else {
            break;
        };
        names.push(ast::unquote(name.text()).to_owned());
        match name.prev_token() {
            Some(d) if d.kind() == DOT => token = d.prev_token(),
            _ => break,
        }
    }
    if names.is_empty() {
        return Site::Nothing;
    }
    names.reverse();
    Site::TestMember(test, names)
}

/// Is `op` (`=` or `<>`) the operator after `Chart.state` in a test?
fn after_chart_state(op: &SyntaxToken) -> bool {
    if ancestor(op, &[TEST]).is_none() {
        return false;
    }
    let mut before = op.prev_token();
    if op.kind() == R_ANGLE {
        before = before.and_then(|t| t.prev_token());
    }
    while let Some(t) = before.as_ref().filter(|t| t.kind().is_trivia()) {
        before = t.prev_token();
    }
    let Some(state) = before else {
        return false;
    };
    state.text().eq_ignore_ascii_case("state")
        && state
            .prev_token()
            .is_some_and(|d| d.kind() == DOT && d.prev_token().is_some_and(|c| c.kind() == IDENT))
}

/// After `Name.` in a chart: the name must stand right before the dot.
fn chart_dot_site(dot: &SyntaxToken) -> Site {
    let Some(chart) = ancestor(dot, &[CHART]) else {
        return Site::Nothing;
    };
    match dot.prev_token() {
        Some(name) if name.kind() == IDENT => Site::ChartDot(chart, name.text().to_owned()),
        _ => Site::Nothing,
    }
}

/// After a `.`: the incoming messages of an instance, in an actual parameter.
fn message_site(dot: &SyntaxToken) -> Site {
    let Some(actual) = ancestor(dot, &[ACTUAL]) else {
        return Site::Nothing;
    };
    match dot.prev_token() {
        Some(name) if name.kind() == IDENT => Site::Message(actual, name.text().to_owned()),
        _ => Site::Nothing,
    }
}

/// After `->`: a transition's target or a jump's target step.
fn arrow_site(arrow: &SyntaxNode) -> Site {
    let Some(owner) = arrow.parent() else {
        return Site::Nothing;
    };
    match owner.kind() {
        TRANS => Site::Endpoint {
            trans: owner,
            source: false,
        },
        JUMP | LOOP => Site::JumpTarget(owner),
        _ => Site::Nothing,
    }
}

/// Headers (state, transition, group) and chart expressions.
fn header_or_expression(prev: &SyntaxToken, parent: &SyntaxNode, same_line: bool) -> Site {
    let header = prev.parent_ancestors().find(|n| {
        matches!(
            n.kind(),
            STATE | TRANS | GROUP | CONDITION | ASSIGNMENT | QUALIFIER_ACTION | STEP_TIME | BODY
        )
    });
    let Some(header) = header else {
        return Site::Nothing;
    };
    match header.kind() {
        STATE if prev.kind() == NUMBER || parent.kind() != STATE => Site::StateHeader(header),
        // After the target endpoint, a priority number, an attribute or the display name.
        TRANS if prev.kind() != PRIO_KW && has_arrow_before(&header, prev) => {
            Site::TransHeader(header)
        }
        GROUP if parent.kind() == NAME => Site::GroupHeader,
        QUALIFIER_ACTION | STEP_TIME
            if same_line
                && (matches!(prev.kind(), MIN_KW | MAX_KW | COMMA)
                    || parent.kind() == QUALIFIER) =>
        {
            Site::ChartOperand {
                node: header,
                negatable: false,
            }
        }
        CONDITION | ASSIGNMENT => chart_expression_site(prev, &header, same_line),
        _ => Site::Nothing,
    }
}

/// Does the transition header have its `->` before `token`?
fn has_arrow_before(trans: &SyntaxNode, token: &SyntaxToken) -> bool {
    trans
        .children()
        .any(|n| n.kind() == ARROW && n.text_range().end() < token.text_range().end())
}

/// Inside a chart condition or assignment, after `prev`.
fn chart_expression_site(prev: &SyntaxToken, statement: &SyntaxNode, same_line: bool) -> Site {
    let operator = matches!(
        prev.kind(),
        AND_KW | OR_KW | XOR_KW | NOT_KW | EQ | L_ANGLE | R_ANGLE | L_PAREN
    );
    if operator {
        return Site::ChartOperand {
            node: statement.clone(),
            negatable: true,
        };
    }
    let ends_operand = matches!(
        prev.kind(),
        IDENT | NUMBER | STRING | TYPED_CONST | CHAR | R_PAREN
    );
    // In an assignment, only the value after `:=` is an expression.
    let in_value = statement.kind() == CONDITION
        || statement
            .children()
            .any(|n| n.kind() == ASSIGN_OP && n.text_range().end() <= prev.text_range().start());
    if ends_operand && same_line && in_value {
        Site::ChartOperator
    } else {
        Site::Nothing
    }
}

/// The operand class of an opcode as written in a file of mnemonic set `set`. An operation of
/// the other set is read in that set; an unknown one is treated like bit logic.
fn opcode_class(opcode: &str, set: Mnemonic) -> OperandClass {
    [set, set.other()]
        .into_iter()
        .find_map(|set| lang::to_simatic_op(opcode, set))
        .and_then(|simatic| operation(&simatic))
        .map_or(OperandClass::Scan, |op| op.operand)
}

// ------------------------------------------------------------------------------ proposals

/// Collects proposals, filtered by the typed word.
struct Proposals {
    range: TextRange,
    typed: String,
    items: Vec<CompletionItem>,
}

impl Proposals {
    /// Adds a proposal with rank `rank` (lower ranks sort first; within a rank, the order of
    /// addition).
    fn add(
        &mut self,
        rank: u8,
        label: impl Into<String>,
        kind: CompletionKind,
    ) -> Option<&mut CompletionItem> {
        let label = label.into();
        if !matches_typed(&label, &self.typed) {
            return None;
        }
        let sort_text = format!("{rank:02}{:05}", self.items.len());
        self.items.push(CompletionItem {
            label,
            kind,
            detail: None,
            documentation: None,
            insert_text: None,
            filter_text: None,
            is_snippet: false,
            replace_range: self.range,
            sort_text: Some(sort_text),
        });
        self.items.last_mut()
    }

    /// Adds a keyword with a detail.
    fn keyword(&mut self, rank: u8, word: &str, detail: &str) {
        if let Some(item) = self.add(rank, word, CompletionKind::Keyword) {
            item.detail = Some(detail.to_owned());
        }
    }

    /// Adds a snippet.
    fn snippet(&mut self, rank: u8, label: &str, detail: &str, body: String) {
        if let Some(item) = self.add(rank, label, CompletionKind::Snippet) {
            item.detail = Some(detail.to_owned());
            item.insert_text = Some(body);
            item.is_snippet = true;
        }
    }

    fn finish(mut self) -> Vec<CompletionItem> {
        for item in &mut self.items {
            if item
                .insert_text
                .as_ref()
                .is_some_and(|insert| *insert != item.label)
            {
                item.filter_text = Some(item.label.clone());
            }
        }
        self.items.sort_by(|a, b| a.sort_text.cmp(&b.sort_text));
        self.items
    }
}

/// Does `label` contain `typed` as a case-insensitive subsequence?
fn matches_typed(label: &str, typed: &str) -> bool {
    let mut label = label.chars().map(|c| c.to_ascii_lowercase());
    typed
        .chars()
        .map(|c| c.to_ascii_lowercase())
        .all(|t| label.any(|l| l == t))
}

/// Everything a completion needs.
struct Completer<'a> {
    db: &'a dyn salsa::Database,
    ws: Workspace,
    file: File,
    root: SyntaxNode,
    mnemonic: Mnemonic,
    index: &'a GlobalIndex,
    cursor: Cursor,
    out: Proposals,
}

fn complete(
    db: &dyn salsa::Database,
    ws: Workspace,
    file: File,
    offset: TextSize,
) -> Vec<CompletionItem> {
    let root = db::parse(db, file).syntax_node();
    if offset > root.text_range().end() {
        return Vec::new();
    }
    let Some(cursor) = Cursor::new(&root, offset) else {
        return Vec::new();
    };
    let site = classify(&root, &cursor);
    let out = Proposals {
        range: cursor.replace_range(),
        typed: cursor.typed(),
        items: Vec::new(),
    };
    let mut completer = Completer {
        db,
        ws,
        file,
        root,
        mnemonic: db::file_mnemonic(db, ws, file),
        index: db::global_index(db, ws),
        cursor,
        out,
    };
    let operand_site = matches!(
        site,
        Site::Operand { .. } | Site::ActualValue(_) | Site::ChartOperand { .. }
    );
    // A string is only ever typed as a quoted symbol in operand position.
    if completer.cursor.quoted() && !operand_site {
        return Vec::new();
    }
    completer.fill(site);
    completer.out.finish()
}

impl<'a> Completer<'a> {
    fn fill(&mut self, site: Site) {
        match site {
            Site::Item { first } => self.items(first),
            Site::GraphMember(graph) => self.graph_members(&graph),
            Site::Statement(owner) => self.statement_start(&owner),
            Site::Operand { node, opcode, time } => self.operand(&node, opcode.as_deref(), time),
            Site::GraphVariable(graph) => {
                if let Some(scope) = self.graph_scope(&graph) {
                    self.variables(&scope, &[], false, false);
                }
            }
            Site::Type { interface } => self.types(interface),
            Site::MsgKind => {
                self.out.keyword(0, "msg in", "incoming message");
                self.out.keyword(0, "msg out", "outgoing message");
            }
            Site::MsgDirection => {
                self.out.keyword(0, "in", "incoming message");
                self.out.keyword(0, "out", "outgoing message");
            }
            Site::MnemonicSet => {
                self.value(0, "simatic", "German mnemonics: U E 1.0");
                self.value(0, "international", "English mnemonics: A I 1.0");
            }
            Site::Activate(activate) => self.activate(&activate),
            Site::StateHeader(state) => self.state_header(&state),
            Site::Endpoint { trans, source } => self.endpoints(&trans, source),
            Site::TransHeader(trans) => self.trans_header(&trans),
            Site::GroupHeader => {
                self.out.keyword(0, "fc", "the FC the group compiles to");
                self.out.keyword(0, "db", "the DB the group compiles to");
            }
            Site::GroupMember => self.group_members(),
            Site::OptionName => {
                for (name, detail) in GROUP_OPTIONS {
                    self.value(0, name, detail);
                }
            }
            Site::InstanceGraph => self.graph_names(),
            Site::Formal(instance) => self.formals(&instance),
            Site::ActualValue(actual) => self.actual_value(&actual),
            Site::Message(actual, instance) => self.messages(&actual, &instance),
            Site::ChartMember => self.chart_members(),
            Site::ChartProp(keyword) => self.chart_prop(keyword),
            Site::SequencerMember => {
                self.seq_elements();
                self.out
                    .keyword(2, "start", "start condition of the sequencer");
                self.out
                    .keyword(2, "pre", "statements before the steps, each cycle");
                self.out
                    .keyword(2, "post", "statements after the steps, each cycle");
            }
            Site::BranchElement => self.seq_elements(),
            Site::Branches => {
                self.out
                    .keyword(0, "branch", "a branch of the parallel or alternative")
            }
            Site::StepItem => self.step_items(),
            Site::ChartOperand { node, negatable } => self.chart_operand(&node, negatable),
            Site::ChartOperator => {
                self.out.keyword(0, "and", "logical AND");
                self.out.keyword(0, "or", "logical OR");
                self.out.keyword(0, "xor", "exclusive OR");
            }
            Site::JumpTarget(jump) => self.step_names(&jump),
            Site::InterfaceSection => self.section_keywords(0),
            Site::TestStatement(test) => self.test_statements(&test),
            Site::RunEntry => self.runnable(false),
            Site::CommandChart => self.runnable(true),
            Site::Command => {
                for (command, detail) in TEST_COMMANDS {
                    self.value(0, command, detail);
                }
            }
            Site::RestartMode => {
                self.value(
                    0,
                    "cold",
                    "unbuffered: memory back to its initial values, charts Ready",
                );
                self.value(0, "warm", "buffered: memory kept, INIT_SD = 1 next cycle");
            }
            Site::TestOperand(test) => self.test_operand(&test),
            Site::TestMember(test, names) => self.test_members(&test, &names),
            Site::OpStates => {
                for state in OpState::ALL {
                    self.value(0, state.name(), "operating state of a chart");
                }
            }
            Site::ChartDot(chart, name) => self.chart_dot(&chart, &name),
            Site::FbFormals(call) => self.fb_formals(&call),
            Site::Nothing => {}
        }
    }

    // -------------------------------------------------------------------- IEC charts

    /// `Inst.`: the members of the instance's function block, inputs first; `Step.` in an IEC
    /// chart: `X` and `T`.
    fn chart_dot(&mut self, chart: &SyntaxNode, name: &str) {
        let Some(chart) = ast::Chart::cast(chart.clone()) else {
            return;
        };
        if let Some(fb) = fb_instance(&chart, name) {
            for member in fb.members() {
                let direction = match member.direction {
                    Direction::Input => "input",
                    Direction::Output => "output",
                };
                if let Some(item) = self.out.add(0, member.name, CompletionKind::Formal) {
                    item.detail = Some(format!("{direction} {}", member.ty));
                    item.documentation = Some(member.doc.to_owned());
                }
            }
            return;
        }
        if chart.profile() != ast::Profile::Iec {
            return;
        }
        let is_step = chart
            .syntax()
            .descendants()
            .filter_map(ast::Step::cast)
            .any(|s| {
                s.name()
                    .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
            });
        if is_step {
            self.value(0, "X", "BOOL: the step is active");
            self.value(0, "T", "TIME: how long the step has been active");
        }
    }

    /// Inside `Inst( ... )`: the formals not given yet, inputs as `IN := `, outputs as
    /// `Q => `.
    fn fb_formals(&mut self, call: &SyntaxNode) {
        let Some(call) = ast::FbCall::cast(call.clone()) else {
            return;
        };
        let Some(chart) = call.syntax().ancestors().find_map(ast::Chart::cast) else {
            return;
        };
        let Some(fb) = call.callee().and_then(|c| fb_instance(&chart, &c.text())) else {
            return;
        };
        let given: Vec<String> = call
            .args()
            .filter_map(|a| a.formal())
            .map(|f| f.text())
            .collect();
        for member in fb.members() {
            if given.iter().any(|g| g.eq_ignore_ascii_case(member.name)) {
                continue;
            }
            let (rank, arrow, direction) = match member.direction {
                Direction::Input => (0, ":=", "input"),
                Direction::Output => (1, "=>", "output"),
            };
            if let Some(item) = self.out.add(rank, member.name, CompletionKind::Formal) {
                item.detail = Some(format!("{direction} {}", member.ty));
                item.documentation = Some(member.doc.to_owned());
                item.insert_text = Some(format!("{} {arrow} ", member.name));
            }
        }
    }

    /// At the start of a statement of an IEC chart: `IF`, `CASE` and a call of each function
    /// block instance.
    fn iec_statements(&mut self, chart: &ast::Chart) {
        self.out.snippet(
            1,
            "IF",
            "IF condition THEN ... END_IF;",
            "IF ${1:condition} THEN\n  $0\nEND_IF;".to_owned(),
        );
        self.out.snippet(
            1,
            "CASE",
            "CASE selector OF ... END_CASE;",
            "CASE ${1:selector} OF\n  ${2:1}: $0\nEND_CASE;".to_owned(),
        );
        for (_, decl) in crate::rules::decls::declarations(chart.var_sections()) {
            let (Some(name), Some(ty)) = (decl.name(), decl.ty().and_then(|t| t.name())) else {
                continue;
            };
            let Some(fb) = FbType::from_name(ty.text()) else {
                continue;
            };
            let name = name.text();
            let label = format!("{name}()");
            self.out.snippet(
                1,
                &label,
                &format!("call {}", fb.signature()),
                format!("{name}($0);"),
            );
        }
    }

    // -------------------------------------------------------------------- test paths

    /// The run scope of the test at `test`.
    fn run_scope(&self, test: &SyntaxNode) -> Option<RunScope> {
        let test = ast::Test::cast(test.clone())?;
        let run = crate::lower::run_list(self.db, self.ws, &test);
        Some(RunScope::build(self.db, self.ws, &run))
    }

    /// The first names of a test path: the instances, groups and charts the test runs, then
    /// the symbols.
    fn test_operand(&mut self, test: &SyntaxNode) {
        let Some(scope) = self.run_scope(test) else {
            return;
        };
        let mut seen = HashSet::new();
        for group in &scope.groups {
            for instance in &group.instances {
                if seen.insert(index::key(&instance.name))
                    && let Some(item) =
                        self.out
                            .add(0, instance.name.clone(), CompletionKind::Instance)
                {
                    item.detail = Some(format!("instance of group {}", group.name));
                }
            }
        }
        for chart in &scope.charts {
            if let Some(item) = self.out.add(0, chart.name.clone(), CompletionKind::Graph) {
                item.detail = Some("chart".to_owned());
            }
        }
        for group in &scope.groups {
            if let Some(item) = self
                .out
                .add(1, group.name.clone(), CompletionKind::Instance)
            {
                item.detail = Some("group".to_owned());
            }
        }
        self.symbols(&[], false, &GraphInterface::default());
    }

    /// What may follow `names.` in a test path (`runtime.md` §5.3).
    fn test_members(&mut self, test: &SyntaxNode, names: &[String]) {
        let Some(scope) = self.run_scope(test) else {
            return;
        };
        let same = |a: &str, b: &str| a.eq_ignore_ascii_case(b);
        let first = names[0].as_str();
        if let Some(chart) = scope.charts.iter().find(|c| same(&c.name, first)) {
            self.chart_path_members(chart, &names[1..]);
            return;
        }
        let group = scope.groups.iter().find(|g| same(&g.name, first));
        let instance = match (group, names.len()) {
            (Some(group), 1) => {
                for instance in &group.instances {
                    if let Some(item) =
                        self.out
                            .add(0, instance.name.clone(), CompletionKind::Instance)
                    {
                        item.detail = Some(format!("instance of group {}", group.name));
                    }
                }
                return;
            }
            (Some(group), 2) => group.instances.iter().find(|i| same(&i.name, &names[1])),
            (None, 1) => scope
                .groups
                .iter()
                .flat_map(|g| g.instances.iter())
                .find(|i| same(&i.name, first)),
            _ => None,
        };
        if let Some(instance) = instance {
            self.instance_members(instance.graph);
            return;
        }
        if names.len() == 1 {
            self.block_members(first);
        }
    }

    /// `Inst.`: the graph's variables, its predefined variables, `state` and `previous`.
    fn instance_members(&mut self, graph: (File, u32)) {
        let loc = ItemLoc::new(self.db, graph.0, graph.1);
        if let Some(scope) = db::graph_scope(self.db, loc).as_ref() {
            for var in scope.vars.iter() {
                if let Some(item) = self.out.add(0, var.name.clone(), CompletionKind::Variable) {
                    let ty = var.ty.map_or_else(|| "?".to_owned(), |t| t.to_string());
                    item.detail = Some(format!("{} {ty}", var.section.as_str()));
                }
            }
        }
        self.out
            .keyword(1, "state", "WORD: the instance's current state");
        self.out.keyword(
            1,
            "previous",
            "WORD: the state before the last state change",
        );
        for p in lang::PREDEFINED.iter().filter(|p| !p.internal) {
            if let Some(item) = self.out.add(2, p.name, CompletionKind::PredefinedVariable) {
                item.detail = Some(format!("predefined {}", p.ty));
                item.documentation = Some(p.meaning.to_owned());
            }
        }
    }

    /// `Chart.`, `Chart.Seq.`, `Chart.[Seq.]Step.`.
    fn chart_path_members(&mut self, chart: &crate::lower::ScopeChart, rest: &[String]) {
        let same = |a: &str, b: &str| a.eq_ignore_ascii_case(b);
        let step_members = |out: &mut Proposals| {
            out.keyword(0, "X", "BOOL: the step is active");
            out.keyword(0, "T", "TIME: how long the step has been active");
            out.keyword(0, "error", "BOOL: the step exceeded its supervision time");
        };
        match rest {
            [] => {
                for (name, _, ty) in &chart.vars {
                    if let Some(item) = self.out.add(0, name.clone(), CompletionKind::Variable) {
                        item.detail = Some(ty.map_or_else(|| "?".to_owned(), |t| t.to_string()));
                    }
                }
                for sequencer in &chart.sequencers {
                    if let Some(item) =
                        self.out
                            .add(1, sequencer.name.clone(), CompletionKind::Step)
                    {
                        item.detail = Some("sequencer".to_owned());
                    }
                }
                for sequencer in &chart.sequencers {
                    for (step, _) in &sequencer.steps {
                        if let Some(item) = self.out.add(1, step.clone(), CompletionKind::Step) {
                            item.detail = Some(format!("step of sequencer {}", sequencer.name));
                        }
                    }
                }
                self.out.keyword(2, "state", "the chart's operating state");
            }
            [name] => {
                if let Some(sequencer) = chart.sequencers.iter().find(|s| same(&s.name, name)) {
                    for (step, _) in &sequencer.steps {
                        if let Some(item) = self.out.add(0, step.clone(), CompletionKind::Step) {
                            item.detail = Some(format!("step of sequencer {}", sequencer.name));
                        }
                    }
                } else if chart
                    .sequencers
                    .iter()
                    .any(|s| s.steps.iter().any(|(n, _)| same(n, name)))
                {
                    step_members(&mut self.out);
                }
            }
            [sequencer, step] => {
                let found = chart.sequencers.iter().any(|s| {
                    same(&s.name, sequencer) && s.steps.iter().any(|(n, _)| same(n, step))
                });
                if found {
                    step_members(&mut self.out);
                }
            }
            _ => {}
        }
    }

    /// `Block.`: `calls` and the outputs of its declared interface.
    fn block_members(&mut self, written: &str) {
        let index = self.index;
        let Some((key, name)) = crate::lower::block_key(index, written, self.mnemonic) else {
            return;
        };
        self.out
            .keyword(1, "calls", &format!("DINT: how often {name} was called"));
        for entry in &index.block_interfaces {
            let reference = ast::unquote(entry.reference.trim());
            let same = crate::lower::block_key(index, reference, self.mnemonic)
                .is_some_and(|(k, _)| k == key)
                || reference.eq_ignore_ascii_case(written);
            if !same {
                continue;
            }
            let loc = ItemLoc::new(self.db, entry.file, entry.item);
            let Some(ast::Item::BlockInterface(interface)) =
                db::item_root(self.db, loc).and_then(ast::Item::cast)
            else {
                return;
            };
            for (section, decl) in crate::rules::decls::declarations(interface.var_sections()) {
                if !matches!(section, Section::Out | Section::InOut) {
                    continue;
                }
                let Some(formal) = decl.name().map(|n| n.text()) else {
                    continue;
                };
                if let Some(item) = self.out.add(0, formal, CompletionKind::Formal) {
                    item.detail = Some(format!("{} of {name}: its stub value", section.as_str()));
                }
            }
            return;
        }
    }

    /// Adds a fixed value.
    fn value(&mut self, rank: u8, label: &str, detail: &str) {
        if let Some(item) = self.out.add(rank, label, CompletionKind::Value) {
            item.detail = Some(detail.to_owned());
        }
    }

    // -------------------------------------------------------------------- items and members

    fn items(&mut self, first: bool) {
        let set = self.mnemonic;
        let and = lang::op_in_set("U", set);
        self.out.snippet(
            0,
            "graph",
            "graph Name < ... > with a startup transition",
            format!(
                "graph ${{1:Name}} <\n  state 0 \"${{2:Init}}\" < >\n  trans any->0 prio 1 \"startup\" < {and} INIT_SD; >\n  $0\n>"
            ),
        );
        self.out.snippet(
            0,
            "group",
            "group Name < instance ... >",
            "group ${1:Name} <\n  instance ${2:Inst} : ${3:Graph} <\n    $0\n  >\n>".to_owned(),
        );
        self.out.snippet(
            0,
            "chart",
            "chart Name < sequencer ... >",
            "chart ${1:Name} <\n  sequencer ${2:S1} <\n    start < ${3:TRUE}; >\n    step ${4:START} < $0 >\n  >\n>"
                .to_owned(),
        );
        self.out.snippet(
            0,
            "test",
            "test Name < run ...; expect ...; >",
            "test ${1:Name} <\n  run ${2:Group};\n  $0\n>".to_owned(),
        );
        self.out.keyword(1, "symbols", "a table of global symbols");
        self.out
            .keyword(1, "block", "the interface of an external block");
        if first {
            self.out
                .keyword(1, "mnemonic", "the STL mnemonics of this file");
        }
    }

    fn section_keywords(&mut self, rank: u8) {
        self.out.keyword(rank, "in", "input parameters");
        self.out.keyword(rank, "out", "output parameters");
        self.out
            .keyword(rank, "in_out", "in/out parameters and messages");
        self.out.keyword(rank, "stat", "static variables");
    }

    fn graph_members(&mut self, graph: &SyntaxNode) {
        let next = self
            .item_loc(graph)
            .map(|item| graph_members(self.db, item))
            .and_then(|m| m.states.iter().map(|s| s.number).max())
            .map_or(0, |n| n.saturating_add(1));
        self.out.snippet(
            0,
            "state",
            "state N \"name\" < ... >",
            format!("state ${{1:{next}}} \"${{2:Name}}\" <\n  $0\n>"),
        );
        self.out.snippet(
            0,
            "trans",
            "trans A->B prio N < ... >",
            "trans ${1:0}->${2:1} prio ${3:1} <\n  $0\n>".to_owned(),
        );
        self.section_keywords(1);
        self.out
            .keyword(1, "activate", "activate predefined variables");
        self.out
            .keyword(1, "permanent", "instructions that run every cycle");
    }

    fn statement_start(&mut self, owner: &SyntaxNode) {
        let (labels, labels_first) = match owner.kind() {
            STATE => (STATE_LABELS, true),
            PERMANENT => (PERMANENT_LABELS, true),
            _ => (TRANS_LABELS, false),
        };
        let (label_rank, op_rank) = if labels_first { (0, 1) } else { (1, 0) };
        for (label, detail) in labels {
            if let Some(item) = self.out.add(label_rank, *label, CompletionKind::Label) {
                item.detail = Some((*detail).to_owned());
                item.insert_text = Some(format!("{label} "));
            }
        }
        if owner.kind() == STATE {
            self.out
                .keyword(2, "wait", "minimum dwell time for 'waits' transitions");
            self.out
                .keyword(2, "supervise", "supervision time of the state");
        }
        for op in OPERATIONS {
            let label = lang::op_in_set(op.simatic, self.mnemonic);
            if let Some(item) = self.out.add(op_rank, label, CompletionKind::Opcode) {
                item.detail = Some(op.description.to_owned());
            }
        }
    }

    fn state_header(&mut self, state: &SyntaxNode) {
        let present = attribute_words(state);
        for (word, detail) in [
            ("fault", "fault state (diagnostic attribute F)"),
            ("message", "message state (diagnostic attribute M)"),
        ] {
            if !present.contains(word) {
                self.out.keyword(0, word, detail);
            }
        }
    }

    fn trans_header(&mut self, trans: &SyntaxNode) {
        let mut present = attribute_words(trans);
        if trans.children().any(|n| n.kind() == PRIO_CLAUSE) {
            present.insert("prio".to_owned());
        }
        for (word, detail) in [
            ("prio", "priority: 1 is the highest"),
            ("auto", "fires only in automatic mode"),
            ("manual", "fires only in manual mode"),
            ("waits", "honours the source state's wait time"),
            ("fault", "fault transition (for diagnostics)"),
        ] {
            if !present.contains(word) {
                self.out.keyword(0, word, detail);
            }
        }
    }

    fn endpoints(&mut self, trans: &SyntaxNode, source: bool) {
        let Some(graph) = trans.ancestors().find(|n| n.kind() == GRAPH) else {
            return;
        };
        let Some(item) = self.item_loc(&graph) else {
            return;
        };
        let members = graph_members(self.db, item);
        let mut seen = HashSet::new();
        let mut states: Vec<&StateInfo> = members
            .states
            .iter()
            .filter(|s| seen.insert(s.number))
            .collect();
        states.sort_by_key(|s| s.number);
        for state in states {
            if let Some(proposal) = self
                .out
                .add(0, state.number.to_string(), CompletionKind::State)
            {
                proposal.detail = state.name.as_ref().map(|n| format!("\"{n}\""));
            }
        }
        if source {
            self.out
                .keyword(1, "any", "any-transition: from every state");
        } else {
            self.out
                .keyword(1, "return", "return transition: back to the previous state");
        }
    }

    /// The predefined variables that need `activate` and are not activated yet.
    fn activate(&mut self, activate: &SyntaxNode) {
        let Some(members) = activate
            .ancestors()
            .find(|n| n.kind() == GRAPH)
            .and_then(|g| self.item_loc(&g))
            .map(|item| graph_members(self.db, item))
        else {
            return;
        };
        // The word being typed is in the list already; it does not count.
        let mut activated = members.activated.clone();
        if let Some(word) = &self.cursor.word
            && let Some(at) = activated.iter().position(|a| a == word.text())
        {
            activated.remove(at);
        }
        for predefined in lang::PREDEFINED.iter().filter(|p| !p.active_by_default) {
            if activated
                .iter()
                .any(|a| a.eq_ignore_ascii_case(predefined.name))
            {
                continue;
            }
            if let Some(item) = self
                .out
                .add(0, predefined.name, CompletionKind::PredefinedVariable)
            {
                item.detail = Some(format!("{} {}", predefined.section.as_str(), predefined.ty));
                item.documentation = Some(predefined.meaning.to_owned());
            }
        }
    }

    fn types(&mut self, interface: bool) {
        let names = Type::NAMES
            .iter()
            .chain(if interface { INTERFACE_TYPES } else { &[] });
        for name in names {
            self.out.add(0, *name, CompletionKind::Type);
        }
    }

    // -------------------------------------------------------------------- graph operands

    /// The declarations of the graph holding `node`.
    fn graph_scope(&self, node: &SyntaxNode) -> Option<GraphScope<'a>> {
        let graph = node.ancestors().find(|n| n.kind() == GRAPH)?;
        let item = self.item_loc(&graph)?;
        Some(GraphScope {
            interface: graph_interface(self.db, item),
            members: graph_members(self.db, item),
        })
    }

    /// An STL operand (after `opcode`), a CALL actual or (`time`) a wait/supervise time.
    fn operand(&mut self, node: &SyntaxNode, opcode: Option<&str>, time: bool) {
        let Some(scope) = self.graph_scope(node) else {
            return;
        };
        let class = opcode.map_or(OperandClass::Load, |op| opcode_class(op, self.mnemonic));
        let preferred: &[Type] = if time {
            &[Type::Time]
        } else {
            class.preferred()
        };
        if class == OperandClass::Nothing {
            return;
        }
        if class == OperandClass::Block {
            self.block_symbols();
            return;
        }
        // A time value must be of type TIME (HG3004): nothing else is proposed there. Elsewhere
        // the preferred types come first and the rest after them.
        let only = time;
        if !self.cursor.quoted() {
            self.variables(&scope, preferred, only, true);
        }
        self.symbols(preferred, only, scope.interface);
    }

    /// The graph's variables and active predefined variables, those of a `preferred` type
    /// first (`only`: no others). `hash`: write `#Name` where a plain name would read as an
    /// address.
    fn variables(&mut self, scope: &GraphScope<'_>, preferred: &[Type], only: bool, hash: bool) {
        let rank = |ty: Option<Type>, base: u8| preference_rank(preferred, only, ty, base);
        for var in &scope.interface.vars {
            let Some(rank) = rank(var.ty, 0) else {
                continue;
            };
            let kind = if var.message().is_some() {
                CompletionKind::Message
            } else {
                CompletionKind::Variable
            };
            let needs_hash = hash && self.reads_as_address(&var.name);
            let detail = var_detail(var);
            if let Some(item) = self.out.add(rank, var.name.clone(), kind) {
                item.detail = Some(detail);
                if needs_hash {
                    item.insert_text = Some(format!("#{}", var.name));
                }
            }
        }
        for predefined in lang::PREDEFINED {
            if predefined.internal
                || !scope.members.is_active(predefined)
                || scope.interface.var(predefined.name).is_some()
            {
                continue;
            }
            let Some(rank) = rank(Some(predefined.ty), 1) else {
                continue;
            };
            if let Some(item) =
                self.out
                    .add(rank, predefined.name, CompletionKind::PredefinedVariable)
            {
                item.detail = Some(format!(
                    "{} {} (predefined)",
                    predefined.section.as_str(),
                    predefined.ty
                ));
                item.documentation = Some(predefined.meaning.to_owned());
            }
        }
    }

    /// Would `name` written plainly read as an address or an area in this file (§2.4)?
    fn reads_as_address(&self, name: &str) -> bool {
        resolve::address_without_space(name, self.mnemonic).is_some()
            || resolve::area_word(name, self.mnemonic).is_some()
    }

    /// Global symbols (not blocks). A symbol is quoted when it is not an identifier, when a
    /// variable of the graph has its name, when it reads as an address, or when the user
    /// started with `"`.
    /// Global symbols, those of a `preferred` type first (`only`: no others).
    fn symbols(&mut self, preferred: &[Type], only: bool, shadowing: &GraphInterface) {
        let quoted = self.cursor.quoted();
        let index = self.index;
        let mut seen = HashSet::new();
        for symbol in &index.symbols {
            if symbol.ty == Some(Type::Block) {
                continue;
            }
            let must_quote = quoted
                || !is_identifier(&symbol.name)
                || shadowing.var(&symbol.name).is_some()
                || lang::predefined(&symbol.name).is_some()
                || self.reads_as_address(&symbol.name);
            let label = if quoted {
                format!("\"{}\"", symbol.name)
            } else {
                symbol.name.clone()
            };
            if !matches_typed(&label, &self.out.typed) || !seen.insert(index::key(&symbol.name)) {
                continue;
            }
            let Some(rank) = preference_rank(preferred, only, symbol.ty, 2) else {
                continue;
            };
            if let Some(item) = self.out.add(rank, label, CompletionKind::Symbol) {
                item.detail = Some(symbol_detail(symbol));
                item.documentation = symbol.comment.clone().filter(|c| !c.is_empty());
                if must_quote && !quoted {
                    item.insert_text = Some(format!("\"{}\"", symbol.name));
                }
            }
        }
    }

    /// Blocks for CALL / CC: block symbols and declared block interfaces.
    fn block_symbols(&mut self) {
        let mut seen = HashSet::new();
        let index = self.index;
        for entry in &index.block_interfaces {
            let reference = entry
                .reference
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ");
            if seen.insert(index::key(&reference))
                && let Some(item) = self.out.add(0, reference, CompletionKind::Symbol)
            {
                item.detail = Some("block with a declared interface".to_owned());
            }
        }
        for symbol in index.symbols.iter().filter(|s| s.ty == Some(Type::Block)) {
            let label = if is_identifier(&symbol.name) && !self.cursor.quoted() {
                symbol.name.clone()
            } else {
                format!("\"{}\"", symbol.name)
            };
            if !seen.insert(index::key(&symbol.name)) {
                continue;
            }
            if let Some(item) = self.out.add(1, label, CompletionKind::Symbol) {
                item.detail = Some(symbol_detail(symbol));
                item.documentation = symbol.comment.clone().filter(|c| !c.is_empty());
            }
        }
    }

    // -------------------------------------------------------------------- groups

    fn group_members(&mut self) {
        self.out.snippet(
            0,
            "instance",
            "instance Name : Graph < ... >",
            "instance ${1:Name} : ${2:Graph} <\n  $0\n>".to_owned(),
        );
        self.out
            .keyword(1, "option", "a compile option of the group");
    }

    /// The statement keywords of a test; `cycle` and `run` first while only they stand
    /// before the cursor (HG9001).
    fn test_statements(&mut self, test: &SyntaxNode) {
        let offset = self.cursor.offset;
        let statements: Vec<ast::TestStmt> = ast::Test::cast(test.clone())
            .map(|t| t.statements().collect())
            .unwrap_or_default();
        let before = |s: &ast::TestStmt| s.syntax().text_range().end() <= offset;
        let at_top = statements
            .iter()
            .filter(|s| before(s))
            .all(|s| matches!(s, ast::TestStmt::Cycle(_) | ast::TestStmt::Run(_)));
        let has = |keyword: &str| statements.iter().any(|s| s.keyword() == keyword);
        let top_rank = if at_top { 0 } else { 2 };
        if !has("cycle") {
            self.out
                .keyword(top_rank, "cycle", "the cycle time (default T#10MS)");
        }
        if !has("run") {
            self.out
                .keyword(top_rank, "run", "the groups and charts to run, in order");
        }
        for (keyword, detail) in TEST_STATEMENTS {
            self.out.keyword(1, keyword, detail);
        }
    }

    /// Groups and plain charts (a test's run list); with `charts_only`, plain charts.
    fn runnable(&mut self, charts_only: bool) {
        let index = self.index;
        for item in &index.items {
            let (kind, what) = match item.kind {
                ItemKind::Group if !charts_only => (CompletionKind::Instance, "group"),
                ItemKind::Chart if !item.chart_type => (CompletionKind::Graph, "chart"),
                _ => continue,
            };
            let path = item.file.path(self.db).clone();
            if let Some(proposal) = self.out.add(0, item.name.clone(), kind) {
                proposal.detail = Some(format!("{what} in {path}"));
            }
        }
    }

    fn graph_names(&mut self) {
        let index = self.index;
        for item in index.items.iter().filter(|i| i.kind == ItemKind::Graph) {
            let path = item.file.path(self.db).clone();
            if let Some(proposal) = self.out.add(0, item.name.clone(), CompletionKind::Graph) {
                proposal.detail = Some(format!("graph in {path}"));
            }
        }
    }

    /// The interface of the graph an instance instantiates.
    fn instance_interface(&self, instance: &ast::Instance) -> Option<&'a GraphInterface> {
        let graph = instance.graph()?.text();
        let item = self.index.graph(&graph)?;
        let loc = ItemLoc::new(self.db, item.file, item.item);
        Some(graph_interface(self.db, loc))
    }

    /// The formals not yet wired, inserting `Formal := `.
    fn formals(&mut self, instance: &SyntaxNode) {
        let Some(instance) = ast::Instance::cast(instance.clone()) else {
            return;
        };
        let Some(interface) = self.instance_interface(&instance) else {
            return;
        };
        let current = self.cursor.word.clone();
        let wired: Vec<String> = instance
            .actuals()
            .filter_map(|a| a.formal()?.token())
            .filter(|t| Some(t) != current.as_ref())
            .map(|t| t.text().to_owned())
            .collect();
        let is_wired = |name: &str| wired.iter().any(|w| w.eq_ignore_ascii_case(name));
        let mut formals = Vec::new();
        for name in interface.formal_names() {
            if is_wired(name) {
                continue;
            }
            let (detail, rank, kind) = match interface.var(name) {
                Some(var) => {
                    let rank = if var.message() == Some(MsgDir::Incoming) {
                        1
                    } else {
                        0
                    };
                    let kind = if var.message().is_some() {
                        CompletionKind::Message
                    } else {
                        CompletionKind::Formal
                    };
                    (var_detail(var), rank, kind)
                }
                None => ("in BOOL (predefined)".to_owned(), 2, CompletionKind::Formal),
            };
            formals.push((name.to_owned(), detail, rank, kind));
        }
        for (name, detail, rank, kind) in formals {
            if let Some(item) = self.out.add(rank, name.clone(), kind) {
                item.detail = Some(detail);
                item.insert_text = Some(format!("{name} := "));
            }
        }
    }

    /// The value of `Formal := `: global symbols (those of the formal's type first) and, for an
    /// outgoing message, the other instances of the group (`Inst.`).
    fn actual_value(&mut self, actual: &SyntaxNode) {
        let Some(actual) = ast::Actual::cast(actual.clone()) else {
            return;
        };
        let instance = actual.syntax().ancestors().find_map(ast::Instance::cast);
        let formal = actual.formal().map(|f| f.text()).unwrap_or_default();
        let var = instance
            .as_ref()
            .and_then(|i| self.instance_interface(i))
            .and_then(|i| i.var(&formal))
            .cloned();
        let preferred: Vec<Type> = var.as_ref().and_then(|v| v.ty).into_iter().collect();
        if var.as_ref().and_then(|v| v.message()) == Some(MsgDir::Outgoing)
            && !self.cursor.quoted()
            && let Some(instance) = &instance
        {
            self.message_instances(instance);
        }
        self.symbols(&preferred, false, &GraphInterface::default());
    }

    /// The instances of the group of `current` (other than it) that have incoming messages,
    /// inserting `Inst.`.
    fn message_instances(&mut self, current: &ast::Instance) {
        let Some(group) = current.syntax().ancestors().find_map(ast::Group::cast) else {
            return;
        };
        let mut found = Vec::new();
        for instance in group.instances() {
            if instance.syntax() == current.syntax() {
                continue;
            }
            let (Some(name), Some(graph)) = (instance.name(), instance.graph()) else {
                continue;
            };
            let has_incoming = self
                .instance_interface(&instance)
                .is_some_and(|i| i.vars.iter().any(|v| v.message() == Some(MsgDir::Incoming)));
            if has_incoming {
                found.push((name.text(), graph.text()));
            }
        }
        for (name, graph) in found {
            if let Some(item) = self.out.add(0, name.clone(), CompletionKind::Instance) {
                item.detail = Some(format!("instance of {graph}"));
                item.insert_text = Some(format!("{name}."));
            }
        }
    }

    /// After `Inst.`: the incoming messages of that instance's graph.
    fn messages(&mut self, actual: &SyntaxNode, instance_name: &str) {
        let Some(group) = actual.ancestors().find_map(ast::Group::cast) else {
            return;
        };
        let Some(instance) = group.instances().find(|i| {
            i.name()
                .is_some_and(|n| n.text().eq_ignore_ascii_case(instance_name))
        }) else {
            return;
        };
        let Some(interface) = self.instance_interface(&instance) else {
            return;
        };
        let messages: Vec<String> = interface
            .vars
            .iter()
            .filter(|v| v.message() == Some(MsgDir::Incoming))
            .map(|v| v.name.clone())
            .collect();
        let graph = interface.name.clone();
        for name in messages {
            if let Some(item) = self.out.add(0, name, CompletionKind::Message) {
                item.detail = Some(format!("BOOL msg in of {graph}"));
            }
        }
    }

    // -------------------------------------------------------------------- charts

    fn chart_members(&mut self) {
        self.out
            .keyword(0, "sequencer", "a sequencer of steps and transitions");
        self.section_keywords(1);
        self.out
            .keyword(1, "mode", "operating mode: auto or manual");
        self.out.keyword(
            1,
            "switching",
            "switching mode: T, B, T_or_B, T_and_B or step",
        );
        self.out
            .keyword(1, "run", "run option: cyclic, time_monitoring or autostart");
        self.out
            .keyword(1, "profile", "the rules the chart follows: pcs7 or iec");
        self.out
            .keyword(2, "action", "an action with statements (IEC charts)");
    }

    fn chart_prop(&mut self, keyword: SyntaxKind) {
        let values: &[(&str, &str)] = match keyword {
            MODE_KW => &[("auto", "automatic mode"), ("manual", "manual mode")],
            PROFILE_KW => &[
                ("pcs7", "PCS 7 SFC rules (the default)"),
                ("iec", "IEC 61131-3 sequential function chart"),
            ],
            SWITCHING_KW => &[
                ("T", "transitions switch"),
                ("B", "operator commands switch"),
                ("T_or_B", "transitions or operator commands"),
                ("T_and_B", "transitions and operator commands"),
                ("step", "step by step, with confirmation"),
            ],
            _ => &[
                ("cyclic", "cyclic operation"),
                ("time_monitoring", "monitor the step times"),
                ("autostart", "start automatically"),
            ],
        };
        for (value, detail) in values {
            self.value(0, value, detail);
        }
    }

    fn seq_elements(&mut self) {
        self.out.snippet(
            0,
            "step",
            "step NAME < ... >",
            "step ${1:NAME} <\n  $0\n>".to_owned(),
        );
        self.out.keyword(0, "trans", "a transition between steps");
        self.out.keyword(1, "parallel", "parallel branches");
        self.out.keyword(1, "alt", "alternative branches");
        self.out
            .keyword(1, "jump", "a jump to a step of the sequencer");
        self.out
            .keyword(1, "loop", "a loop back to an earlier step");
    }

    fn step_items(&mut self) {
        for (word, detail) in [
            ("init", "statements of the first cycle"),
            ("run", "statements of each cycle"),
            ("term", "statements of the last cycle"),
        ] {
            self.out.keyword(0, word, detail);
        }
        for (qualifier, detail) in QUALIFIERS {
            self.out.keyword(1, qualifier, detail);
        }
        self.out.keyword(2, "min", "minimum step run time");
        self.out.keyword(2, "max", "maximum step run time");
        self.out
            .keyword(2, "confirm", "the operator confirms the step");
    }

    /// An operand of a chart expression: the chart's variables and (for a chart that is not a
    /// chart type) global symbols.
    fn chart_operand(&mut self, node: &SyntaxNode, negatable: bool) {
        let Some(chart) = node.ancestors().find_map(ast::Chart::cast) else {
            return;
        };
        if !self.cursor.quoted() {
            let mut seen = HashSet::new();
            let mut vars = Vec::new();
            for section in chart.var_sections() {
                let Some(kind) = section
                    .keyword()
                    .and_then(|k| Section::from_keyword(k.text()))
                else {
                    continue;
                };
                for decl in section.decls() {
                    let Some(name) = decl.name().map(|n| n.text()).filter(|n| !n.is_empty()) else {
                        continue;
                    };
                    if !seen.insert(index::key(&name)) {
                        continue;
                    }
                    let fb = decl
                        .ty()
                        .and_then(|t| t.name())
                        .and_then(|t| FbType::from_name(t.text()));
                    let ty = decl
                        .ty()
                        .and_then(|t| index::declared_type(&t))
                        .map(|t| t.to_string())
                        .or_else(|| fb.map(|f| f.name().to_owned()))
                        .unwrap_or_else(|| "?".to_owned());
                    vars.push((name, format!("{} {ty}", kind.as_str())));
                }
            }
            for (name, detail) in vars {
                if let Some(item) = self.out.add(0, name, CompletionKind::Variable) {
                    item.detail = Some(detail);
                }
            }
        }
        if !chart.is_type() {
            self.symbols(&[], false, &GraphInterface::default());
        }
        if negatable && !self.cursor.quoted() {
            self.out.keyword(3, "not", "logical negation");
            self.value(3, "TRUE", "BOOL constant");
            self.value(3, "FALSE", "BOOL constant");
        }
        if chart.profile() != ast::Profile::Iec || self.cursor.quoted() {
            return;
        }
        let statement_start = node.kind() == BODY
            && node.parent().is_some_and(|p| {
                matches!(
                    p.kind(),
                    STEP_PHASE
                        | PRE_PART
                        | POST_PART
                        | CHART_ACTION
                        | IF_STMT
                        | ELSIF_CLAUSE
                        | ELSE_CLAUSE
                        | CASE_ARM
                )
            });
        if node.kind() == QUALIFIER_ACTION {
            // A qualifier's operand may name an action.
            for action in chart.actions() {
                let Some(name) = action.name().map(|n| n.text()).filter(|n| !n.is_empty()) else {
                    continue;
                };
                if let Some(item) = self.out.add(0, name, CompletionKind::Variable) {
                    item.detail = Some("action".to_owned());
                }
            }
        } else if statement_start {
            self.iec_statements(&chart);
        } else {
            // Steps as values: `Step.X`, `Step.T`.
            for step in chart.syntax().descendants().filter_map(ast::Step::cast) {
                let Some(name) = step.name().map(|n| n.text()).filter(|n| !n.is_empty()) else {
                    continue;
                };
                if let Some(item) = self.out.add(2, format!("{name}.X"), CompletionKind::Step) {
                    item.detail = Some("BOOL: the step is active".to_owned());
                }
                if let Some(item) = self.out.add(2, format!("{name}.T"), CompletionKind::Step) {
                    item.detail = Some("TIME: how long the step has been active".to_owned());
                }
            }
        }
    }

    /// The steps of the sequencer holding a jump or loop.
    fn step_names(&mut self, jump: &SyntaxNode) {
        let Some(sequencer) = jump.ancestors().find_map(ast::Sequencer::cast) else {
            return;
        };
        let mut steps = Vec::new();
        collect_steps(sequencer.elements(), &mut steps);
        for step in steps {
            let Some(name) = step.name().map(|n| n.text()).filter(|n| !n.is_empty()) else {
                continue;
            };
            let comment = step.comment().map(|c| format!("\"{}\"", c.value()));
            if let Some(item) = self.out.add(0, name, CompletionKind::Step) {
                item.detail = comment;
            }
        }
    }

    // -------------------------------------------------------------------- helpers

    /// The salsa item of a top-level node of the file.
    fn item_loc(&self, node: &SyntaxNode) -> Option<ItemLoc<'a>> {
        let item = node
            .ancestors()
            .find(|n| n.parent().is_some_and(|p| p.kind() == SOURCE_FILE))?;
        let index = item_nodes(&self.root).position(|n| n == item)?;
        Some(ItemLoc::new(self.db, self.file, u32::try_from(index).ok()?))
    }
}

/// The function block type of a chart variable of that name.
fn fb_instance(chart: &ast::Chart, name: &str) -> Option<FbType> {
    chart
        .var_sections()
        .flat_map(|s| s.decls())
        .find(|d| {
            d.name()
                .is_some_and(|n| n.text().eq_ignore_ascii_case(name))
        })
        .and_then(|d| d.ty())
        .and_then(|t| t.name())
        .and_then(|t| FbType::from_name(t.text()))
}

/// A graph's declarations, from the cached queries.
struct GraphScope<'a> {
    interface: &'a GraphInterface,
    members: &'a GraphMembers,
}

/// `in BOOL`, `in_out BOOL msg in`.
fn var_detail(var: &InterfaceVar) -> String {
    let ty = var.ty.map_or_else(|| "?".to_owned(), |t| t.to_string());
    let msg = match var.message() {
        Some(MsgDir::Incoming) => " msg in",
        Some(MsgDir::Outgoing) => " msg out",
        None => "",
    };
    format!("{} {ty}{msg}", var.section.as_str())
}

/// `E 0.0 BOOL` — the address as written and the type.
fn symbol_detail(symbol: &index::Symbol) -> String {
    let address = symbol
        .address_text
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    match symbol.ty {
        Some(ty) => format!("{address} {ty}"),
        None => address,
    }
}

/// The attribute keywords of a header, lower-cased.
fn attribute_words(node: &SyntaxNode) -> HashSet<String> {
    node.children()
        .filter_map(ast::Attribute::cast)
        .filter_map(|a| a.keyword())
        .map(|k| k.text().to_ascii_lowercase())
        .collect()
}

/// Steps of a sequencer, branches included, in text order.
fn collect_steps(elements: impl Iterator<Item = ast::SeqElement>, out: &mut Vec<ast::Step>) {
    for element in elements {
        match element {
            ast::SeqElement::Step(step) => out.push(step),
            ast::SeqElement::Parallel(p) => {
                for branch in p.branches() {
                    collect_steps(branch.elements(), out);
                }
            }
            ast::SeqElement::Alt(a) => {
                for branch in a.branches() {
                    collect_steps(branch.elements(), out);
                }
            }
            _ => {}
        }
    }
}

/// Can `name` be written without quotes?
fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    use crate::ide::fixture;

    use super::{CompletionItem, CompletionKind};

    /// The proposals at the cursor, one a line: kind, label, detail, inserted text.
    fn check(text: &str) -> String {
        render(&complete(text))
    }

    fn complete(text: &str) -> Vec<CompletionItem> {
        let f = fixture::load(text);
        f.host
            .analysis()
            .completions(&f.position)
            .expect("not cancelled")
    }

    fn render(items: &[CompletionItem]) -> String {
        items
            .iter()
            .map(|item| {
                let mut line = format!("{:?} {}", item.kind, item.label);
                if let Some(detail) = &item.detail {
                    line.push_str(&format!(" · {detail}"));
                }
                if let Some(insert) = &item.insert_text {
                    line.push_str(&format!(" ⇒ {}", insert.replace('\n', "⏎")));
                }
                line
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// The labels of the proposals of one kind.
    fn labels(items: &[CompletionItem], kind: CompletionKind) -> Vec<String> {
        items
            .iter()
            .filter(|i| i.kind == kind)
            .map(|i| i.label.clone())
            .collect()
    }

    const VALVE: &str = r#"
graph Ventil_2E "valve" <
  in     < Oben : BOOL; Unten : BOOL; Zeit : TIME; >
  out    < Auf : BOOL; Ab : BOOL; Zaehler : COUNTER; Uhr : TIMER; Wert : INT; >
  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
  activate CurrentState;
  state 0 "Init" < >
  state 1 "Oben" < E: S OM_Oben; >
  state 4 < >
  trans any->0 prio 1 < U INIT_SD; >
"#;

    fn valve(tail: &str) -> String {
        format!(
            "//- main.higraph\n{VALVE}{tail}\n>\n//- symbols.higraph\nsymbols <\n  Bohrer_Oben : E 0.0 BOOL \"drill at top\";\n  \"Not Aus\" : E 0.1;\n  Laufzeit : MD 4 TIME;\n  Oben : E 0.2;\n  GG_Bohr : FC 1;\n>\n"
        )
    }

    #[test]
    fn items_at_the_start_of_a_file() {
        insta::assert_snapshot!(check("// header\n$0"), @r#"
Snippet graph · graph Name < ... > with a startup transition ⇒ graph ${1:Name} <⏎  state 0 "${2:Init}" < >⏎  trans any->0 prio 1 "startup" < U INIT_SD; >⏎  $0⏎>
Snippet group · group Name < instance ... > ⇒ group ${1:Name} <⏎  instance ${2:Inst} : ${3:Graph} <⏎    $0⏎  >⏎>
Snippet chart · chart Name < sequencer ... > ⇒ chart ${1:Name} <⏎  sequencer ${2:S1} <⏎    start < ${3:TRUE}; >⏎    step ${4:START} < $0 >⏎  >⏎>
Snippet test · test Name < run ...; expect ...; > ⇒ test ${1:Name} <⏎  run ${2:Group};⏎  $0⏎>
Keyword symbols · a table of global symbols
Keyword block · the interface of an external block
Keyword mnemonic · the STL mnemonics of this file
"#);
    }

    #[test]
    fn items_after_an_item_have_no_mnemonic() {
        let items = complete("graph G < >\n$0");
        assert_eq!(
            items.iter().map(|i| i.label.as_str()).collect::<Vec<_>>(),
            ["graph", "group", "chart", "test", "symbols", "block"]
        );
        let typed = complete("graph G < >\ng$0");
        assert_eq!(labels(&typed, CompletionKind::Snippet), ["graph", "group"]);
    }

    const TEST_WORKSPACE: &str =
        "group Linie < >\nchart Tank < >\nchart type Vorlage < >\ngraph Blink < >\n";

    const PATH_WORKSPACE: &str = r#"//- plant.higraph
graph Ventil <
  in < Oben : BOOL; >
  out < Auf : BOOL; >
  state 0 < C: U Oben; = Auf; >
  trans any->0 < U INIT_SD; >
>
group Anlage fc FC 1 db DB 1 <
  instance V1 : Ventil < Oben := Start; >
>
chart Mischer <
  in < Freigabe : BOOL; >
  sequencer RUN <
    start < Freigabe; >
    step Heizen < >
    trans T1 < Freigabe; >
  >
>
symbols < Start : E 0.0 BOOL; Dosieren : FC 10; >
block Dosieren < in < Soll : INT; > out < Menge : INT; > in_out < Stand : INT; > >
//- tests.higraph
test T1 <
  run Anlage, Mischer;
  CURSOR
>
"#;

    fn in_path(statement: &str) -> Vec<CompletionItem> {
        complete(&PATH_WORKSPACE.replace("CURSOR", statement))
    }

    #[test]
    fn test_path_members() {
        insta::assert_snapshot!(render(&in_path("set V1.$0")).lines().take(5).collect::<Vec<_>>().join("\n"), @"
        Variable Oben · in BOOL
        Variable Auf · out BOOL
        Keyword state · WORD: the instance's current state
        Keyword previous · WORD: the state before the last state change
        PredefinedVariable ManualMode · predefined BOOL
        ");
        let instance = in_path("expect Anlage.V1.$0");
        assert!(
            labels(&instance, CompletionKind::PredefinedVariable)
                .contains(&"ManualMode".to_owned())
        );
        assert_eq!(labels(&instance, CompletionKind::Variable), ["Oben", "Auf"]);
        insta::assert_snapshot!(render(&in_path("expect Anlage.$0")), @"Instance V1 · instance of group Anlage");
        insta::assert_snapshot!(render(&in_path("expect Mischer.$0")), @"
        Variable Freigabe · BOOL
        Step RUN · sequencer
        Step Heizen · step of sequencer RUN
        Keyword state · the chart's operating state
        ");
        insta::assert_snapshot!(render(&in_path("expect Mischer.RUN.$0")), @"Step Heizen · step of sequencer RUN");
        insta::assert_snapshot!(render(&in_path("expect Mischer.RUN.Heizen.$0")), @"
        Keyword X · BOOL: the step is active
        Keyword T · TIME: how long the step has been active
        Keyword error · BOOL: the step exceeded its supervision time
        ");
        insta::assert_snapshot!(render(&in_path("expect Mischer.Heizen.T$0")), @"Keyword T · TIME: how long the step has been active");
        insta::assert_snapshot!(render(&in_path("expect Dosieren.$0")), @"
        Formal Menge · out of Dosieren: its stub value
        Formal Stand · in_out of Dosieren: its stub value
        Keyword calls · DINT: how often Dosieren was called
        ");
        let states = in_path("expect Mischer.state = $0");
        assert_eq!(states.len(), 16);
        assert_eq!(states[0].label, "Ready");
        insta::assert_snapshot!(render(&in_path("expect V1.Auf and $0")), @"
        Instance V1 · instance of group Anlage
        Graph Mischer · chart
        Instance Anlage · group
        Symbol Start · E 0.0 BOOL
        ");
        insta::assert_snapshot!(render(&in_path("set $0")), @"
        Instance V1 · instance of group Anlage
        Graph Mischer · chart
        Instance Anlage · group
        Symbol Start · E 0.0 BOOL
        ");
        insta::assert_snapshot!(render(&in_path("set V1.Auf := $0")), @"
        Instance V1 · instance of group Anlage
        Graph Mischer · chart
        Instance Anlage · group
        Symbol Start · E 0.0 BOOL
        ");
        insta::assert_snapshot!(render(&in_path("confirm Mi$0")), @"Graph Mischer · chart");
    }

    #[test]
    fn test_statements_put_cycle_and_run_first_while_they_can() {
        let at_top = complete(&format!(
            "{TEST_WORKSPACE}test T <\n  cycle T#10MS;\n  $0\n>"
        ));
        assert_eq!(
            at_top.iter().map(|i| i.label.as_str()).collect::<Vec<_>>(),
            [
                "run", "set", "step", "wait", "until", "expect", "command", "confirm", "restart"
            ]
        );
        let later = complete(&format!("{TEST_WORKSPACE}test T <\n  step;\n  ex$0\n>"));
        assert_eq!(labels(&later, CompletionKind::Keyword), ["expect"]);
        let after = complete(&format!("{TEST_WORKSPACE}test T <\n  step;\n  $0\n>"));
        let labels_after: Vec<&str> = after.iter().map(|i| i.label.as_str()).collect();
        assert_eq!(labels_after.last(), Some(&"run"));
    }

    #[test]
    fn test_run_lists_commands_and_restarts() {
        insta::assert_snapshot!(check(&format!("{TEST_WORKSPACE}test T < run $0 >")), @r#"
Instance Linie · group in main.higraph
Graph Tank · chart in main.higraph
"#);
        insta::assert_snapshot!(check(&format!("{TEST_WORKSPACE}test T < run Linie, T$0 >")), @"Graph Tank · chart in main.higraph");
        insta::assert_snapshot!(check(&format!("{TEST_WORKSPACE}test T < command $0 >")), @"Graph Tank · chart in main.higraph");
        insta::assert_snapshot!(check(&format!("{TEST_WORKSPACE}test T < command Tank re$0 >")), @r#"
Value resume · Held → Resuming
Value reset · Completed, Aborted, Stopped → Ready
"#);
        insta::assert_snapshot!(check(&format!("{TEST_WORKSPACE}test T < restart $0 >")), @r#"
Value cold · unbuffered: memory back to its initial values, charts Ready
Value warm · buffered: memory kept, INIT_SD = 1 next cycle
"#);
    }

    #[test]
    fn nothing_inside_a_comment() {
        assert!(complete("graph G < // sta$0\n>").is_empty());
        assert!(complete("graph G < //$0\n>").is_empty());
    }

    #[test]
    fn graph_members_with_the_next_free_state_number() {
        insta::assert_snapshot!(check(&valve("  $0")), @r#"
Snippet state · state N "name" < ... > ⇒ state ${1:5} "${2:Name}" <⏎  $0⏎>
Snippet trans · trans A->B prio N < ... > ⇒ trans ${1:0}->${2:1} prio ${3:1} <⏎  $0⏎>
Keyword in · input parameters
Keyword out · output parameters
Keyword in_out · in/out parameters and messages
Keyword stat · static variables
Keyword activate · activate predefined variables
Keyword permanent · instructions that run every cycle
"#);
    }

    #[test]
    fn graph_member_being_typed_replaces_the_word() {
        let items = complete(&valve("  sta$0"));
        insta::assert_snapshot!(render(&items), @r#"
Snippet state · state N "name" < ... > ⇒ state ${1:5} "${2:Name}" <⏎  $0⏎>
Keyword stat · static variables
"#);
        let f = fixture::load(&valve("  sta$0"));
        let range = items[0].replace_range;
        assert_eq!(f.slice("main.higraph", range), "sta");
    }

    #[test]
    fn statement_start_in_a_state_offers_labels_first() {
        insta::assert_snapshot!(check(&valve("  state 5 < X$0 >")), @r#"
Label X: · exit actions: once when the state is left ⇒ X: 
Opcode X · exclusive OR with a bit
Opcode XN · exclusive OR NOT with a bit
Opcode X( · exclusive OR with nesting: open a bracket
Opcode XN( · exclusive OR NOT with nesting: open a bracket
Opcode EXP · exponential function of a real
Opcode XOW · exclusive OR word (16 bit)
Opcode XOD · exclusive OR double word (32 bit)
"#);
    }

    #[test]
    fn statement_start_after_a_label_and_after_a_statement() {
        let after_label = complete(&valve("  state 5 < C: $0 >"));
        let after_stmt = complete(&valve("  state 5 < C: U Oben; $0 >"));
        for items in [&after_label, &after_stmt] {
            assert_eq!(
                labels(items, CompletionKind::Label),
                ["E:", "C-:", "C:", "X:"]
            );
            assert_eq!(
                labels(items, CompletionKind::Keyword),
                ["wait", "supervise"]
            );
            assert_eq!(
                labels(items, CompletionKind::Opcode).len(),
                super::OPERATIONS.len()
            );
            assert_eq!(items[0].kind, CompletionKind::Label);
        }
    }

    #[test]
    fn statement_start_in_a_transition_offers_opcodes_first() {
        let items = complete(&valve("  trans 0->1 < U Oben; $0 >"));
        assert_eq!(labels(&items, CompletionKind::Label), ["?:", "!:"]);
        assert_eq!(items[0].label, "U");
        insta::assert_snapshot!(render(&items[..8]), @r#"
Opcode U · AND: scan a bit and AND it with the RLO
Opcode UN · AND NOT: scan a bit and AND its negation
Opcode O · OR: scan a bit and OR it (alone: OR of AND groups)
Opcode ON · OR NOT: scan a bit and OR its negation
Opcode X · exclusive OR with a bit
Opcode XN · exclusive OR NOT with a bit
Opcode U( · AND with nesting: open a bracket
Opcode UN( · AND NOT with nesting: open a bracket
"#);
        let rendered = render(&items);
        let label_lines: Vec<&str> = rendered
            .lines()
            .filter(|l| l.starts_with("Label"))
            .collect();
        insta::assert_snapshot!(label_lines.join("\n"), @r#"
Label ?: · conditions: the transition fires when they give 1 ⇒ ?: 
Label !: · transition actions: once when the transition fires ⇒ !:
"#);
    }

    #[test]
    fn statement_start_in_permanent() {
        let items = complete(&valve("  permanent < $0 >"));
        assert_eq!(labels(&items, CompletionKind::Label), ["C-:", "C:"]);
        assert!(labels(&items, CompletionKind::Keyword).is_empty());
    }

    #[test]
    fn statement_start_on_a_new_line_after_an_opcode() {
        let items = complete(&valve("  state 5 < C: U\n    $0 >"));
        assert_eq!(items[0].kind, CompletionKind::Label);
    }

    #[test]
    fn every_operation_of_the_subset_has_a_description() {
        use crate::lang::{Mnemonic, subset_ops};
        let table: Vec<&str> = super::OPERATIONS.iter().map(|op| op.simatic).collect();
        let mut subset = subset_ops(Mnemonic::Simatic);
        subset.sort();
        let mut sorted = table.clone();
        sorted.sort();
        assert_eq!(sorted, subset);
        assert_eq!(
            super::operation("U(").map(|op| op.description),
            Some("AND with nesting: open a bracket")
        );
    }

    #[test]
    fn international_mnemonics() {
        let text = valve("  trans 0->1 < A Oben; S$0 >").replace(
            "//- main.higraph\n",
            "//- main.higraph\nmnemonic international;\n",
        );
        insta::assert_snapshot!(check(&text), @r#"
Opcode S · set a bit when the RLO is 1 (counter: load the preset)
Opcode SET · set the RLO to 1
Opcode SP · start a timer as pulse
Opcode SE · start a timer as extended pulse
Opcode SD · start a timer as on-delay
Opcode SS · start a timer as retentive on-delay
Opcode SF · start a timer as off-delay
Opcode ABS · absolute value of a real
Opcode SQR · square of a real
Opcode SQRT · square root of a real
Opcode SIN · sine of a real (radians)
Opcode COS · cosine of a real (radians)
Opcode ASIN · arc sine of a real
Opcode ACOS · arc cosine of a real
Opcode SLW · shift word left
Opcode SRW · shift word right
Opcode SLD · shift double word left
Opcode SRD · shift double word right
Opcode SSI · shift integer right with sign
Opcode SSD · shift double integer right with sign
Opcode PUSH · push: copy ACCU 1 into ACCU 2
"#);
    }

    #[test]
    fn international_mnemonics_from_the_configuration() {
        let text = |word: &str| {
            format!(
                "//- higraph.toml\n[workspace]\nmnemonic = \"international\"\n{}",
                valve(&format!("  trans 0->1 < A Oben; {word}$0 >"))
            )
        };
        assert_eq!(
            labels(&complete(&text("CU")), CompletionKind::Opcode),
            ["CU"]
        );
        assert!(complete(&text("ZV")).is_empty());
    }

    #[test]
    fn operand_of_an_unfinished_statement() {
        // The body is never closed and the statement has no `;`: the parser recovers at the
        // next member, the operand position is still recognised.
        insta::assert_snapshot!(check(&valve("  state 1 < C: U $0\n  state 2 < >")), @r#"
Variable Oben · in BOOL
Variable Unten · in BOOL
Variable Auf · out BOOL
Variable Ab · out BOOL ⇒ #Ab
Variable Zaehler · out COUNTER
Variable Uhr · out TIMER
Message IM_Ab · in_out BOOL msg in
Message OM_Oben · in_out BOOL msg out
PredefinedVariable ManualMode · in BOOL (predefined)
PredefinedVariable AutomaticMode · in BOOL (predefined)
PredefinedVariable UsrMsgQuit · in BOOL (predefined)
PredefinedVariable INIT_SD · stat BOOL (predefined)
PredefinedVariable ST_Expired · stat BOOL (predefined)
PredefinedVariable ST_ExpiredPrev · stat BOOL (predefined)
PredefinedVariable WT_Expired · stat BOOL (predefined)
PredefinedVariable UsrMsgSend · stat BOOL (predefined)
Symbol Bohrer_Oben · E 0.0 BOOL
Symbol Not Aus · E 0.1 BOOL ⇒ "Not Aus"
Symbol Oben · E 0.2 BOOL ⇒ "Oben"
Variable Zeit · in TIME
Variable Wert · out INT
PredefinedVariable CurrentState · stat WORD (predefined)
PredefinedVariable ST_CurrValue · stat DWORD (predefined)
PredefinedVariable WT_CurrValue · stat DWORD (predefined)
Symbol Laufzeit · MD 4 TIME
"#);
    }

    #[test]
    fn operand_being_typed() {
        let items = complete(&valve("  state 5 < C: U Ob$0"));
        insta::assert_snapshot!(render(&items), @r#"
Variable Oben · in BOOL
Message OM_Oben · in_out BOOL msg out
Symbol Bohrer_Oben · E 0.0 BOOL
Symbol Oben · E 0.2 BOOL ⇒ "Oben"
"#);
        let f = fixture::load(&valve("  state 5 < C: U Ob$0"));
        assert_eq!(f.slice("main.higraph", items[0].replace_range), "Ob");
    }

    /// A proposal whose inserted text is not the label carries the text the user types for
    /// it as its filter text, whether or not the typed word is complete: `A` or `Ab` for a
    /// variable inserted as `#Ab`; after a `#` nothing extra is inserted.
    #[test]
    fn filter_text_is_what_the_user_types() {
        let filter = |tail: &str, label: &str| {
            let items = complete(&valve(tail));
            let item = items
                .iter()
                .find(|i| i.label == label)
                .unwrap_or_else(|| panic!("no {label} in {}", render(&items)));
            (item.insert_text.clone(), item.filter_text.clone())
        };
        let some = |s: &str| Some(s.to_owned());
        assert_eq!(
            filter("  state 5 < C: = A$0 >", "Ab"),
            (some("#Ab"), some("Ab"))
        );
        assert_eq!(
            filter("  state 5 < C: = Ab$0 >", "Ab"),
            (some("#Ab"), some("Ab"))
        );
        assert_eq!(filter("  state 5 < C: = #A$0 >", "Ab"), (None, None));
        assert_eq!(filter("  state 5 < C: U A$0 >", "Auf"), (None, None));
        assert_eq!(
            filter("  state 5 < C: U No$0 >", "Not Aus"),
            (some("\"Not Aus\""), some("Not Aus"))
        );
        // Every proposal's filter text matches what was typed in its replaced range.
        for tail in [
            "  state 5 < C: U $0 >",
            "  state 5 < C: = A$0 >",
            "  state 5 < C: U Ob$0",
        ] {
            let f = fixture::load(&valve(tail));
            let items = f
                .host
                .analysis()
                .completions(&f.position)
                .unwrap_or_default();
            for item in &items {
                let typed = f.slice(
                    "main.higraph",
                    higraph_syntax::TextRange::new(item.replace_range.start(), f.position.offset),
                );
                let filter = item.filter_text.as_ref().unwrap_or(&item.label);
                assert!(super::matches_typed(filter, typed), "{tail}: {item:?}");
                assert_eq!(
                    item.filter_text.is_some(),
                    item.insert_text.is_some(),
                    "{item:?}"
                );
            }
        }
    }

    #[test]
    fn operand_after_hash_is_a_graph_variable() {
        insta::assert_snapshot!(check(&valve("  state 5 < C: = #A$0 >")), @r#"
Variable Auf · out BOOL
Variable Ab · out BOOL
Variable Zaehler · out COUNTER
Message IM_Ab · in_out BOOL msg in
PredefinedVariable ManualMode · in BOOL (predefined)
PredefinedVariable AutomaticMode · in BOOL (predefined)
PredefinedVariable CurrentState · stat WORD (predefined)
PredefinedVariable ST_CurrValue · stat DWORD (predefined)
PredefinedVariable WT_CurrValue · stat DWORD (predefined)
"#);
        let items = complete(&valve("  state 5 < C: = #$0 >"));
        assert!(labels(&items, CompletionKind::Symbol).is_empty());
        assert!(items.iter().all(|i| i.insert_text.is_none()));
    }

    #[test]
    fn operand_in_quotes_is_a_symbol() {
        let items = complete(&valve("  state 5 < C: U \"$0"));
        insta::assert_snapshot!(render(&items), @r#"
Symbol "Bohrer_Oben" · E 0.0 BOOL
Symbol "Not Aus" · E 0.1 BOOL
Symbol "Oben" · E 0.2 BOOL
Symbol "Laufzeit" · MD 4 TIME
"#);
        let f = fixture::load(&valve("  state 5 < C: U \"No$0"));
        let items = f
            .host
            .analysis()
            .completions(&f.position)
            .unwrap_or_default();
        assert_eq!(render(&items), "Symbol \"Not Aus\" · E 0.1 BOOL");
        assert_eq!(f.slice("main.higraph", items[0].replace_range), "\"No");
    }

    #[test]
    fn operands_of_timer_and_counter_operations() {
        let timer = complete(&valve("  state 5 < C: SE $0"));
        assert_eq!(timer[0].label, "Uhr");
        let counter = complete(&valve("  state 5 < C: ZV $0"));
        assert_eq!(counter[0].label, "Zaehler");
        let load = complete(&valve("  state 5 < C: L $0"));
        insta::assert_snapshot!(render(&load[..4]), @r#"
Variable Zeit · in TIME
Variable Wert · out INT
PredefinedVariable CurrentState · stat WORD (predefined)
PredefinedVariable ST_CurrValue · stat DWORD (predefined)
"#);
        assert!(complete(&valve("  state 5 < C: SET $0")).is_empty());
        assert!(complete(&valve("  state 5 < C: U( $0")).is_empty());
    }

    #[test]
    fn time_values_propose_only_time_operands() {
        // language.md §3.2: a time value is a time constant or a TIME operand (HG3004).
        insta::assert_snapshot!(check(&valve("  state 5 < supervise L$0")), @"Symbol Laufzeit · MD 4 TIME");
    }

    #[test]
    fn call_proposes_blocks() {
        let text = format!(
            "{}//- blocks.higraph\nblock FC 10 \"Dosieren\" < in < Menge : INT; > >\n",
            valve("  state 5 < C: CALL $0")
        );
        insta::assert_snapshot!(check(&text), @r#"
Symbol FC 10 · block with a declared interface
Symbol GG_Bohr · FC 1 BLOCK
"#);
    }

    #[test]
    fn variable_section_types() {
        insta::assert_snapshot!(check("graph G < in < A : $0"), @r#"
Type BOOL
Type BYTE
Type WORD
Type DWORD
Type INT
Type DINT
Type REAL
Type S5TIME
Type TIME
Type DATE
Type TIME_OF_DAY
Type TOD
Type DATE_AND_TIME
Type DT
Type CHAR
Type STRING
Type TIMER
Type COUNTER
"#);
        let interface = complete("block FC 10 < in < P : $0 > >");
        assert!(labels(&interface, CompletionKind::Type).contains(&"BLOCK_DB".to_owned()));
        let symbol = complete("symbols < S : MW 10 $0 >");
        assert!(labels(&symbol, CompletionKind::Type).contains(&"INT".to_owned()));
    }

    #[test]
    fn message_kinds_in_in_out() {
        insta::assert_snapshot!(check("graph G < in_out < M : BOOL $0"), @r#"
Keyword msg in · incoming message
Keyword msg out · outgoing message
"#);
        insta::assert_snapshot!(check("graph G < in_out < M : BOOL msg $0"), @r#"
Keyword in · incoming message
Keyword out · outgoing message
"#);
        assert!(complete("graph G < in < M : BOOL $0").is_empty());
    }

    #[test]
    fn mnemonic_sets() {
        insta::assert_snapshot!(check("mnemonic $0"), @r#"
Value simatic · German mnemonics: U E 1.0
Value international · English mnemonics: A I 1.0
"#);
    }

    #[test]
    fn activate_offers_inactive_predefined_variables() {
        insta::assert_snapshot!(check(&valve("  activate StateChange, $0")), @r#"
PredefinedVariable PreviousState · stat WORD
PredefinedVariable ST_Stop · stat BOOL
PredefinedVariable WT_Stop · stat BOOL
"#);
    }

    #[test]
    fn state_and_transition_header_keywords() {
        insta::assert_snapshot!(check(&valve("  state 5 \"Auf\" fault $0 < >")), @"Keyword message · message state (diagnostic attribute M)");
        insta::assert_snapshot!(check(&valve("  trans 1->4 prio 2 auto $0 < >")), @r#"
Keyword manual · fires only in manual mode
Keyword waits · honours the source state's wait time
Keyword fault · fault transition (for diagnostics)
"#);
        assert!(complete(&valve("  trans 1->4 prio $0 < >")).is_empty());
    }

    #[test]
    fn transition_endpoints_are_state_numbers() {
        insta::assert_snapshot!(check(&valve("  trans $0")), @r#"
State 0 · "Init"
State 1 · "Oben"
State 4
Keyword any · any-transition: from every state
"#);
        insta::assert_snapshot!(check(&valve("  trans 1->$0\n  trans 1->4 < >")), @r#"
State 0 · "Init"
State 1 · "Oben"
State 4
Keyword return · return transition: back to the previous state
"#);
        let items = complete(&valve("  trans 1->4$0 < >"));
        assert_eq!(labels(&items, CompletionKind::State), ["4"]);
    }

    const GROUP: &str = r#"//- graphs.higraph
graph Ventil_2E <
  in < Oben : BOOL; Zeit : TIME; >
  out < Auf : BOOL; >
  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
>
graph Bohren <
  in_out < IM_Oben : BOOL msg in; IM_Start : BOOL msg in; OM_Senken : BOOL msg out; >
>
//- symbols.higraph
symbols <
  Bohrer_Oben : E 0.0 BOOL;
  Wartezeit : MD 4 TIME;
>
//- group.higraph
"#;

    #[test]
    fn group_members() {
        insta::assert_snapshot!(check(&format!("{GROUP}group G <\n  $0\n>\n")), @r#"
Snippet instance · instance Name : Graph < ... > ⇒ instance ${1:Name} : ${2:Graph} <⏎  $0⏎>
Keyword option · a compile option of the group
"#);
        insta::assert_snapshot!(check(&format!("{GROUP}group G <\n  option $0\n>\n")), @r#"
Value cyclic_rlo0 · run the cyclic actions once more with RLO = 0 when leaving a state
Value any_once · an any-transition does not fire when already in its target state
Value precyclic_on_entry · run C- actions in the entry cycle too
Value restructure · rebuild the instance DB
Value reserve · reserve N words in the DB (only with 'restructure')
Value refdata · generate reference data
"#);
        insta::assert_snapshot!(check(&format!("{GROUP}group G $0 <\n>\n")), @r#"
Keyword fc · the FC the group compiles to
Keyword db · the DB the group compiles to
"#);
    }

    #[test]
    fn instance_graph_names() {
        insta::assert_snapshot!(check(&format!("{GROUP}group G <\n  instance V : $0\n>\n")), @r#"
Graph Ventil_2E · graph in graphs.higraph
Graph Bohren · graph in graphs.higraph
"#);
        let items = complete(&format!("{GROUP}group G <\n  instance V : Bo$0 < >\n>\n"));
        assert_eq!(labels(&items, CompletionKind::Graph), ["Bohren"]);
    }

    #[test]
    fn instance_formals_not_yet_wired() {
        insta::assert_snapshot!(
            check(&format!("{GROUP}group G <\n  instance V : Ventil_2E <\n    Oben := Bohrer_Oben;\n    $0\n  >\n>\n")),
            @r#"
Formal Zeit · in TIME ⇒ Zeit := 
Formal Auf · out BOOL ⇒ Auf := 
Message OM_Oben · in_out BOOL msg out ⇒ OM_Oben := 
Message IM_Ab · in_out BOOL msg in ⇒ IM_Ab := 
Formal ManualMode · in BOOL (predefined) ⇒ ManualMode := 
Formal AutomaticMode · in BOOL (predefined) ⇒ AutomaticMode := 
Formal UsrMsgQuit · in BOOL (predefined) ⇒ UsrMsgQuit :=
"#
        );
        // The formal being typed counts as not wired.
        let items = complete(&format!(
            "{GROUP}group G <\n  instance V : Ventil_2E <\n    Oben := Bohrer_Oben;\n    Ze$0\n  >\n>\n"
        ));
        assert_eq!(render(&items), "Formal Zeit · in TIME ⇒ Zeit := ");
    }

    #[test]
    fn incoming_messages_after_instance_dot() {
        let group = |tail: &str| {
            format!(
                "{GROUP}group G <\n  instance B : Bohren < >\n  instance V : Ventil_2E <\n    OM_Oben := {tail}\n  >\n>\n"
            )
        };
        insta::assert_snapshot!(check(&group("B.$0")), @r#"
Message IM_Oben · BOOL msg in of Bohren
Message IM_Start · BOOL msg in of Bohren
"#);
        insta::assert_snapshot!(check(&group("B.IM_S$0;")), @"Message IM_Start · BOOL msg in of Bohren");
        // The example of the brief: `Vorschub.` with nothing after it.
        let text = format!(
            "{GROUP}group G <\n  instance Vorschub : Ventil_2E < >\n  instance B : Bohren <\n    OM_Senken := Vorschub.$0\n  >\n>\n"
        );
        assert_eq!(
            render(&complete(&text)),
            "Message IM_Ab · BOOL msg in of Ventil_2E"
        );
    }

    #[test]
    fn actual_values() {
        let group = |tail: &str| {
            format!(
                "{GROUP}group G <\n  instance B : Bohren < >\n  instance V : Ventil_2E <\n    {tail}\n  >\n>\n"
            )
        };
        insta::assert_snapshot!(check(&group("OM_Oben := $0")), @r#"
Instance B · instance of Bohren ⇒ B.
Symbol Bohrer_Oben · E 0.0 BOOL
Symbol Wartezeit · MD 4 TIME
"#);
        insta::assert_snapshot!(check(&group("Zeit := $0")), @r#"
Symbol Wartezeit · MD 4 TIME
Symbol Bohrer_Oben · E 0.0 BOOL
"#);
    }

    const CHART: &str = r#"//- symbols.higraph
symbols < Freigabe : E 1.0; >
//- chart.higraph
chart Mischer <
  in < Fuellstand : REAL; Start : BOOL; >
  out < Heizung : BOOL; >
  sequencer RUN prio 1 <
    start < Freigabe; >
    step START < init < Heizung := FALSE; > >
    trans T1 < Fuellstand >= 80.0; >
    parallel <
      branch < step HEIZEN "heat" < N Heizung; > >
      branch < step RUEHREN < > >
    >
    trans T2 < Start; >
    step ENDE < >
"#;

    fn chart(tail: &str) -> String {
        format!("{CHART}{tail}\n  >\n>\n")
    }

    #[test]
    fn chart_members_and_properties() {
        insta::assert_snapshot!(check("chart C <\n  $0\n>"), @r#"
Keyword sequencer · a sequencer of steps and transitions
Keyword in · input parameters
Keyword out · output parameters
Keyword in_out · in/out parameters and messages
Keyword stat · static variables
Keyword mode · operating mode: auto or manual
Keyword switching · switching mode: T, B, T_or_B, T_and_B or step
Keyword run · run option: cyclic, time_monitoring or autostart
Keyword profile · the rules the chart follows: pcs7 or iec
Keyword action · an action with statements (IEC charts)
"#);
        insta::assert_snapshot!(check("chart C <\n  switching $0\n>"), @r#"
Value T · transitions switch
Value B · operator commands switch
Value T_or_B · transitions or operator commands
Value T_and_B · transitions and operator commands
Value step · step by step, with confirmation
"#);
        insta::assert_snapshot!(check("chart C <\n  run $0\n>"), @r#"
Value cyclic · cyclic operation
Value time_monitoring · monitor the step times
Value autostart · start automatically
"#);
        let mode = complete("chart C <\n  mode $0\n>");
        assert_eq!(labels(&mode, CompletionKind::Value), ["auto", "manual"]);
    }

    #[test]
    fn sequencer_elements_and_step_items() {
        insta::assert_snapshot!(check(&chart("    $0")), @r#"
Snippet step · step NAME < ... > ⇒ step ${1:NAME} <⏎  $0⏎>
Keyword trans · a transition between steps
Keyword parallel · parallel branches
Keyword alt · alternative branches
Keyword jump · a jump to a step of the sequencer
Keyword loop · a loop back to an earlier step
Keyword start · start condition of the sequencer
Keyword pre · statements before the steps, each cycle
Keyword post · statements after the steps, each cycle
"#);
        insta::assert_snapshot!(check(&chart("    step X < $0 >")), @r#"
Keyword init · statements of the first cycle
Keyword run · statements of each cycle
Keyword term · statements of the last cycle
Keyword N · non-stored: 1 while the step is active
Keyword S · set (stored)
Keyword R · reset
Keyword P · pulse: 1 for one cycle when the step becomes active
Keyword L · time limited: 1 for the given time (needs a time)
Keyword D · time delayed: 1 after the given time (needs a time)
Keyword SD · stored and time delayed (needs a time)
Keyword DS · delayed and stored (needs a time)
Keyword SL · stored and time limited (needs a time)
Keyword min · minimum step run time
Keyword max · maximum step run time
Keyword confirm · the operator confirms the step
"#);
        let branch = complete(&chart("    parallel < $0 >"));
        assert_eq!(
            render(&branch),
            "Keyword branch · a branch of the parallel or alternative"
        );
        let element = complete(&chart("    alt < branch < $0 > >"));
        assert_eq!(element[0].label, "step");
    }

    #[test]
    fn jump_targets_are_the_steps_of_the_sequencer() {
        insta::assert_snapshot!(check(&chart("    jump J1 -> $0")), @r#"
Step START
Step HEIZEN · "heat"
Step RUEHREN
Step ENDE
"#);
        let items = complete(&chart("    loop L1 -> HE$0 < >"));
        // `HE` is a subsequence of both names.
        assert_eq!(labels(&items, CompletionKind::Step), ["HEIZEN", "RUEHREN"]);
    }

    #[test]
    fn chart_conditions() {
        insta::assert_snapshot!(check(&chart("    trans T3 < $0 >")), @r#"
Variable Fuellstand · in REAL
Variable Start · in BOOL
Variable Heizung · out BOOL
Symbol Freigabe · E 1.0 BOOL
Keyword not · logical negation
Value TRUE · BOOL constant
Value FALSE · BOOL constant
"#);
        insta::assert_snapshot!(check(&chart("    trans T3 < Start and F$0 >")), @r#"
Variable Fuellstand · in REAL
Symbol Freigabe · E 1.0 BOOL
Value FALSE · BOOL constant
"#);
        insta::assert_snapshot!(check(&chart("    trans T3 < Start $0 >")), @r#"
Keyword and · logical AND
Keyword or · logical OR
Keyword xor · exclusive OR
"#);
        // `>` with nothing after it on the line closes the body for the parser; completion
        // still treats it as a comparison being typed.
        let compare = complete(&chart("    trans T3 < Fuellstand > $0\n    >"));
        assert_eq!(compare[0].label, "Fuellstand");
        let closed = complete(&chart("    trans T3 < Start; > $0"));
        assert_eq!(closed[0].label, "step");
        let assignment = complete(&chart("    step X < run < Heizung := $0 > >"));
        assert!(labels(&assignment, CompletionKind::Keyword).contains(&"not".to_owned()));
        let target = complete(&chart("    step X < run < $0 > >"));
        assert_eq!(
            labels(&target, CompletionKind::Variable),
            ["Fuellstand", "Start", "Heizung"]
        );
        assert!(labels(&target, CompletionKind::Keyword).is_empty());
        let qualifier = complete(&chart("    step X < N $0 >"));
        assert_eq!(labels(&qualifier, CompletionKind::Symbol), ["Freigabe"]);
    }

    #[test]
    fn chart_types_use_only_their_interface() {
        let items = complete(
            "//- s.higraph\nsymbols < Freigabe : E 1.0; >\n//- c.higraph\nchart type T < in < A : BOOL; > sequencer S < start < $0 > > >",
        );
        assert_eq!(render(&items[..1]), "Variable A · in BOOL");
        assert!(labels(&items, CompletionKind::Symbol).is_empty());
    }

    #[test]
    fn block_interface_sections() {
        let items = complete("block FC 1 <\n  $0\n>");
        assert_eq!(
            labels(&items, CompletionKind::Keyword),
            ["in", "out", "in_out", "stat"]
        );
    }

    /// Every feature of this module family at every offset of real files, and of every prefix
    /// of them (as if the file were being typed from the start): no panic, ranges in bounds.
    #[test]
    fn never_panics_while_typing() {
        let files = [
            (
                "bohrmaschine.higraph",
                include_str!("../../../../examples/drilling/bohrmaschine.higraph"),
            ),
            (
                "ventil_2e.higraph",
                include_str!("../../../../examples/drilling/graphs/ventil_2e.higraph"),
            ),
            (
                "symbols.higraph",
                include_str!("../../../../examples/drilling/symbols.higraph"),
            ),
            (
                "mixer.higraph",
                include_str!("../../../../examples/mixer/mixer.higraph"),
            ),
        ];
        let mut host = crate::AnalysisHost::new();
        host.load(crate::WorkspaceData {
            files: files
                .iter()
                .map(|(p, t)| ((*p).to_owned(), crate::FileContents::Text((*t).to_owned())))
                .collect(),
            ..crate::WorkspaceData::default()
        });
        let check_all = |host: &crate::AnalysisHost, path: &str, len: usize, step: usize| {
            let analysis = host.analysis();
            for offset in (0..=len).step_by(step) {
                let offset = higraph_syntax::TextSize::from(offset as u32);
                let position = super::FilePosition {
                    path: path.to_owned(),
                    offset,
                };
                for item in analysis.completions(&position).expect("not cancelled") {
                    assert!(usize::from(item.replace_range.end()) <= len);
                    assert!(item.replace_range.start() <= offset);
                }
            }
            for hint in analysis.inlay_hints(path, None).expect("not cancelled") {
                assert!(usize::from(hint.offset) <= len);
            }
            let _ = analysis.document_symbols(path).expect("not cancelled");
        };
        for (path, text) in files {
            check_all(&host, path, text.len(), 1);
            for cut in (0..text.len()).step_by(41) {
                let Some(prefix) = text.get(..cut) else {
                    continue;
                };
                host.set_file_contents(path, crate::FileContents::Text(prefix.to_owned()));
                check_all(&host, path, prefix.len(), 11);
            }
            host.set_file_contents(path, crate::FileContents::Text(text.to_owned()));
        }
        let _ = host
            .analysis()
            .workspace_symbols("a")
            .expect("not cancelled");
    }

    #[test]
    fn large_symbol_tables_are_filtered_by_the_typed_word() {
        let mut text = String::from("//- s.higraph\nsymbols <\n");
        for i in 0..2000 {
            text.push_str(&format!("  Sym_{i} : M {i}.0;\n"));
        }
        text.push_str(">\n//- g.higraph\ngraph G < state 0 < C: U Sym_199$0\n");
        let items = complete(&text);
        // Of 2000 symbols, those that contain `Sym_199` as a subsequence.
        let symbols = labels(&items, CompletionKind::Symbol);
        assert_eq!(symbols.len(), 29);
        assert_eq!(symbols[..3], ["Sym_199", "Sym_1099", "Sym_1199"]);
    }

    const IEC: &str = "chart Ampel <
  profile iec;
  stat < Uhr : TON; Teile : INT; Lampe : BOOL; >
  action Zaehlen < Teile := Teile + 1; >
  sequencer Haupt <
";

    fn iec(tail: &str) -> String {
        format!("{IEC}{tail}\n  >\n>\n")
    }

    #[test]
    fn function_block_members_after_the_dot() {
        insta::assert_snapshot!(check(&iec("    step Rot < >\n    trans Weiter < Uhr.$0 >\n    step Gruen < >")), @r#"
Formal IN · input BOOL
Formal PT · input TIME
Formal Q · output BOOL
Formal ET · output TIME
"#);
        // Steps as values in an IEC chart.
        let items = complete(&iec(
            "    step Rot < >\n    trans Weiter < Rot.$0 >\n    step Gruen < >",
        ));
        assert_eq!(labels(&items, CompletionKind::Value), ["X", "T"]);
        // Not in a PCS 7 chart, where `Rot.X` is an external reference.
        let pcs7 = "chart C <\n  sequencer S <\n    start < TRUE; >\n    step Rot < >\n    trans W < Rot.$0 >\n    step G < >\n  >\n>\n";
        assert!(complete(pcs7).is_empty());
    }

    #[test]
    fn function_block_formals_in_a_call() {
        insta::assert_snapshot!(check(&iec("    step Rot < run < Uhr(IN := TRUE, $0); > >")), @r#"
Formal PT · input TIME ⇒ PT := 
Formal Q · output BOOL ⇒ Q => 
Formal ET · output TIME ⇒ ET => 
"#);
    }

    #[test]
    fn actions_and_statements_in_iec_charts() {
        let items = complete(&iec("    step Rot < P1 $0 >"));
        assert!(labels(&items, CompletionKind::Variable).contains(&"Zaehlen".to_owned()));
        let items = complete(&iec("    step Rot < run < $0 > >"));
        let snippets = labels(&items, CompletionKind::Snippet);
        assert_eq!(snippets, ["IF", "CASE", "Uhr()"]);
        let items = complete(&iec("    step Rot < >\n    trans W < $0 >"));
        assert!(labels(&items, CompletionKind::Step).contains(&"Rot.X".to_owned()));
        // The instance's detail names its block.
        assert!(
            items
                .iter()
                .any(|i| i.label == "Uhr" && i.detail.as_deref() == Some("stat TON"))
        );
        insta::assert_snapshot!(check("chart C <\n  profile $0\n>"), @r#"
Value pcs7 · PCS 7 SFC rules (the default)
Value iec · IEC 61131-3 sequential function chart
"#);
    }
}
