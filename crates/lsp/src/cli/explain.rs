//! `higraph-lsp explain HGnnnn`: prints the documentation of a diagnostic code — what the rule
//! checks, why, an example and how to fix it (`tooling.md` §2).
//!
//! The documentation is `docs/rules/HGnnnn.md`, embedded into the analysis crate at build
//! time (`higraph_analysis::registry::rule_docs`). The
//! code may be written in any letter case (`hg2105`). An unknown or malformed code is a usage
//! error (exit status 2).

use std::process::ExitCode;

use higraph_analysis::registry;

use super::{CliError, ExplainArgs, write_stdout};

pub(crate) fn run(args: &ExplainArgs) -> Result<ExitCode, CliError> {
    let code = normalise(&args.code)?;
    let text = documentation(&code).ok_or_else(|| {
        CliError::new(format!(
            "unknown diagnostic code '{code}'; the codes run from HG0001 to HG9904 \
             (`higraph-lsp check` shows the code of every diagnostic)"
        ))
    })?;
    write_stdout(text.as_bytes())?;
    Ok(ExitCode::SUCCESS)
}

/// `hg2105` → `HG2105`; anything that is not `HG` and four digits is refused.
fn normalise(written: &str) -> Result<String, CliError> {
    let code = written.trim().to_ascii_uppercase();
    let well_formed =
        code.len() == 6 && code.starts_with("HG") && code[2..].bytes().all(|b| b.is_ascii_digit());
    if well_formed {
        Ok(code)
    } else {
        Err(CliError::new(format!(
            "'{}' is not a diagnostic code; codes look like HG2105",
            written.trim()
        )))
    }
}

/// The documentation of a code: its file, or (should a file be missing) a short text made
/// from the registry.
fn documentation(code: &str) -> Option<String> {
    if let Some((_, text)) = registry::rule_docs().iter().find(|(c, _)| *c == code) {
        return Some((*text).to_owned());
    }
    let rule = registry::rule_of(code)?;
    let off = if rule.off_by_default {
        " (off by default)"
    } else {
        ""
    };
    Some(format!(
        "# {code}\n\nSeverity: {}{off}\n\nMessage: {}\n",
        rule.default_severity.as_str(),
        rule.template
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    use higraph_analysis::Severity;

    fn doc(code: &str) -> &'static str {
        registry::rule_docs()
            .iter()
            .find(|(c, _)| *c == code)
            .map(|(_, text)| *text)
            .unwrap_or_else(|| panic!("no documentation for {code}"))
    }

    #[test]
    fn codes_are_normalised() {
        assert_eq!(normalise("hg2105").ok(), Some("HG2105".to_owned()));
        assert_eq!(normalise(" HG0001 ").ok(), Some("HG0001".to_owned()));
        assert!(normalise("2105").is_err());
        assert!(normalise("HG21050").is_err());
        assert!(normalise("HGxxxx").is_err());
        assert!(normalise("").is_err());
    }

    /// Every code of the registry has a documentation file and every file is a code.
    #[test]
    fn every_code_is_documented() {
        let codes: Vec<&str> = registry::RULES.iter().map(|r| r.code.as_str()).collect();
        let documented: Vec<&str> = registry::rule_docs()
            .iter()
            .map(|(code, _)| *code)
            .collect();
        assert_eq!(codes, documented);
    }

    /// The `Severity:` line of every file matches the registry's default severity and
    /// off-by-default mark.
    #[test]
    fn severities_match_the_registry() {
        for rule in registry::RULES {
            let code = rule.code.as_str();
            let text = doc(code);
            let line = text
                .lines()
                .find(|l| l.starts_with("Severity: "))
                .unwrap_or_else(|| panic!("{code}: no 'Severity:' line"));
            let severity = match rule.default_severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
                Severity::Info => "info",
                Severity::Hint => "hint",
            };
            let expected = if rule.off_by_default {
                format!("Severity: {severity} (off by default)")
            } else {
                format!("Severity: {severity}")
            };
            assert_eq!(line, expected, "{code}");
        }
    }

    /// Every file has the title line and the four sections, in order.
    #[test]
    fn documentation_has_its_sections() {
        for (code, text) in registry::rule_docs() {
            let first = text.lines().next().unwrap_or_default();
            assert!(
                first.starts_with(&format!("# {code}: ")) && first.len() > 10,
                "{code}: title line is '{first}'"
            );
            let mut at = 0;
            for heading in ["## What it checks", "## Why", "## Example", "## How to fix"] {
                let found = text[at..]
                    .find(&format!("\n{heading}\n"))
                    .unwrap_or_else(|| panic!("{code}: '{heading}' missing or out of order"));
                at += found + heading.len();
            }
            assert!(text.contains("\n```"), "{code}: no example block");
        }
    }

    /// The `.higraph` examples parse: those of syntax codes produce their code, all others
    /// parse without syntax errors.
    #[test]
    fn examples_parse() {
        for (code, text) in registry::rule_docs() {
            for example in examples(text, "higraph") {
                let parse = higraph_syntax::parse(&example);
                let codes: Vec<&str> = parse.errors().iter().map(|e| e.code.as_str()).collect();
                if code.starts_with("HG0") {
                    assert!(
                        codes.contains(code),
                        "{code}: the example gives {codes:?}:\n{example}"
                    );
                } else {
                    assert!(
                        codes.is_empty(),
                        "{code}: the example has syntax errors {codes:?}:\n{example}"
                    );
                }
            }
        }
    }

    /// The fenced code blocks of `lang` in a markdown text.
    fn examples(text: &str, lang: &str) -> Vec<String> {
        let mut out = Vec::new();
        let mut current: Option<String> = None;
        for line in text.lines() {
            match &mut current {
                None if line == format!("```{lang}") => current = Some(String::new()),
                Some(_) if line == "```" => out.extend(current.take()),
                Some(block) => {
                    block.push_str(line);
                    block.push('\n');
                }
                None => {}
            }
        }
        out
    }

    #[test]
    fn explain_falls_back_to_the_registry() {
        assert!(documentation("HG9999").is_none());
        assert!(
            documentation("HG2105").is_some_and(|t| t.starts_with("# HG2105: ")),
            "the file is used"
        );
    }
}
