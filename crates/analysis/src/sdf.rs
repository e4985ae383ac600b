//! Import of STEP 7 symbol tables in System Data Format (`tooling.md` §3): one symbol a line,
//! four comma-separated double-quoted fields — symbol, address, data type, comment — each
//! possibly padded with spaces.
//!
//! * HG6005: a file that is missing, unreadable or not an `.sdf` export is reported on its
//!   entry in `higraph.toml`; a line that cannot be read is reported on that line and skipped.
//! * HG6007: a data type this language does not know (a UDT, ARRAY, STRUCT, ...) is imported
//!   untyped. A block symbol's data type names a block (`FB 10`, or `FB` alone as the DIF
//!   layout writes it) and makes it a block.
//! * A row of a variable table (`VAT 1` in the address column) is skipped: it is no operand.
//!
//! Addresses are read in the workspace's mnemonic set; those of the other set are translated.
//! Lines end at LF, CR LF or a lone CR. The rules on the imported symbols themselves (HG6001,
//! HG6002, HG6003, HG6006, HG1301) are workspace rules in `rules::symbols`; they are reported
//! on a field of the line (the name, the address or the data type, as each row of
//! `diagnostics.md` says: the value inside the quotes, without padding), HG6005 and HG6007 on
//! the whole line.

use higraph_syntax::{TextRange, TextSize};

use crate::{
    address::{self, Address, AddressError},
    db::{File, Workspace},
    diag::{Diag, Loc},
    index::{Symbol, SymbolSource},
    lang::{Mnemonic, Type},
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
        .map(|(i, import)| {
            let problem = match &import.file {
                Ok(file) => match unrecognised_format(import, file.contents(db).text()) {
                    None => return parse_table(db, *file, i, mnemonic),
                    Some(reason) => reason,
                },
                Err(reason) => reason.clone(),
            };
            let mut table = ImportedTable::default();
            if let Some(config) = ws.config_file(db) {
                table.problems.push(Diag::new(
                    "HG6005",
                    Loc::in_file(config, import.entry),
                    format!("cannot import symbol table {}: {problem}", import.path),
                ));
            }
            table
        })
        .collect()
}

/// Why a loaded file is not a symbol table export this importer reads: a file that is not an
/// `.sdf` export (STEP 7's `.asc`, `.dif` and `.seq` formats are not supported), or binary data.
fn unrecognised_format(import: &Import, text: &str) -> Option<String> {
    let is_sdf = import
        .path
        .rsplit_once('.')
        .is_some_and(|(_, ext)| ext.eq_ignore_ascii_case("sdf"));
    if !is_sdf {
        return Some(
            "the format is not recognised (expected a STEP 7 symbol table export in System Data Format, .sdf)"
                .to_owned(),
        );
    }
    text.contains('\0')
        .then(|| "the format is not recognised (the file contains binary data)".to_owned())
}

/// The lines of a text with their start offsets, without line breaks (LF, CR LF or a lone CR
/// end a line).
fn lines(text: &str) -> Vec<(usize, &str)> {
    let mut lines = Vec::new();
    let bytes = text.as_bytes();
    let mut start = 0;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\n' => {
                lines.push((start, &text[start..i]));
                start = i + 1;
            }
            b'\r' => {
                lines.push((start, &text[start..i]));
                if bytes.get(i + 1) == Some(&b'\n') {
                    i += 1;
                }
                start = i + 1;
            }
            _ => {}
        }
        i += 1;
    }
    if start < text.len() {
        lines.push((start, &text[start..]));
    }
    lines
}

fn parse_table(
    db: &dyn salsa::Database,
    file: File,
    import: usize,
    mnemonic: Mnemonic,
) -> ImportedTable {
    let text = file.contents(db).text();
    let path = file.path(db).clone();
    let mut table = ImportedTable::default();
    for (n, (line_start, line)) in lines(text).into_iter().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let range = TextRange::new(size(line_start), size(line_start + line.len()));
        let loc = Loc::in_file(file, range);
        // A field's range in the file (its value, without quotes and padding).
        let field_loc = |field: TextRange| Loc::in_file(file, field + size(line_start));
        let bad_line = |reason: String| {
            Diag::new(
                "HG6005",
                loc,
                format!("line {} of {path} cannot be read: {reason}", n + 1),
            )
        };
        match parse_line(line, mnemonic) {
            // A variable table (VAT) names no operand: nothing to import.
            Ok(None) => {}
            Ok(Some(line)) => {
                if let Some(type_text) = &line.unsupported_type {
                    table.problems.push(Diag::new(
                        "HG6007",
                        loc,
                        format!(
                            "imported symbol '{}' has data type {type_text}, which is not supported; it is treated as untyped",
                            line.name
                        ),
                    ));
                }
                table.symbols.push(Symbol {
                    name: line.name,
                    quoted: true,
                    source: SymbolSource::Imported(import),
                    name_loc: field_loc(line.name_range),
                    address_text: line.address_text,
                    address_loc: field_loc(line.address_range),
                    address: Some(line.address),
                    type_loc: line.type_range.map(field_loc),
                    ty: line.ty,
                    type_text: line.type_text,
                    comment: line.comment,
                });
            }
            Err(reason) => table.problems.push(bad_line(reason)),
        }
    }
    table
}

/// One symbol line of an export.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Line {
    name: String,
    /// Where the name, the address and a non-empty data type stand in the line (the values
    /// inside the quotes, without padding).
    name_range: TextRange,
    address_text: String,
    address_range: TextRange,
    address: Address,
    /// The data type field, if not empty.
    type_text: Option<String>,
    type_range: Option<TextRange>,
    /// The type: the data type, else the address's; `None` if unsupported.
    ty: Option<Type>,
    /// The data type field if it names a type this language does not support (HG6007).
    unsupported_type: Option<String>,
    comment: Option<String>,
}

/// Reads one line: four quoted fields — symbol, address, data type, comment. `None` for a row
/// that names a variable table (`"Beobachtung","VAT     1",...`): STEP 7 lists them among the
/// symbols, but they are no operand of a program.
fn parse_line(text: &str, mnemonic: Mnemonic) -> Result<Option<Line>, String> {
    let fields = split_fields(text)?;
    let [name, address, data_type_field, comment] = <[Field; 4]>::try_from(fields)
        .map_err(|fields| format!("expected 4 fields, found {}", fields.len()))?;
    if name.text.is_empty() {
        return Err("the symbol name is empty".to_owned());
    }
    if is_vat(&address.text) {
        return Ok(None);
    }
    let address_value = read_address(&address.text, mnemonic)?;
    let (ty, unsupported_type) = data_type(&data_type_field.text, &address_value, mnemonic);
    let typed = !data_type_field.text.is_empty();
    Ok(Some(Line {
        name: name.text,
        name_range: name.range,
        address: address_value,
        address_range: address.range,
        address_text: address.text,
        ty,
        unsupported_type,
        type_range: typed.then_some(data_type_field.range),
        type_text: typed.then_some(data_type_field.text),
        comment: (!comment.text.is_empty()).then_some(comment.text),
    }))
}

/// Reads the address field in the workspace's set; addresses of the other set are
/// translated (`diagnostics.md` §2.7a).
fn read_address(text: &str, mnemonic: Mnemonic) -> Result<Address, String> {
    let compact: String = text.split_whitespace().collect();
    let read =
        address::read(&compact, mnemonic).or_else(|| address::read(&compact, mnemonic.other()));
    match read.map(|r| r.address) {
        Some(Ok(address)) => Ok(address),
        Some(Err(AddressError::Malformed(reason))) => {
            Err(format!("'{text}' is not a valid address: {reason}"))
        }
        Some(Err(AddressError::BitOutOfRange { bit, .. })) => Err(format!(
            "'{text}' is not a valid address: bit number {bit} is outside 0..7"
        )),
        Some(Err(AddressError::NeedsDb)) => Err(format!(
            "'{text}' is not a valid address: it needs a data block number"
        )),
        Some(Err(AddressError::InstanceDb)) => Err(format!(
            "'{text}' is not a valid address: instance-DB operands are not available"
        )),
        None => Err(format!("'{text}' is not an address")),
    }
}

/// The type of an imported symbol and, if the data type is not supported, its text. An empty
/// data type means the address's type; a block symbol's data type names a block (`FC 1`,
/// `UDT 5` for a DB), which gives the block type.
fn data_type(text: &str, address: &Address, mnemonic: Mnemonic) -> (Option<Type>, Option<String>) {
    if text.is_empty() {
        return (Some(address.ty()), None);
    }
    if address.block_kind().is_some() && is_block_reference(text, mnemonic) {
        return (Some(Type::Block), None);
    }
    match parse_type(text) {
        Some(ty) => (Some(ty), None),
        None => (None, Some(text.to_owned())),
    }
}

/// `FC 1`, `UDT 5`, `VAT 1`: the data type STEP 7 exports for block symbols (for an instance
/// DB, its FB; for a shared DB, the DB itself or its UDT). Exports in the DIF layout write the
/// block kind alone (`FB`, `DB`, `SFC`, ...); it is read the same way.
fn is_block_reference(text: &str, mnemonic: Mnemonic) -> bool {
    let compact: String = text.split_whitespace().collect();
    const KINDS: [&str; 8] = ["OB", "FC", "FB", "DB", "SFC", "SFB", "UDT", "VAT"];
    KINDS.iter().any(|k| compact.eq_ignore_ascii_case(k))
        || is_vat(&compact)
        || address::read(&compact, mnemonic)
            .and_then(|r| r.address.ok())
            .is_some_and(|a| a.block_kind().is_some())
}

/// `VAT 1`, `VAT1`: a variable table.
fn is_vat(text: &str) -> bool {
    let compact: String = text.split_whitespace().collect();
    compact
        .get(..3)
        .is_some_and(|p| p.eq_ignore_ascii_case("VAT"))
        && compact.len() > 3
        && compact[3..].bytes().all(|b| b.is_ascii_digit())
}

/// A type name of the language, `STRING[n]` included.
fn parse_type(text: &str) -> Option<Type> {
    let compact: String = text.split_whitespace().collect();
    if let Some(ty) = Type::from_name(&compact, false) {
        return Some(ty);
    }
    let upper = compact.to_ascii_uppercase();
    let length = upper.strip_prefix("STRING[")?.strip_suffix(']')?;
    let n: u16 = length.parse().ok()?;
    (1..=254).contains(&n).then_some(Type::String(n))
}

/// One field of a line: its value without quotes and padding, and where that value stands in
/// the line (an empty value: the position just inside its opening quote).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Field {
    text: String,
    range: TextRange,
}

/// Splits `"a","b" , "c","d"` into trimmed field values with their ranges in the line.
fn split_fields(line: &str) -> Result<Vec<Field>, String> {
    let mut fields = Vec::new();
    // Offsets are kept relative to `line`: `rest` is always a suffix of it.
    let offset = |rest: &str| line.len() - rest.len();
    let mut rest = line.trim_start();
    loop {
        let Some(after_quote) = rest.strip_prefix('"') else {
            return Err("a field must be enclosed in double quotes".to_owned());
        };
        let Some(end) = after_quote.find('"') else {
            return Err("a field is not closed with '\"'".to_owned());
        };
        let raw = &after_quote[..end];
        let value = raw.trim();
        let start = offset(after_quote) + (raw.len() - raw.trim_start().len());
        fields.push(Field {
            text: value.to_owned(),
            range: TextRange::at(size(start), size(value.len())),
        });
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
        let line = r#" "Motor ein"    ,"A   4.0 ","  BOOL    ","Motor on",""  "#;
        let fields = split_fields(line).expect("fields");
        let texts: Vec<&str> = fields.iter().map(|f| f.text.as_str()).collect();
        assert_eq!(texts, ["Motor ein", "A   4.0", "BOOL", "Motor on", ""]);
        for field in &fields {
            assert_eq!(&line[field.range], field.text);
        }
        assert_eq!(fields[0].range, TextRange::new(2.into(), 11.into()));
        assert_eq!(fields[4].range, TextRange::empty(53.into()));
        assert!(split_fields(r#""a","b"#).is_err());
        assert!(split_fields("a,b").is_err());
    }

    #[test]
    fn decodes_windows_1252() {
        // `C4 20 80` is not UTF-8 (a lead byte followed by a space).
        assert_eq!(decode(b"\xC4 \x80"), "Ä €");
        assert_eq!(decode("Ä".as_bytes()), "Ä");
        assert_eq!(decode("\u{FEFF}x".as_bytes()), "x");
    }

    #[test]
    fn splits_lines_at_every_line_break() {
        assert_eq!(
            lines("a\r\nb\rc\n\nd"),
            vec![(0, "a"), (3, "b"), (5, "c"), (7, ""), (8, "d")]
        );
        assert_eq!(lines(""), Vec::<(usize, &str)>::new());
    }

    #[test]
    fn reads_lines_of_both_mnemonic_sets() {
        let set = Mnemonic::Simatic;
        let line = parse_line(r#""Motor","Q   4.0","BOOL","""#, set)
            .expect("line")
            .expect("a symbol");
        assert_eq!(line.address.display(set), "A 4.0");
        assert_eq!(line.ty, Some(Type::Bool));
        let block = parse_line(r#""GG","FC   1","FC   1","""#, set)
            .expect("line")
            .expect("a symbol");
        assert_eq!(
            (block.ty, block.unsupported_type),
            (Some(Type::Block), None)
        );
        let udt = parse_line(r#""Rezept","MD 20","UDT 7","""#, set)
            .expect("line")
            .expect("a symbol");
        assert_eq!(udt.ty, None);
        assert_eq!(udt.unsupported_type.as_deref(), Some("UDT 7"));
        let untyped = parse_line(r#""Wert","MW 2","","""#, set)
            .expect("line")
            .expect("a symbol");
        assert_eq!(untyped.ty, Some(Type::Word));
        assert!(parse_line(r#""Band","A 4.1","BOOL""#, set).is_err());
        assert!(parse_line(r#""Band","X 4.1","BOOL","""#, set).is_err());
        assert!(parse_line(r#""","A 4.1","BOOL","""#, set).is_err());
    }

    /// Block rows as STEP 7 exports them: every block kind in the address column, the data
    /// type in the ASC form (`FB 10`) or the DIF form (`FB`); variable tables are skipped.
    #[test]
    fn reads_block_rows_as_step7_exports_them() {
        let set = Mnemonic::Simatic;
        let rows = [
            r#""Cycle Execution ","OB    1","OB    1","Main program""#,
            r#""Motor_Steuerung ","FB   10","FB   10","""#,
            r#""Motor_DB        ","DB   10","FB   10","instance DB""#,
            r#""Motor_DB2       ","DB   11","FB","instance DB (DIF)""#,
            r#""Rezept          ","DB   20","DB","shared DB (DIF)""#,
            r#""Rezept2         ","DB   21","UDT   5","""#,
            r#""Rezepttyp       ","UDT    5","UDT    5","""#,
            r#""TEST_DATE       ","SFC    1","SFC","read clock""#,
            r#""ALARM           ","SFB   33","SFB   33","""#,
            r#""Lauf            ","FC    3","FC","""#,
        ];
        for row in rows {
            let line = parse_line(row, set)
                .unwrap_or_else(|e| panic!("{row}: {e}"))
                .unwrap_or_else(|| panic!("{row}: skipped"));
            assert_eq!(
                (line.ty, line.unsupported_type),
                (Some(Type::Block), None),
                "{row}"
            );
            assert!(line.address.block_kind().is_some(), "{row}");
        }
        for vat in [
            r#""Beobachtung","VAT     1","VAT     1","""#,
            r#""Beobachtung","VAT1","","""#,
            r#""Beobachtung","vat 2","VAT","""#,
        ] {
            assert_eq!(parse_line(vat, set), Ok(None), "{vat}");
        }
        // A bare block kind is a block type only on a block symbol.
        let bit = parse_line(r#""Band","A 4.1","FB","""#, set)
            .expect("line")
            .expect("a symbol");
        assert_eq!(bit.unsupported_type.as_deref(), Some("FB"));
    }
}
