//! Names: what the language accepts, renaming what it does not, uniqueness (letter case does
//! not matter, as in IEC 61131-3 and in the language).

use std::collections::{HashMap, HashSet};

/// Reserved in an IEC chart (`docs/iec.md` §2): the IEC keywords, the IEC type names and the
/// standard function blocks (S7 type names such as `TIMER` are not: `Timer : TON;` is the
/// usual IEC declaration). IEC tools do not accept them as names either, so a name from a
/// PLCopen file meets them only when the file is odd.
const RESERVED: &[&str] = &[
    "IF",
    "THEN",
    "ELSIF",
    "ELSE",
    "END_IF",
    "CASE",
    "OF",
    "END_CASE",
    "MOD",
    "AND",
    "OR",
    "XOR",
    "NOT",
    "TRUE",
    "FALSE",
    "BOOL",
    "BYTE",
    "WORD",
    "DWORD",
    "INT",
    "DINT",
    "REAL",
    "TIME",
    "DATE",
    "TIME_OF_DAY",
    "TOD",
    "DATE_AND_TIME",
    "DT",
    "STRING",
    "ARRAY",
    "STRUCT",
    "TON",
    "TOF",
    "TP",
    "R_TRIG",
    "F_TRIG",
    "CTU",
    "CTD",
    "CTUD",
    "SR",
    "RS",
];

/// Whether the language takes `name` as it is.
pub fn is_valid(name: &str) -> bool {
    let mut chars = name.chars();
    let Some(first) = chars.next() else {
        return false;
    };
    (first.is_ascii_alphabetic() || first == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !RESERVED.iter().any(|r| r.eq_ignore_ascii_case(name))
}

/// A name the language accepts, as close to `name` as possible: characters other than ASCII
/// letters, digits and `_` become `_`, a leading digit or a reserved word gets a prefix.
pub fn sanitize(name: &str, prefix: &str) -> String {
    let mut out: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    // No `__` and no trailing `_` (HG1101/HG1102).
    while out.contains("__") {
        out = out.replace("__", "_");
    }
    let trimmed = out.trim_end_matches('_');
    out = if trimmed.is_empty() && !out.is_empty() {
        prefix.to_owned()
    } else {
        trimmed.to_owned()
    };
    if out.is_empty() {
        return prefix.to_owned();
    }
    if !out.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        || RESERVED.iter().any(|r| r.eq_ignore_ascii_case(&out))
    {
        out = format!("{prefix}_{}", out.trim_start_matches('_'));
    }
    out
}

/// Names taken in one name space, compared without letter case.
#[derive(Debug, Default)]
pub struct NameSet {
    taken: HashSet<String>,
    /// The next suffix to try per base name, so that many equal names cost linear time.
    next: HashMap<String, usize>,
}

impl NameSet {
    pub fn insert(&mut self, name: &str) -> bool {
        self.taken.insert(name.to_ascii_uppercase())
    }

    /// `name`, or `name_2`, `name_3`, ... — the first that is free; taken.
    pub fn unique(&mut self, name: &str) -> String {
        if self.insert(name) {
            return name.to_owned();
        }
        let key = name.to_ascii_uppercase();
        let mut n = self.next.get(&key).copied().unwrap_or(2);
        loop {
            let candidate = format!("{name}_{n}");
            n += 1;
            if self.insert(&candidate) {
                self.next.insert(key, n);
                return candidate;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sanitizing() {
        assert!(is_valid("Schritt_mit_sehr_langem_Namen"));
        assert!(!is_valid("Step 1"));
        assert!(!is_valid("TON"));
        assert_eq!(sanitize("Step 1", "S"), "Step_1");
        assert_eq!(sanitize("1", "S"), "S_1");
        assert_eq!(sanitize("Tür", "S"), "T_r");
        assert_eq!(sanitize("", "S"), "S");
        assert_eq!(sanitize("__", "S"), "S");
        assert_eq!(sanitize("if", "V"), "V_if");
        let mut set = NameSet::default();
        assert_eq!(set.unique("A"), "A");
        assert_eq!(set.unique("a"), "a_2");
        assert_eq!(set.unique("A"), "A_3");
    }
}
