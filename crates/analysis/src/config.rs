//! The workspace configuration `higraph.toml` (`tooling.md` §3): parsed from text (no I/O),
//! with every problem reported as HG6101 on the offending key or value. Problems never stop
//! the analysis: the defaults apply.

use std::collections::BTreeMap;

use higraph_syntax::{TextRange, TextSize};
use toml::de::{DeTable, DeValue};

use crate::{FileContents, Severity, lang::Mnemonic, registry};

/// A configured severity: a level, or `off`.
pub type Level = Option<Severity>;

/// The parsed configuration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Config {
    pub include: Vec<String>,
    pub exclude: Vec<String>,
    pub mnemonic: Mnemonic,
    /// Symbol tables to import, as written, with the range of each entry.
    pub symbols: Vec<(String, TextRange)>,
    /// Per-code severity overrides (`None` = off).
    pub severities: BTreeMap<String, Level>,
    /// HG6101 problems: range in `higraph.toml` and the problem text.
    pub problems: Vec<(TextRange, String)>,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            include: vec!["**/*.higraph".to_owned()],
            exclude: Vec::new(),
            mnemonic: Mnemonic::Simatic,
            symbols: Vec::new(),
            severities: BTreeMap::new(),
            problems: Vec::new(),
        }
    }
}

fn range(span: std::ops::Range<usize>) -> TextRange {
    let size = |n: usize| TextSize::from(u32::try_from(n).unwrap_or(u32::MAX));
    TextRange::new(size(span.start), size(span.end.max(span.start)))
}

impl Config {
    /// The configuration of `higraph.toml`'s contents: parsed if they are text; the defaults
    /// with the problem otherwise.
    pub fn of_contents(contents: &FileContents) -> Config {
        let problem = match contents {
            FileContents::Text(text) => return Config::parse(text),
            FileContents::NotUtf8 {
                invalid_offset,
                invalid_len,
                ..
            } => {
                // In the text the analysis sees, each invalid byte is one U+FFFD.
                let end = invalid_offset + invalid_len * char::REPLACEMENT_CHARACTER.len_utf8();
                (
                    range(*invalid_offset..end),
                    format!("file is not valid UTF-8 (invalid byte at offset {invalid_offset})"),
                )
            }
            FileContents::Unreadable { reason } => {
                (range(0..0), format!("cannot read file: {reason}"))
            }
        };
        Config {
            problems: vec![problem],
            ..Config::default()
        }
    }

    /// Parses `higraph.toml`.
    pub fn parse(text: &str) -> Config {
        let mut config = Config::default();
        let table = match DeTable::parse(text) {
            Ok(table) => table,
            Err(error) => {
                let span = error.span().unwrap_or(0..0);
                let message = error
                    .message()
                    .lines()
                    .next()
                    .unwrap_or("invalid TOML")
                    .to_owned();
                config
                    .problems
                    .push((range(span), format!("TOML syntax error: {message}")));
                return config;
            }
        };
        for (key, value) in table.get_ref() {
            match key.get_ref().as_ref() {
                "workspace" => config.workspace(value),
                "diagnostics" => config.diagnostics(value),
                other => config
                    .problems
                    .push((range(key.span()), format!("unknown section '{other}'"))),
            }
        }
        config
    }

    /// Drops the `symbols` entries the reader refused (a table outside the workspace),
    /// reporting each problem on its entry (HG6101).
    pub fn refuse_symbols(&mut self, refused: &std::collections::HashMap<String, String>) {
        if refused.is_empty() {
            return;
        }
        let problems = &mut self.problems;
        self.symbols.retain(|(path, at)| match refused.get(path) {
            Some(problem) => {
                problems.push((*at, problem.clone()));
                false
            }
            None => true,
        });
    }

    /// The severity of `code` after overrides; `None` if the rule is off.
    pub fn severity(&self, code: &str) -> Level {
        if let Some(level) = self.severities.get(code)
            && !is_fixed(code)
        {
            return *level;
        }
        let rule = registry::rule_of(code)?;
        (!rule.off_by_default).then_some(rule.default_severity)
    }

    fn workspace(&mut self, value: &toml::Spanned<DeValue<'_>>) {
        let DeValue::Table(table) = value.get_ref() else {
            self.problems.push((
                range(value.span()),
                "'workspace' must be a table".to_owned(),
            ));
            return;
        };
        for (key, value) in table {
            let name = key.get_ref().as_ref();
            match name {
                "include" | "exclude" | "symbols" => match string_array(value) {
                    Some(list) => match name {
                        "include" => {
                            if let Some(globs) = self.globs(name, list) {
                                self.include = globs;
                            }
                        }
                        "exclude" => {
                            if let Some(globs) = self.globs(name, list) {
                                self.exclude = globs;
                            }
                        }
                        _ => {
                            self.symbols = list
                                .into_iter()
                                .map(|(path, at)| (normalise_path(&path), at))
                                .collect();
                        }
                    },
                    None => self.problems.push((
                        range(value.span()),
                        format!("'workspace.{name}' must be an array of strings"),
                    )),
                },
                "mnemonic" => match value.get_ref() {
                    DeValue::String(s) if Mnemonic::parse(s).is_some() => {
                        self.mnemonic = Mnemonic::parse(s).unwrap_or_default();
                    }
                    _ => self.problems.push((
                        range(value.span()),
                        "'workspace.mnemonic' must be \"simatic\" or \"international\"".to_owned(),
                    )),
                },
                other => self.problems.push((
                    range(key.span()),
                    format!("unknown key 'workspace.{other}'"),
                )),
            }
        }
    }

    /// The patterns of `include` or `exclude`, if every one is a valid glob; otherwise each
    /// invalid one is a problem and the key keeps its default.
    fn globs(&mut self, key: &str, list: Vec<(String, TextRange)>) -> Option<Vec<String>> {
        let mut valid = true;
        for (pattern, at) in &list {
            if let Err(error) = globset::Glob::new(pattern) {
                valid = false;
                // The kind alone: `globset`'s whole message repeats the pattern.
                let reason = error.kind().to_string();
                self.problems.push((
                    *at,
                    format!("invalid glob pattern '{pattern}' in 'workspace.{key}': {reason}"),
                ));
            }
        }
        valid.then(|| list.into_iter().map(|(pattern, _)| pattern).collect())
    }

    fn diagnostics(&mut self, value: &toml::Spanned<DeValue<'_>>) {
        let DeValue::Table(table) = value.get_ref() else {
            self.problems.push((
                range(value.span()),
                "'diagnostics' must be a table".to_owned(),
            ));
            return;
        };
        for (key, value) in table {
            let code = key.get_ref().as_ref();
            if registry::rule_of(code).is_none() {
                self.problems.push((
                    range(key.span()),
                    format!("unknown diagnostic code '{code}'"),
                ));
                continue;
            }
            if registry::is_syntax_code(code) {
                self.problems.push((
                    range(key.span()),
                    format!("{code} is a syntax error and its severity cannot be changed"),
                ));
                continue;
            }
            if code == CONFIG_PROBLEM {
                self.problems.push((
                    range(key.span()),
                    format!(
                        "{code} reports the problems of this file and its severity cannot be changed"
                    ),
                ));
                continue;
            }
            let level = match value.get_ref() {
                DeValue::String(s) => match s.as_ref() {
                    "error" => Some(Some(Severity::Error)),
                    "warning" => Some(Some(Severity::Warning)),
                    "info" => Some(Some(Severity::Info)),
                    "hint" => Some(Some(Severity::Hint)),
                    "off" => Some(None),
                    _ => None,
                },
                _ => None,
            };
            match level {
                Some(level) => {
                    self.severities.insert(code.to_owned(), level);
                }
                None => self.problems.push((
                    range(value.span()),
                    format!(
                        "invalid severity for {code}; use \"error\", \"warning\", \"info\", \"hint\" or \"off\""
                    ),
                )),
            }
        }
    }
}

/// The code of the configuration's own problems: it cannot be turned off or down, so a
/// broken `higraph.toml` is never silent.
const CONFIG_PROBLEM: &str = "HG6101";

/// Codes whose severity the configuration cannot change: the syntax errors and HG6101.
fn is_fixed(code: &str) -> bool {
    registry::is_syntax_code(code) || code == CONFIG_PROBLEM
}

/// A workspace-relative path as output names files (`diagnostics.md` §4.1): `/`
/// separators, no `.` segments, `x/..` folded away (`plc/../plc/a.sdf` is `plc/a.sdf`).
/// Leading `..` segments (a file outside the workspace) are kept.
fn normalise_path(path: &str) -> String {
    let mut segments: Vec<&str> = Vec::new();
    for segment in path.split(['/', '\\']) {
        match segment {
            "" | "." => {}
            ".." if segments.last().is_some_and(|last| *last != "..") => {
                segments.pop();
            }
            _ => segments.push(segment),
        }
    }
    let joined = segments.join("/");
    if path.starts_with('/') {
        format!("/{joined}")
    } else {
        joined
    }
}

fn string_array(value: &toml::Spanned<DeValue<'_>>) -> Option<Vec<(String, TextRange)>> {
    let DeValue::Array(items) = value.get_ref() else {
        return None;
    };
    items
        .iter()
        .map(|item| match item.get_ref() {
            DeValue::String(s) => Some((s.to_string(), range(item.span()))),
            _ => None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_settings_and_reports_problems() {
        let text = "[workspace]\nmnemonic = \"international\"\nsymbols = [\"a.sdf\"]\nfoo = 1\n\n\
                    [diagnostics]\nHG2105 = \"off\"\nHG4403 = \"hint\"\nHG0001 = \"off\"\nHG9999 = \"error\"\nHG2304 = \"loud\"\n";
        let config = Config::parse(text);
        assert_eq!(config.mnemonic, Mnemonic::International);
        assert_eq!(config.symbols[0].0, "a.sdf");
        assert_eq!(config.severity("HG2105"), None);
        assert_eq!(config.severity("HG4403"), Some(Severity::Hint));
        assert_eq!(config.severity("HG4307"), None, "off by default");
        assert_eq!(config.severity("HG0001"), Some(Severity::Error));
        let problems: Vec<&str> = config.problems.iter().map(|(_, p)| p.as_str()).collect();
        assert_eq!(problems.len(), 4, "{problems:?}");
        let (r, _) = config
            .problems
            .iter()
            .find(|(_, p)| p.contains("workspace.foo"))
            .expect("the unknown key is reported");
        assert_eq!(&text[std::ops::Range::<usize>::from(*r)], "foo");
    }

    #[test]
    fn the_configuration_problem_code_cannot_be_changed() {
        let text = "[diagnostics]\nHG6101 = \"off\"\n[workspace]\nfoo = 1\n";
        let config = Config::parse(text);
        assert_eq!(config.severity("HG6101"), Some(Severity::Error));
        let problems: Vec<(&str, &str)> = config
            .problems
            .iter()
            .map(|(at, p)| (&text[std::ops::Range::<usize>::from(*at)], p.as_str()))
            .collect();
        assert_eq!(
            problems,
            [
                (
                    "HG6101",
                    "HG6101 reports the problems of this file and its severity cannot be changed"
                ),
                ("foo", "unknown key 'workspace.foo'"),
            ]
        );
    }

    #[test]
    fn refused_symbol_tables_are_problems_on_their_entries() {
        let text = "[workspace]\nsymbols = [\"a.sdf\", \"../b.sdf\"]\n";
        let mut config = Config::parse(text);
        let refused = [("../b.sdf".to_owned(), "outside".to_owned())].into();
        config.refuse_symbols(&refused);
        assert_eq!(config.symbols.len(), 1);
        assert_eq!(config.symbols[0].0, "a.sdf");
        let [(at, problem)] = config.problems.as_slice() else {
            panic!("one problem expected: {:?}", config.problems);
        };
        assert_eq!(problem, "outside");
        assert_eq!(&text[std::ops::Range::<usize>::from(*at)], "\"../b.sdf\"");
    }

    #[test]
    fn syntax_errors_are_problems_not_crashes() {
        let config = Config::parse("[workspace\nmnemonic = ");
        assert_eq!(config.problems.len(), 1);
        assert_eq!(config.mnemonic, Mnemonic::Simatic);
    }

    #[test]
    fn an_invalid_glob_is_a_problem_and_its_key_keeps_the_default() {
        let text = "[workspace]\ninclude = [\"src/**\", \"[abc\"]\nexclude = [\"old/**\"]\n";
        let config = Config::parse(text);
        assert_eq!(config.include, vec!["**/*.higraph".to_owned()]);
        assert_eq!(config.exclude, vec!["old/**".to_owned()]);
        let [(at, problem)] = config.problems.as_slice() else {
            panic!("one problem expected: {:?}", config.problems);
        };
        assert_eq!(&text[std::ops::Range::<usize>::from(*at)], "\"[abc\"");
        assert!(
            problem.starts_with("invalid glob pattern '[abc' in 'workspace.include': "),
            "{problem}"
        );
    }

    #[test]
    fn a_configuration_that_is_not_utf8_is_a_problem_with_the_defaults() {
        let contents = FileContents::from_bytes(b"[workspace]\nmnemonic = \"\xff\"\n".to_vec());
        let config = Config::of_contents(&contents);
        assert_eq!(config.mnemonic, Mnemonic::Simatic);
        let [(at, problem)] = config.problems.as_slice() else {
            panic!("one problem expected: {:?}", config.problems);
        };
        assert_eq!(
            problem,
            "file is not valid UTF-8 (invalid byte at offset 24)"
        );
        assert_eq!(
            &contents.text()[std::ops::Range::<usize>::from(*at)],
            "\u{FFFD}"
        );
    }

    #[test]
    fn symbol_table_paths_are_named_as_output_names_files() {
        assert_eq!(normalise_path("plc/../plc/other.sdf"), "plc/other.sdf");
        assert_eq!(normalise_path("./plc//a.sdf"), "plc/a.sdf");
        assert_eq!(normalise_path("plc\\a.sdf"), "plc/a.sdf");
        assert_eq!(normalise_path("../shared/a.sdf"), "../shared/a.sdf");
        assert_eq!(normalise_path("/abs/x/../a.sdf"), "/abs/a.sdf");
        let config = Config::parse("[workspace]\nsymbols = [\"plc/../plc/a.sdf\"]\n");
        assert_eq!(config.symbols[0].0, "plc/a.sdf");
    }
}
