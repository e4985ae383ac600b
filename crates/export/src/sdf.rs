//! The STEP 7 System Data Format symbol table `build` writes beside the sources
//! (`tooling.md` §3): one symbol a line, four comma-separated double-quoted fields — symbol,
//! address, data type, comment — padded with spaces to the widths STEP 7 exports (24, 12, 10
//! and 80 characters), Windows-1252, CR LF.

use crate::cp1252::{self, Unencodable};

/// One symbol of the table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Symbol {
    pub name: String,
    /// The absolute address or block (`E 0.0`, `FC 1`, `DB 1`), in the mnemonics of the build.
    pub address: String,
    /// The data type (`BOOL`, `FC`, `DB`, ...).
    pub ty: String,
    pub comment: String,
}

/// The table as text (LF line ends), in the order given. A `"` inside a field would end it
/// early, so it is written as `'`.
pub fn text(symbols: &[Symbol]) -> String {
    let mut out = String::new();
    for s in symbols {
        let field = |v: &str, width: usize| {
            let v = v.replace('"', "'");
            format!("\"{v:<width$}\"")
        };
        out.push_str(&field(&s.name, 24));
        out.push(',');
        out.push_str(&field(&s.address, 12));
        out.push(',');
        out.push_str(&field(&s.ty, 10));
        out.push(',');
        out.push_str(&field(&s.comment, 80));
        out.push('\n');
    }
    out
}

/// The table as Windows-1252 bytes with CR LF line ends, one symbol a line.
pub fn write(symbols: &[Symbol]) -> Result<Vec<u8>, Unencodable> {
    cp1252::encode(&text(symbols))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn padded_fields_crlf() {
        let bytes = write(&[Symbol {
            name: "Start".into(),
            address: "E 0.7".into(),
            ty: "BOOL".into(),
            comment: "Starttaster \u{e4}".into(),
        }])
        .unwrap();
        let line = String::from_utf8_lossy(&bytes).into_owned();
        assert!(line.starts_with(
            "\"Start                   \",\"E 0.7       \",\"BOOL      \",\"Starttaster "
        ));
        assert!(bytes.ends_with(b"\"\r\n"));
        assert!(bytes.contains(&0xE4));
    }
}
