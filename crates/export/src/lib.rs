//! The writers behind `higraph-lsp build`: pure functions from a lowered program (or a
//! collected chart model) to the bytes of the files `build` writes. No salsa, no LSP, no I/O:
//! the analysis collects, this crate writes, the CLI and the server put the bytes on disk.
//!
//! | module    | what |
//! |-----------|------|
//! | `awl`     | a graph group as a STEP 7 external source (DB, FC, optional OB 1) |
//! | `sdf`     | the symbols the generated code uses, as a STEP 7 symbol table |
//! | `cp1252`  | Windows-1252 text with CR LF line ends, refusing what it cannot encode |
//! | `plcopen` | charts as PLCopen TC6 XML 2.01 function blocks with SFC bodies |

pub mod awl;
pub mod cp1252;
pub mod plcopen;
pub mod sdf;
