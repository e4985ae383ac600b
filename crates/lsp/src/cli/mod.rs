//! The command line (`tooling.md` §2): argument definitions and dispatch to one module per
//! subcommand. Every subcommand returns an exit status; a [`CliError`] is a usage error or
//! unreadable input and ends with status 2 and a message on stderr, never a panic.

mod build;
mod check;
mod explain;
// `fmt` itself would clash with `std::fmt`.
#[path = "fmt.rs"]
mod fmt_command;
mod import;
mod output;
mod parse;
mod paths;
mod render;
mod test;

use std::fmt;
use std::io::{self, IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::workspace::WorkspaceError;

/// Exit status 1: error-level diagnostics were found (`diagnostics.md` §4.3).
pub(crate) const EXIT_FAILURE: u8 = 1;
/// Exit status 2: the command could not run.
pub(crate) const EXIT_USAGE: u8 = 2;

/// Language server and checker for Siemens S7 HiGraph state graphs and SFC charts.
#[derive(Debug, Parser)]
#[command(name = "higraph-lsp", version, about, long_about = None)]
#[command(
    after_help = "Documentation: the docs/ folder of the higraph-lsp repository (tutorial, \
language reference, configuration, CI, editors); `higraph-lsp explain CODE` prints the page of \
one diagnostic code."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Accepted and ignored: without a subcommand the language server runs on stdin/stdout
    /// (editors' clients append `--stdio`).
    #[arg(long, hide = true)]
    stdio: bool,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the language server on stdin/stdout (also what `higraph-lsp` without a command
    /// does).
    Lsp(LspArgs),
    /// Check a workspace and report diagnostics.
    Check(CheckArgs),
    /// Print the syntax tree of a file (for debugging the parser).
    Parse(ParseArgs),
    /// Rewrite files in the canonical layout (`--check`: only list files that would change).
    Fmt(FmtArgs),
    /// Print the documentation of a diagnostic code (what, why, example, fix).
    Explain(ExplainArgs),
    /// Draw a graph, group or chart as SVG or Graphviz DOT.
    Render(RenderArgs),
    /// Run the `test` items of a workspace on the simulated machine.
    Test(TestArgs),
    /// Generate STEP 7 sources for the graph groups and PLCopen XML for the charts.
    #[command(long_about = BUILD_ABOUT)]
    Build(BuildArgs),
    /// Convert the SFC programs and function blocks of PLCopen XML files into IEC charts.
    #[command(long_about = IMPORT_ABOUT)]
    Import(ImportArgs),
}

const IMPORT_ABOUT: &str = "\
Convert the SFC programs and function blocks of PLCopen TC6 XML 2.01 files (the neutral \
format, CODESYS and Beremiz exports) into IEC charts (`profile iec;`).

Each POU whose body is SFC becomes `<POU name>.higraph` in the output folder, laid out as \
`fmt` lays it out. What the language cannot express (loops and function calls in ST, LD or \
FBD bodies, macro steps, user-defined types, ...) is reported as `FILE:LINE: warning: ...` \
with its POU and element, and the rest still imports: an action body that cannot be \
imported becomes an empty action, a condition FALSE, each with a comment. Existing files are \
not replaced without --force. Exit status: 0 everything imported, 1 files written with \
problems reported, 2 usage error, unreadable file, invalid XML or a file not replaced.";

/// Arguments of `higraph-lsp import`.
#[derive(Debug, Args)]
pub(crate) struct ImportArgs {
    /// PLCopen XML files to import.
    #[arg(value_name = "FILE", required = true)]
    pub files: Vec<PathBuf>,
    /// Write the charts into this folder (created if needed) instead of the current folder.
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Replace files that already exist.
    #[arg(long)]
    pub force: bool,
}

const BUILD_ABOUT: &str = "\
Generate STEP 7 sources for the graph groups and PLCopen XML for the charts.

The workspace is analysed as `check` analyses it. If the groups or charts to build, or what \
they use (the graphs of their instances, symbol tables, block interfaces), have errors, \
nothing is written: the diagnostics are printed and the exit status is 1. Otherwise each \
group becomes `<group>.awl`, all charts of the run one `charts.xml`, and the symbols the \
sources use `symbols.sdf`. Files whose contents would not change are not rewritten; other \
files in the output folder are left alone. Exit status: 0 built, 1 errors in the input, 2 \
usage or I/O error.";

/// Arguments of `higraph-lsp build`.
#[derive(Debug, Args)]
pub(crate) struct BuildArgs {
    /// Files or folders whose groups and charts are built (default: the whole workspace); the
    /// workspace is found as `check` finds it, from the first PATH or the current folder.
    #[arg(value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    /// What to generate.
    #[arg(long, value_enum, default_value_t = BuildTarget::Awl)]
    pub target: BuildTarget,
    /// Write into this folder (created if needed) instead of `build/` in the workspace root.
    /// It is never analysed afterwards; it must not be the workspace root or hold its
    /// sources.
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Also generate an organization block OB 1 that calls each group's FC, with INIT_SD set
    /// in the first cycle after a restart.
    #[arg(long)]
    pub with_ob1: bool,
    /// Use absolute addresses and block numbers instead of symbols, and write no
    /// `symbols.sdf` (for tools that cannot import a symbol table, such as Awlsim).
    #[arg(long)]
    pub absolute: bool,
}

/// What `build` generates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum BuildTarget {
    /// STEP 7 sources (`<group>.awl`) for the graph groups.
    Awl,
    /// one PLCopen XML document (`charts.xml`) for the charts.
    Plcopen,
    /// both.
    All,
}

/// Arguments of `higraph-lsp test`.
#[derive(Debug, Args)]
pub(crate) struct TestArgs {
    /// Files or folders whose tests run (default: every test of the workspace); the workspace
    /// is found as `check` finds it, from the first PATH or the current folder.
    #[arg(value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    /// Run only the tests whose name contains PATTERN (any letter case).
    #[arg(long, value_name = "PATTERN")]
    pub filter: Option<String>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = TestFormat::Human)]
    pub format: TestFormat,
    /// Write a JSON trace and a VCD waveform of every test that runs into this folder
    /// (created if needed; only earlier traces are replaced).
    #[arg(long, value_name = "DIR")]
    pub trace: Option<PathBuf>,
}

/// The output formats of `test`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum TestFormat {
    /// one line per test and the failures with their source lines, like `cargo test`.
    Human,
    /// one JSON object with every test, its result and failures.
    Json,
    /// JUnit XML for CI test reporters.
    Junit,
}

/// Arguments of `higraph-lsp lsp`.
#[derive(Debug, Args)]
pub(crate) struct LspArgs {
    /// Talk over stdin/stdout (the only transport; accepted for editors that pass it).
    #[arg(long)]
    pub stdio: bool,
}

/// Arguments of `higraph-lsp check`.
#[derive(Debug, Args)]
pub(crate) struct CheckArgs {
    /// Files or folders to report on (default: the current folder). The workspace is the
    /// nearest folder upwards from the first PATH that holds `higraph.toml`, else the first
    /// PATH's folder.
    #[arg(value_name = "PATH")]
    pub paths: Vec<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    pub format: Format,
    /// Make warnings fail the check too (exit status 1).
    #[arg(long, value_enum, value_name = "LINT")]
    pub deny: Vec<Deny>,
    /// Configuration file to use instead of the workspace's `higraph.toml` (all its settings
    /// apply; it must be readable).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// When to colour the human output.
    #[arg(long, value_enum, value_name = "WHEN", default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Arguments of `higraph-lsp fmt`.
#[derive(Debug, Args)]
pub(crate) struct FmtArgs {
    /// Change nothing: list the files that would be reformatted and exit with status 1 if
    /// there are any.
    #[arg(long)]
    pub check: bool,
    /// Files or folders to format (default: the current folder). Only `.higraph` files of the
    /// workspace are formatted, minus those `higraph.toml` excludes; files named here are
    /// always formatted.
    #[arg(value_name = "PATH")]
    pub paths: Vec<PathBuf>,
}

/// Arguments of `higraph-lsp explain`.
#[derive(Debug, Args)]
pub(crate) struct ExplainArgs {
    /// A diagnostic code such as HG2105 (any letter case).
    #[arg(value_name = "CODE")]
    pub code: String,
}

/// Arguments of `higraph-lsp render`.
#[derive(Debug, Args)]
pub(crate) struct RenderArgs {
    /// The graph, group or chart to draw (any letter case).
    #[arg(value_name = "NAME")]
    pub name: String,
    /// Output format.
    #[arg(long, value_enum, default_value_t = RenderFormat::Svg)]
    pub format: RenderFormat,
    /// Write to this file instead of standard output.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<std::path::PathBuf>,
    /// A folder of the workspace (default: the current folder); the workspace is found as
    /// `check` finds it.
    #[arg(long, value_name = "DIR")]
    pub dir: Option<std::path::PathBuf>,
    /// Let `-o` replace a file that is not a picture (a source file, or any file whose text
    /// does not start with `<svg`, `<?xml` or `digraph`).
    #[arg(long)]
    pub force: bool,
}

/// The output formats of `render`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum RenderFormat {
    /// a self-contained SVG picture (the default).
    Svg,
    /// Graphviz DOT text.
    Dot,
}

/// Arguments of `higraph-lsp parse`.
#[derive(Debug, Args)]
pub(crate) struct ParseArgs {
    /// The file to parse.
    pub file: PathBuf,
}

/// The output formats of `check` (`tooling.md` §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Format {
    /// rustc-style blocks with the source line underlined (the default).
    Human,
    /// `path:line:col: severity[CODE]: message`, one line per diagnostic.
    Short,
    /// one JSON object with positions in UTF-16 units (described in docs/ci.md).
    Json,
    /// GitHub Actions workflow commands (`::error file=…`).
    Github,
    /// a SARIF 2.1.0 log (one run), e.g. for GitHub code scanning.
    Sarif,
}

/// What `--deny` can turn into failures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Deny {
    /// warnings make the exit status 1, like errors.
    Warnings,
}

/// When to colour output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ColorChoice {
    /// colour when standard output is a terminal and `NO_COLOR` is not set.
    Auto,
    /// always colour.
    Always,
    /// never colour.
    Never,
}

/// A problem that stops a command: bad arguments or unreadable input (exit status 2).
#[derive(Debug)]
pub(crate) struct CliError {
    message: String,
}

impl CliError {
    pub(crate) fn new(message: impl Into<String>) -> CliError {
        CliError {
            message: message.into(),
        }
    }
}

impl From<WorkspaceError> for CliError {
    fn from(error: WorkspaceError) -> CliError {
        CliError::new(error.to_string())
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

/// What `higraph-lsp` without a command says on stderr when its input is a terminal.
const TERMINAL_NOTICE: &str = "\
higraph-lsp: this is the HiGraph language server. It speaks the Language Server Protocol on
stdin/stdout and is meant to be started by an editor. Run `higraph-lsp --help` for the
commands (check, fmt, render, explain, ...). Press Ctrl+D or Ctrl+C to stop.
";

/// Parses the command line and runs the command.
pub fn run() -> ExitCode {
    // clap prints its own usage errors and exits with status 2; `--help` and `--version`
    // exit with 0.
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Check(args)) => check::run(&args),
        Some(Command::Parse(args)) => parse::run(&args),
        Some(Command::Fmt(args)) => fmt_command::run(&args),
        Some(Command::Explain(args)) => explain::run(&args),
        Some(Command::Render(args)) => render::run(&args),
        Some(Command::Test(args)) => test::run(&args),
        Some(Command::Build(args)) => build::run(&args),
        Some(Command::Import(args)) => import::run(&args),
        Some(Command::Lsp(_)) | None => {
            // Someone typed `higraph-lsp` in a terminal: say what this is. The server still
            // runs (an editor never starts it on a terminal).
            if io::stdin().is_terminal() {
                let _ = io::stderr().write_all(TERMINAL_NOTICE.as_bytes());
            }
            Ok(crate::server::run())
        }
    };
    match result {
        Ok(status) => status,
        Err(error) => {
            let _ = writeln!(io::stderr(), "error: {error}");
            ExitCode::from(EXIT_USAGE)
        }
    }
}

/// Writes to standard output. A closed pipe (`higraph-lsp check | head`) is not an error
/// worth a message; anything else is reported.
pub(crate) fn write_stdout(bytes: &[u8]) -> Result<(), CliError> {
    let mut stdout = io::stdout().lock();
    match stdout.write_all(bytes).and_then(|()| stdout.flush()) {
        Ok(()) => Ok(()),
        Err(error) if error.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(error) => Err(CliError::new(format!(
            "cannot write to standard output: {error}"
        ))),
    }
}

pub(crate) use crate::workspace::io_reason;
