//! The STEP 7 System Data Format symbol table `build` writes beside the sources.

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

/// The table as Windows-1252 bytes with CR LF line ends, one symbol a line.
pub fn write(symbols: &[Symbol]) -> Vec<u8> {
    let _ = symbols;
    todo!("sdf::write")
}
