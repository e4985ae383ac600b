//! Graph groups: instances with their actual parameters (`language.md` §4).

use std::fmt::Write;

/// One `instance Name : Graph < actuals >`.
#[derive(Debug, Clone)]
pub(crate) struct Instance {
    pub(crate) name: String,
    pub(crate) graph: String,
    pub(crate) comment: Option<String>,
    /// `(formal, actual)` as written.
    pub(crate) actuals: Vec<(String, String)>,
}

/// One `group`.
#[derive(Debug, Clone)]
pub(crate) struct Group {
    pub(crate) name: String,
    /// As written after `fc` / `db`: `FC 1`, `GG_Bereich_01`.
    pub(crate) fc: String,
    pub(crate) db: String,
    pub(crate) comment: Option<String>,
    /// Option lines without `option` and `;`: `cyclic_rlo0`, `reserve 100`.
    pub(crate) options: Vec<String>,
    pub(crate) instances: Vec<Instance>,
}

impl Group {
    /// The group's text in the canonical layout (`:=` aligned per instance).
    pub(crate) fn render(&self) -> String {
        let mut out = String::with_capacity(40 * 16 * self.instances.len() + 256);
        write!(out, "group {} fc {} db {}", self.name, self.fc, self.db).unwrap();
        if let Some(c) = &self.comment {
            write!(out, " \"{c}\"").unwrap();
        }
        out.push_str(" <\n");
        for o in &self.options {
            writeln!(out, "  option {o};").unwrap();
        }
        for inst in &self.instances {
            out.push('\n');
            write!(out, "  instance {} : {}", inst.name, inst.graph).unwrap();
            if let Some(c) = &inst.comment {
                write!(out, " \"{c}\"").unwrap();
            }
            out.push_str(" <\n");
            let width = inst.actuals.iter().map(|(f, _)| f.len()).max().unwrap_or(0);
            for (formal, actual) in &inst.actuals {
                writeln!(out, "    {formal:width$} := {actual};").unwrap();
            }
            out.push_str("  >\n");
        }
        out.push_str(">\n");
        out
    }
}
