//! PLCopen TC6 XML 2.01 sequential function charts to chart text of the `iec` profile
//! (`docs/iec.md` §8).
//!
//! [`import`] takes the text of a PLCopen document (the neutral format, CODESYS exports with
//! `<xhtml xmlns=...>` bodies and `addData`, Beremiz exports with `<xhtml:p><![CDATA[...]]>`;
//! namespaces are ignored, elements are matched by local name) and returns one chart text per
//! program or function block whose body is SFC, and the problems found on the way. No I/O:
//! the command line reads the file, formats the texts and writes them.
//!
//! * `xml.rs` — small helpers over `roxmltree` (children by local name, text of ST bodies,
//!   line numbers).
//! * `pou.rs` — one POU: its variables, named actions and transitions, and its SFC network,
//!   turned from a graph of `localId` connections into the language's nested sequence
//!   (steps, transitions, `alt`/`parallel` branches, `jump`s) and written as text.
//! * `st.rs` — structured text to the language's statements and expressions.
//!
//! Robustness: nothing panics on input; malformed XML is an [`Error`]; everything the
//! language cannot express is a [`Problem`] and the rest imports. Every walk is a loop or
//! bounded recursion ([`st::MAX_DEPTH`], [`pou::MAX_BRANCH_DEPTH`]); every SFC element is
//! visited at most once, so the cost is linear in the document.

mod names;
mod network;
mod pou;
pub mod st;
mod xml;

use std::fmt;

/// One chart made from one POU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Chart {
    /// The POU's name in the document.
    pub pou: String,
    /// The chart's name (the POU's name, renamed only if the language cannot accept it).
    pub name: String,
    /// The chart text (canonical layout as far as this crate can tell; the command line runs
    /// the formatter over it).
    pub text: String,
}

/// Something that could not be imported as it is: the rest of the POU still imports.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// 1-based line of the XML element.
    pub line: usize,
    /// The POU it belongs to.
    pub pou: Option<String>,
    /// The element: `step Gruen`, `transition T3`, `action Zaehlen`, `variable X`, ...
    pub element: Option<String>,
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.pou, &self.element) {
            (Some(p), Some(e)) => write!(f, "POU {p}, {e}: {}", self.message),
            (Some(p), None) => write!(f, "POU {p}: {}", self.message),
            (None, Some(e)) => write!(f, "{e}: {}", self.message),
            (None, None) => f.write_str(&self.message),
        }
    }
}

/// The result of [`import`].
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Import {
    pub charts: Vec<Chart>,
    /// In document order.
    pub problems: Vec<Problem>,
    /// Names of the POUs that have no SFC body (not imported, not a problem).
    pub skipped: Vec<String>,
}

/// Why a document could not be read at all.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Error {
    /// Not well-formed XML (1-based line and column).
    Xml {
        line: u32,
        column: u32,
        message: String,
    },
    /// Well-formed, but not a PLCopen project.
    NotPlcopen(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Xml {
                line,
                column,
                message,
            } => write!(f, "invalid XML at {line}:{column}: {message}"),
            Error::NotPlcopen(message) => write!(f, "not a PLCopen project: {message}"),
        }
    }
}

impl std::error::Error for Error {}

/// Converts a PLCopen document into chart texts.
pub fn import(text: &str) -> Result<Import, Error> {
    let options = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..roxmltree::ParsingOptions::default()
    };
    let doc = roxmltree::Document::parse_with_options(text, options).map_err(|e| {
        let mut pos = e.pos();
        if matches!(e, roxmltree::Error::UnexpectedEndOfStream) {
            // roxmltree has no position for it: the end of the text.
            let lines = xml::Lines::new(text);
            let line = lines.line(text.len());
            let start = text.rfind('\n').map_or(0, |i| i + 1);
            pos = roxmltree::TextPos::new(line as u32, (text.len() - start) as u32 + 1);
        }
        Error::Xml {
            line: pos.row,
            column: pos.col,
            message: e.to_string(),
        }
    })?;
    let root = doc.root_element();
    if root.tag_name().name() != "project" {
        return Err(Error::NotPlcopen(format!(
            "the root element is <{}>, not <project>",
            root.tag_name().name()
        )));
    }
    let lines = xml::Lines::new(text);
    let mut out = Import::default();
    let mut chart_names = names::NameSet::default();
    let globals = pou::constant_globals(&doc);
    // POUs anywhere in the document: CODESYS keeps the POUs of an application inside the
    // resource's addData.
    for node in doc.descendants() {
        if !node.is_element() || node.tag_name().name() != "pou" {
            continue;
        }
        pou::import_pou(node, &globals, &lines, &mut chart_names, &mut out);
    }
    // In the order of the file (stable: problems of one line keep their order).
    out.problems.sort_by_key(|p| p.line);
    if out.charts.is_empty() && out.problems.is_empty() {
        out.problems.push(Problem {
            line: lines.line(root.range().start),
            pou: None,
            element: None,
            message: "the document has no program or function block with an SFC body".into(),
        });
    }
    Ok(out)
}
