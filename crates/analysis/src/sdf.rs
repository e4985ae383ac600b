//! Import of STEP 7 symbol tables in System Data Format (`tooling.md` §3): one symbol a line,
//! four comma-separated double-quoted fields — symbol, address, data type, comment — each
//! possibly padded with spaces. Bad lines are reported (HG6005) and skipped; unsupported data
//! types are imported untyped (HG6007).

use higraph_syntax::{TextRange, TextSize};

use crate::{
    address,
    db::{File, Workspace},
    diag::{Diag, Loc},
    index::{Symbol, SymbolSource},
    lang::Type,
};

/// An import as configured: the path written in `higraph.toml` and the loaded file (or why it
/// could not be loaded).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Import {
    pub path: String,
    /// The range of the entry in `higraph.toml`.
    pub entry: TextRange,
    pub file: Result<File, String>,
}

/// The symbols and problems of one imported table.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ImportedTable {
    pub symbols: Vec<Symbol>,
    pub problems: Vec<Diag>,
}

/// Decodes an `.sdf` file: UTF-8 when valid, otherwise Windows-1252 (`diagnostics.md` §2.7a).
pub fn decode(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(text) => text.strip_prefix('\u{FEFF}').unwrap_or(text).to_owned(),
        Err(_) => bytes.iter().map(|&b| windows_1252(b)).collect(),
    }
}

fn windows_1252(byte: u8) -> char {
    const HIGH: [char; 32] = [
        '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8D}', 'Ž',
        '\u{8F}', '\u{90}', '‘', '’', '“', '”', '•', '–', '—', '˜', '™', 'š', '›', 'œ', '\u{9D}',
        'ž', 'Ÿ',
    ];
    match byte {
        0x80..=0x9F => HIGH[usize::from(byte - 0x80)],
        _ => char::from(byte),
    }
}

/// All imported tables of the workspace, in `higraph.toml` order.
#[salsa::tracked(returns(ref))]
pub fn imported_tables(db: &dyn salsa::Database, ws: Workspace) -> Vec<ImportedTable> {
    let mnemonic = ws.config(db).mnemonic;
    ws.imports(db)
        .iter()
        .enumerate()
        .map(|(i, import)| match &import.file {
            Ok(file) => parse_table(db, *file, i, mnemonic),
            Err(reason) => {
                let mut table = ImportedTable::default();
                if let Some(config) = ws.config_file(db) {
                    table.problems.push(Diag::new(
                        "HG6005",
                        Loc::in_file(config, import.entry),
                        format!("cannot import symbol table {}: {reason}", import.path),
                    ));
                }
                table
            }
        })
        .collect()
}

fn parse_table(
    db: &dyn salsa::Database,
    file: File,
    import: usize,
    mnemonic: crate::lang::Mnemonic,
) -> ImportedTable {
    let text = file.contents(db).text().to_owned();
    let path = file.path(db).clone();
    let mut table = ImportedTable::default();
    let mut offset = 0usize;
    for (n, raw_line) in text.split_inclusive('\n').enumerate() {
        let line_start = offset;
        offset += raw_line.len();
        let line = raw_line.trim_end_matches(['\n', '\r']);
        if line.trim().is_empty() {
            continue;
        }
        let range = TextRange::new(size(line_start), size(line_start + line.len()));
        let loc = Loc::in_file(file, range);
        let line_no = n + 1;
        let fields = match split_fields(line) {
            Ok(fields) if fields.len() == 4 => fields,
            Ok(fields) => {
                table.problems.push(Diag::new(
                    "HG6005",
                    loc,
                    format!(
                        "line {line_no} of {path} cannot be read: expected 4 fields, found {}",
                        fields.len()
                    ),
                ));
                continue;
            }
            Err(reason) => {
                table.problems.push(Diag::new(
                    "HG6005",
                    loc,
                    format!("line {line_no} of {path} cannot be read: {reason}"),
                ));
                continue;
            }
        };
        let [name, address_text, type_text, comment] =
            [&fields[0], &fields[1], &fields[2], &fields[3]];
        if name.is_empty() {
            table.problems.push(Diag::new(
                "HG6005",
                loc,
                format!("line {line_no} of {path} cannot be read: the symbol name is empty"),
            ));
            continue;
        }
        let compact: String = address_text.split_whitespace().collect();
        let read = address::read(&compact, mnemonic)
            .or_else(|| address::read(&compact, mnemonic.other()))
            .and_then(|r| r.address.ok());
        let Some(address) = read else {
            table.problems.push(Diag::new(
                "HG6005",
                loc,
                format!(
                    "line {line_no} of {path} cannot be read: '{address_text}' is not an address"
                ),
            ));
            continue;
        };
        let ty = if type_text.is_empty() {
            Some(address.ty())
        } else {
            match Type::from_name(type_text, false) {
                Some(ty) => Some(ty),
                None => {
                    table.problems.push(Diag::new(
                        "HG6007",
                        loc,
                        format!(
                            "imported symbol '{name}' has data type {type_text}, which is not supported; it is treated as untyped"
                        ),
                    ));
                    None
                }
            }
        };
        table.symbols.push(Symbol {
            name: name.clone(),
            quoted: true,
            source: SymbolSource::Imported(import),
            name_loc: loc,
            address_text: address_text.clone(),
            address_loc: loc,
            address: Some(address),
            type_text: (!type_text.is_empty()).then(|| type_text.clone()),
            type_loc: None,
            ty,
            comment: (!comment.is_empty()).then(|| comment.clone()),
        });
    }
    table
}

/// Splits `"a","b" , "c","d"` into trimmed field values.
fn split_fields(line: &str) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut rest = line.trim();
    loop {
        let Some(after_quote) = rest.strip_prefix('"') else {
            return Err("a field must be enclosed in double quotes".to_owned());
        };
        let Some(end) = after_quote.find('"') else {
            return Err("a field is not closed with '\"'".to_owned());
        };
        fields.push(after_quote[..end].trim().to_owned());
        rest = after_quote[end + 1..].trim_start();
        if rest.is_empty() {
            return Ok(fields);
        }
        match rest.strip_prefix(',') {
            Some(next) => rest = next.trim_start(),
            None => return Err("fields must be separated by ','".to_owned()),
        }
    }
}

fn size(n: usize) -> TextSize {
    TextSize::from(u32::try_from(n).unwrap_or(u32::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_padded_fields() {
        assert_eq!(
            split_fields(r#""Motor ein"    ,"A   4.0 ","BOOL    ","Motor on""#),
            Ok(vec![
                "Motor ein".into(),
                "A   4.0".into(),
                "BOOL".into(),
                "Motor on".into()
            ])
        );
        assert!(split_fields(r#""a","b"#).is_err());
        assert!(split_fields("a,b").is_err());
    }

    #[test]
    fn decodes_windows_1252() {
        assert_eq!(decode(b"\xC4\x80"), "Ä€");
        assert_eq!(decode("Ä".as_bytes()), "Ä");
    }
}
