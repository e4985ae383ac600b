//! The one `SyntaxKind` enum: tokens produced by the lexer, contextual keywords the parser
//! remaps identifiers to, and the node kinds of the concrete syntax tree.

use logos::Logos;

/// Every kind of token and node in the HiGraph syntax tree.
///
/// The lexer is context-free and produces only the token kinds up to `LEX_ERROR`; keywords are
/// contextual, so the parser *remaps* an `IDENT` to a `*_KW` kind where the grammar uses it as
/// a keyword. Node kinds follow after `__LAST_TOKEN`.
#[derive(Logos, Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u16)]
#[allow(non_camel_case_types, clippy::upper_case_acronyms)]
pub enum SyntaxKind {
    // ---------------------------------------------------------------- trivia
    /// Spaces, tabs and line breaks (LF, CR LF, CR); also a leading byte-order mark.
    #[regex(r"[ \t\r\n]+")]
    WHITESPACE = 0,
    /// `// ...` to the end of the line.
    #[regex(r"//[^\r\n]*", allow_greedy = true)]
    COMMENT,

    // ---------------------------------------------------------------- words and literals
    /// A maximal run of letters, digits and `_` not starting with a digit.
    #[regex(r"[\p{L}_][\p{L}0-9_]*")]
    IDENT,
    /// Digits, optional fraction, optional exponent.
    #[regex(r"[0-9]+(\.[0-9]+)?([eE][+-]?[0-9]+)?")]
    NUMBER,
    /// An identifier or number immediately followed by `#` and a body: `B#16#FF`, `T#5S`,
    /// `B#(1, 2)`, `16#FF` (invalid, but one token).
    #[regex(r"[\p{L}_0-9][\p{L}0-9_]*#(\([^)\r\n]*\)?|[\p{L}0-9_.:#\-]*)")]
    TYPED_CONST,
    /// `"..."`; unclosed strings end at the line's end.
    #[regex(r#""[^"\r\n]*"?"#)]
    STRING,
    /// `'...'` character or string constant; `''` inside stands for one quote.
    #[regex(r"'([^'\r\n]|'')*'?")]
    CHAR,

    // ---------------------------------------------------------------- punctuation
    #[token("<")]
    L_ANGLE,
    #[token(">")]
    R_ANGLE,
    #[token(";")]
    SEMI,
    #[token(":")]
    COLON,
    #[token(",")]
    COMMA,
    #[token(".")]
    DOT,
    #[token("(")]
    L_PAREN,
    #[token(")")]
    R_PAREN,
    #[token("[")]
    L_BRACK,
    #[token("]")]
    R_BRACK,
    #[token("=")]
    EQ,
    #[token("-")]
    MINUS,
    #[token("+")]
    PLUS,
    #[token("*")]
    STAR,
    #[token("/")]
    SLASH,
    #[token("?")]
    QUESTION,
    #[token("!")]
    BANG,
    #[token("#")]
    HASH,
    /// A run of characters that cannot begin any token (HG0009).
    LEX_ERROR,

    // ---------------------------------------------------------------- contextual keywords
    MNEMONIC_KW,
    SIMATIC_KW,
    INTERNATIONAL_KW,
    GRAPH_KW,
    GROUP_KW,
    CHART_KW,
    SYMBOLS_KW,
    BLOCK_KW,
    IN_KW,
    OUT_KW,
    IN_OUT_KW,
    STAT_KW,
    MSG_KW,
    ACTIVATE_KW,
    PERMANENT_KW,
    STATE_KW,
    FAULT_KW,
    MESSAGE_KW,
    WAIT_KW,
    SUPERVISE_KW,
    TRANS_KW,
    ANY_KW,
    RETURN_KW,
    PRIO_KW,
    AUTO_KW,
    MANUAL_KW,
    WAITS_KW,
    FC_KW,
    DB_KW,
    OPTION_KW,
    INSTANCE_KW,
    TYPE_KW,
    MODE_KW,
    SWITCHING_KW,
    RUN_KW,
    SEQUENCER_KW,
    START_KW,
    PRE_KW,
    POST_KW,
    STEP_KW,
    INIT_KW,
    TERM_KW,
    MIN_KW,
    MAX_KW,
    CONFIRM_KW,
    PARALLEL_KW,
    ALT_KW,
    BRANCH_KW,
    JUMP_KW,
    LOOP_KW,
    TEST_KW,
    CYCLE_KW,
    SET_KW,
    UNTIL_KW,
    WITHIN_KW,
    EXPECT_KW,
    COMMAND_KW,
    RESTART_KW,
    COLD_KW,
    WARM_KW,
    PROFILE_KW,
    ACTION_KW,
    IF_KW,
    THEN_KW,
    ELSIF_KW,
    ELSE_KW,
    END_IF_KW,
    CASE_KW,
    OF_KW,
    END_CASE_KW,
    MOD_KW,
    AND_KW,
    OR_KW,
    XOR_KW,
    NOT_KW,
    #[doc(hidden)]
    __LAST_TOKEN,

    // ---------------------------------------------------------------- nodes
    SOURCE_FILE,
    /// Text the parser could not fit into the grammar (an HG0001 recovery, a stray `>`).
    ERROR,
    /// `mnemonic simatic;`
    MNEMONIC,
    /// `graph NAME ["comment"] < ... >`
    GRAPH,
    /// `< ... >` of any item, member or step part.
    BODY,
    /// A declared name (the NAME or STRING token that introduces something).
    NAME,
    /// A name used to refer to something declared elsewhere.
    NAME_REF,
    /// A display name or comment string after a header.
    COMMENT_STRING,
    /// `in < ... >`, `out`, `in_out`, `stat`.
    VAR_SECTION,
    /// `Oben : BOOL msg in := TRUE "comment";`
    VAR_DECL,
    /// `BOOL`, `STRING[20]`.
    TYPE_REF,
    /// `msg in` / `msg out`.
    MSG_KIND,
    /// `:= constant` of a declaration.
    INITIAL_VALUE,
    /// `activate CurrentState, StateChange;`
    ACTIVATE,
    /// `permanent < C-: ... C: ... >`
    PERMANENT,
    /// `state N ["name"] {fault|message} < ... >`
    STATE,
    /// `fault`, `message`, `auto`, `manual`, `waits` after a header.
    ATTRIBUTE,
    /// `trans A->B {clause} < ... >`
    TRANS,
    /// `4`, `any` or `return` in a transition header.
    ENDPOINT,
    /// `prio N`.
    PRIO_CLAUSE,
    /// `->`, joined from `-` and `>`.
    ARROW,
    /// `:=`, joined from `:` and `=`.
    ASSIGN_OP,
    /// A labelled run of statements (`C: S x; R y;`), or the unlabelled statements before the
    /// first label.
    BLOCK,
    /// `E:` `C-:` `C:` `X:` `?:` `!:`.
    LABEL,
    /// `wait time_value;`
    WAIT_ITEM,
    /// `supervise time_value;`
    SUPERVISE_ITEM,
    /// One STL instruction up to and including its `;`.
    STL_STMT,
    /// `NAME:` at the start of an STL statement that is not a block label (HG4003).
    JUMP_LABEL,
    /// The operation of an STL statement (`U`, `U(`, `)`, `==I`, `RND+`, ...).
    OPCODE,
    /// An absolute address: `E 1.0`, `MW10`, `DB10.DBX 5.1`, `T 5`, `FC 10`.
    ADDRESS,
    /// `#Name` — an explicit graph variable.
    VAR_REF,
    /// `"Name"` in operand position — a global symbol.
    SYMBOL_REF,
    /// A constant: number (with a joined `-`), typed constant, `'c'`, `TRUE`, `FALSE`.
    LITERAL,
    /// `[ ... ]` in operand position — indirect addressing (HG4004).
    INDIRECT,
    /// `==0`, `<>0`, `>0`, ... in operand position (HG4003).
    STATUS_OPERAND,
    /// `FC 10, DB 10 ( P := x, ... )` after CALL / CC.
    CALL_ARGS,
    /// `FC 10`, `FB20`, `"Dosieren"`, `Name`: a block named in CALL, `block`, `fc`/`db`.
    BLOCK_REF,
    /// `( P := x, ... )`.
    PARAM_LIST,
    /// `P := x`.
    PARAM,
    /// `group NAME [fc ..] [db ..] ["comment"] < ... >`
    GROUP,
    /// `fc block_name`.
    FC_CLAUSE,
    /// `db block_name`.
    DB_CLAUSE,
    /// `option NAME [INT];`
    OPTION,
    /// `instance NAME : GRAPH ["comment"] < ... >`
    INSTANCE,
    /// `Formal := value;`
    ACTUAL,
    /// `Inst.Msg` as the value of an actual.
    MESSAGE_TARGET,
    /// `symbols < ... >`
    SYMBOLS,
    /// `Name : address [type] ["comment"];`
    SYMBOL,
    /// `block block_ref ["comment"] < var sections >`
    BLOCK_INTERFACE,
    /// `chart [type] NAME ["comment"] < ... >`
    CHART,
    /// `mode auto;`, `switching T;`, `run cyclic;`, `profile iec;`.
    CHART_PROP,
    /// `action NAME ["comment"] < statements >` in a chart.
    CHART_ACTION,
    /// `sequencer NAME [prio N] < ... >`
    SEQUENCER,
    /// `start < conditions >`
    START_PART,
    /// `pre < statements >` / `post < statements >`
    PRE_PART,
    POST_PART,
    /// `step NAME ["comment"] < ... >`
    STEP,
    /// `init < ... >`, `run < ... >`, `term < ... >`
    STEP_PHASE,
    /// `N Valve;`, `L Pump, T#5S;`
    QUALIFIER_ACTION,
    /// `N`, `S`, `SD`, ...
    QUALIFIER,
    /// `min T#1S;` / `max T#10M;`
    STEP_TIME,
    /// `confirm;`
    CONFIRM,
    /// `trans NAME ["comment"] < conditions >` in a sequencer.
    CHART_TRANS,
    /// `parallel < branch ... >`
    PARALLEL,
    /// `alt < branch ... >`
    ALT,
    /// `branch < elements >`
    BRANCH,
    /// `jump NAME -> TARGET ["comment"] < conditions >`
    JUMP,
    /// `loop NAME -> TARGET ["comment"] < conditions >`
    LOOP,
    /// `expr;` in a start part, transition, jump or loop.
    CONDITION,
    /// `path := expr;` in a step phase, pre or post.
    ASSIGNMENT,
    /// `IF c THEN stmts {ELSIF ..} [ELSE ..] END_IF;`
    IF_STMT,
    /// `ELSIF c THEN stmts` of an `IF`.
    ELSIF_CLAUSE,
    /// `ELSE stmts` of an `IF` or a `CASE`.
    ELSE_CLAUSE,
    /// `CASE e OF arms [ELSE ..] END_CASE;`
    CASE_STMT,
    /// `1, 3..5: stmts` of a `CASE`.
    CASE_ARM,
    /// `3`, `-1`, `3..5` of a case arm.
    CASE_LABEL,
    /// `Timer(IN := x, Q => y);`
    FB_CALL,
    /// `IN := x` or `Q => y` of a call.
    FB_ARG,
    /// `=>`, joined from `=` and `>`, of an output argument.
    OUTPUT_OP,
    /// `a and b`, `x >= 5.0`, `a + b`, `a MOD b`.
    BIN_EXPR,
    /// `not a`, `-a`.
    PREFIX_EXPR,
    /// `( expr )`.
    PAREN_EXPR,
    /// `NAME { . NAME }`, `"symbol"` or an address in a chart.
    PATH,
    /// A chart operator spelled with two tokens: `<>`, `<=`, `>=`.
    COMPARE_OP,
    /// `test NAME ["description"] < statements >`
    TEST,
    /// `cycle T#10MS;`
    TEST_CYCLE,
    /// `run G, C;`
    TEST_RUN,
    /// `set path := expr;`
    TEST_SET,
    /// `step;` / `step N;`
    TEST_STEP,
    /// `wait T#1S;`
    TEST_WAIT,
    /// `until expr within T#1S ["message"];`
    TEST_UNTIL,
    /// `within T#1S` of an `until`.
    WITHIN_CLAUSE,
    /// `expect expr ["message"];`
    TEST_EXPECT,
    /// `command Chart start;`
    TEST_COMMAND,
    /// `confirm Chart.Step;`
    TEST_CONFIRM,
    /// `restart cold;` / `restart warm;`
    TEST_RESTART,
    /// A path in a test: `(NAME | "symbol") { . NAME }` or an address.
    TEST_PATH,
    #[doc(hidden)]
    __LAST,
}

use SyntaxKind::*;

impl SyntaxKind {
    /// White space and comments.
    pub fn is_trivia(self) -> bool {
        matches!(self, WHITESPACE | COMMENT)
    }

    /// Token kinds (as opposed to node kinds).
    pub fn is_token(self) -> bool {
        (self as u16) < (__LAST_TOKEN as u16)
    }

    /// Contextual keywords.
    pub fn is_keyword(self) -> bool {
        (MNEMONIC_KW as u16..=NOT_KW as u16).contains(&(self as u16))
    }

    /// Every contextual keyword with its spelling in lower case, in the order of the enum.
    pub const KEYWORDS: [(&'static str, SyntaxKind); 75] = [
        ("mnemonic", MNEMONIC_KW),
        ("simatic", SIMATIC_KW),
        ("international", INTERNATIONAL_KW),
        ("graph", GRAPH_KW),
        ("group", GROUP_KW),
        ("chart", CHART_KW),
        ("symbols", SYMBOLS_KW),
        ("block", BLOCK_KW),
        ("in", IN_KW),
        ("out", OUT_KW),
        ("in_out", IN_OUT_KW),
        ("stat", STAT_KW),
        ("msg", MSG_KW),
        ("activate", ACTIVATE_KW),
        ("permanent", PERMANENT_KW),
        ("state", STATE_KW),
        ("fault", FAULT_KW),
        ("message", MESSAGE_KW),
        ("wait", WAIT_KW),
        ("supervise", SUPERVISE_KW),
        ("trans", TRANS_KW),
        ("any", ANY_KW),
        ("return", RETURN_KW),
        ("prio", PRIO_KW),
        ("auto", AUTO_KW),
        ("manual", MANUAL_KW),
        ("waits", WAITS_KW),
        ("fc", FC_KW),
        ("db", DB_KW),
        ("option", OPTION_KW),
        ("instance", INSTANCE_KW),
        ("type", TYPE_KW),
        ("mode", MODE_KW),
        ("switching", SWITCHING_KW),
        ("run", RUN_KW),
        ("sequencer", SEQUENCER_KW),
        ("start", START_KW),
        ("pre", PRE_KW),
        ("post", POST_KW),
        ("step", STEP_KW),
        ("init", INIT_KW),
        ("term", TERM_KW),
        ("min", MIN_KW),
        ("max", MAX_KW),
        ("confirm", CONFIRM_KW),
        ("parallel", PARALLEL_KW),
        ("alt", ALT_KW),
        ("branch", BRANCH_KW),
        ("jump", JUMP_KW),
        ("loop", LOOP_KW),
        ("test", TEST_KW),
        ("cycle", CYCLE_KW),
        ("set", SET_KW),
        ("until", UNTIL_KW),
        ("within", WITHIN_KW),
        ("expect", EXPECT_KW),
        ("command", COMMAND_KW),
        ("restart", RESTART_KW),
        ("cold", COLD_KW),
        ("warm", WARM_KW),
        ("profile", PROFILE_KW),
        ("action", ACTION_KW),
        ("if", IF_KW),
        ("then", THEN_KW),
        ("elsif", ELSIF_KW),
        ("else", ELSE_KW),
        ("end_if", END_IF_KW),
        ("case", CASE_KW),
        ("of", OF_KW),
        ("end_case", END_CASE_KW),
        ("mod", MOD_KW),
        ("and", AND_KW),
        ("or", OR_KW),
        ("xor", XOR_KW),
        ("not", NOT_KW),
    ];

    /// The keyword kind for a (case-insensitive) word, if the word is a keyword somewhere.
    ///
    /// The parser asks this for every identifier, so the candidates are found by length and
    /// first letter before any text is compared.
    pub fn from_keyword(word: &str) -> Option<SyntaxKind> {
        let &first = word.as_bytes().first()?;
        let candidates: &[(&str, SyntaxKind)] = match (word.len(), first.to_ascii_lowercase()) {
            (2, b'd') => &[("db", DB_KW)],
            (2, b'f') => &[("fc", FC_KW)],
            (2, b'i') => &[("in", IN_KW), ("if", IF_KW)],
            (2, b'o') => &[("or", OR_KW), ("of", OF_KW)],
            (3, b'a') => &[("any", ANY_KW), ("alt", ALT_KW), ("and", AND_KW)],
            (3, b'm') => &[
                ("msg", MSG_KW),
                ("min", MIN_KW),
                ("max", MAX_KW),
                ("mod", MOD_KW),
            ],
            (3, b'n') => &[("not", NOT_KW)],
            (3, b'o') => &[("out", OUT_KW)],
            (3, b'p') => &[("pre", PRE_KW)],
            (3, b'r') => &[("run", RUN_KW)],
            (3, b's') => &[("set", SET_KW)],
            (3, b'x') => &[("xor", XOR_KW)],
            (4, b'a') => &[("auto", AUTO_KW)],
            (4, b'c') => &[("cold", COLD_KW), ("case", CASE_KW)],
            (4, b'e') => &[("else", ELSE_KW)],
            (4, b'i') => &[("init", INIT_KW)],
            (4, b'j') => &[("jump", JUMP_KW)],
            (4, b'l') => &[("loop", LOOP_KW)],
            (4, b'm') => &[("mode", MODE_KW)],
            (4, b'p') => &[("prio", PRIO_KW), ("post", POST_KW)],
            (4, b's') => &[("stat", STAT_KW), ("step", STEP_KW)],
            (4, b't') => &[
                ("type", TYPE_KW),
                ("term", TERM_KW),
                ("test", TEST_KW),
                ("then", THEN_KW),
            ],
            (4, b'w') => &[("wait", WAIT_KW), ("warm", WARM_KW)],
            (5, b'b') => &[("block", BLOCK_KW)],
            (5, b'c') => &[("chart", CHART_KW), ("cycle", CYCLE_KW)],
            (5, b'e') => &[("elsif", ELSIF_KW)],
            (5, b'f') => &[("fault", FAULT_KW)],
            (5, b'g') => &[("graph", GRAPH_KW), ("group", GROUP_KW)],
            (5, b's') => &[("state", STATE_KW), ("start", START_KW)],
            (5, b't') => &[("trans", TRANS_KW)],
            (5, b'u') => &[("until", UNTIL_KW)],
            (5, b'w') => &[("waits", WAITS_KW)],
            (6, b'a') => &[("action", ACTION_KW)],
            (6, b'b') => &[("branch", BRANCH_KW)],
            (6, b'e') => &[("expect", EXPECT_KW), ("end_if", END_IF_KW)],
            (6, b'i') => &[("in_out", IN_OUT_KW)],
            (6, b'm') => &[("manual", MANUAL_KW)],
            (6, b'o') => &[("option", OPTION_KW)],
            (6, b'r') => &[("return", RETURN_KW)],
            (6, b'w') => &[("within", WITHIN_KW)],
            (7, b'c') => &[("confirm", CONFIRM_KW), ("command", COMMAND_KW)],
            (7, b'm') => &[("message", MESSAGE_KW)],
            (7, b'p') => &[("profile", PROFILE_KW)],
            (7, b'r') => &[("restart", RESTART_KW)],
            (7, b's') => &[("simatic", SIMATIC_KW), ("symbols", SYMBOLS_KW)],
            (8, b'a') => &[("activate", ACTIVATE_KW)],
            (8, b'e') => &[("end_case", END_CASE_KW)],
            (8, b'i') => &[("instance", INSTANCE_KW)],
            (8, b'm') => &[("mnemonic", MNEMONIC_KW)],
            (8, b'p') => &[("parallel", PARALLEL_KW)],
            (9, b'p') => &[("permanent", PERMANENT_KW)],
            (9, b's') => &[
                ("supervise", SUPERVISE_KW),
                ("switching", SWITCHING_KW),
                ("sequencer", SEQUENCER_KW),
            ],
            (13, b'i') => &[("international", INTERNATIONAL_KW)],
            _ => return None,
        };
        candidates
            .iter()
            .find(|(keyword, _)| keyword.eq_ignore_ascii_case(word))
            .map(|&(_, kind)| kind)
    }
}

impl From<SyntaxKind> for rowan::SyntaxKind {
    fn from(kind: SyntaxKind) -> Self {
        Self(kind as u16)
    }
}

/// The rowan language tag of HiGraph trees.
#[derive(Debug, Copy, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum HiGraphLanguage {}

impl rowan::Language for HiGraphLanguage {
    type Kind = SyntaxKind;

    fn kind_from_raw(raw: rowan::SyntaxKind) -> SyntaxKind {
        assert!(raw.0 < __LAST as u16, "invalid SyntaxKind {}", raw.0);
        // SAFETY: `SyntaxKind` is `repr(u16)` and `raw.0` was checked to be in range.
        unsafe { std::mem::transmute::<u16, SyntaxKind>(raw.0) }
    }

    fn kind_to_raw(kind: SyntaxKind) -> rowan::SyntaxKind {
        kind.into()
    }
}

pub type SyntaxNode = rowan::SyntaxNode<HiGraphLanguage>;
pub type SyntaxToken = rowan::SyntaxToken<HiGraphLanguage>;
pub type SyntaxElement = rowan::SyntaxElement<HiGraphLanguage>;

#[cfg(test)]
mod tests {
    use super::SyntaxKind::{self, *};

    /// `KEYWORDS` lists every keyword kind once, and `from_keyword` reads each spelling (in
    /// any case) as its kind.
    #[test]
    fn keyword_table_is_complete() {
        let count = NOT_KW as u16 - MNEMONIC_KW as u16 + 1;
        assert_eq!(SyntaxKind::KEYWORDS.len(), usize::from(count));
        for (i, &(text, kind)) in SyntaxKind::KEYWORDS.iter().enumerate() {
            assert_eq!(kind as u16, MNEMONIC_KW as u16 + i as u16, "{text}");
            assert!(kind.is_keyword());
            assert_eq!(SyntaxKind::from_keyword(text), Some(kind));
            assert_eq!(SyntaxKind::from_keyword(&text.to_uppercase()), Some(kind));
        }
    }
}
