//! `higraph-gen max-graph|max-group|plant [--seed N] -o DIR`: writes a generated workload.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, ValueEnum};

/// Writes the benchmark workloads of tooling.md §7 (deterministic by seed).
#[derive(Debug, Parser)]
#[command(name = "higraph-gen", version)]
struct Args {
    /// Which workload to generate.
    workload: Workload,
    /// The seed; the same seed always gives the same files.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output folder (created if missing; existing files of the same name are overwritten).
    #[arg(short = 'o', long = "out", value_name = "DIR")]
    out: PathBuf,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum Workload {
    /// One graph at the limits: 255 states, 4090 transitions (`max_graph.higraph`).
    MaxGraph,
    /// A group of 255 instances of 20 graphs, all messages wired.
    MaxGroup,
    /// 300 graphs, 20 groups, 10 charts, a 5000-symbol table, in folders.
    Plant,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let files = match args.workload {
        Workload::MaxGraph => vec![(
            "max_graph.higraph".to_string(),
            higraph_workload::max_graph(args.seed),
        )],
        Workload::MaxGroup => higraph_workload::max_group(args.seed),
        Workload::Plant => higraph_workload::plant(args.seed),
    };
    let mut bytes = 0;
    for (path, text) in &files {
        if let Err(e) = write(&args.out.join(path), text) {
            eprintln!(
                "higraph-gen: cannot write {}: {e}",
                args.out.join(path).display()
            );
            return ExitCode::from(2);
        }
        bytes += text.len();
    }
    eprintln!(
        "wrote {} file(s), {bytes} bytes, to {}",
        files.len(),
        args.out.display()
    );
    ExitCode::SUCCESS
}

fn write(path: &Path, text: &str) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(path, text)
}
