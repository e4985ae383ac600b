//! How the cost of each command grows with its input: for every family of inputs that once
//! cost more than linear time, the size doubles three times and each size is timed (best of a
//! few runs). The table shows the times and the growth per doubling; linear cost gives about
//! 2×, the target is at most 2.3×.
//!
//! ```text
//! cargo build --release -p higraph-lsp
//! cargo run --release -p higraph-lsp --example scaling [-- --runs 3 --family NAME --server PATH]
//! ```
//!
//! The inputs come from `higraph_workload::scaling`. The commands run the release binary (by
//! default `target/release/higraph-lsp`, honouring `CARGO_TARGET_DIR`) on files written to a
//! temporary folder, so a time includes starting the process, reading and printing; writing
//! the inputs is not timed. "One keystroke" runs in process: an `AnalysisHost` holds the big
//! file, and the time is that of one edit inside one of its items plus all diagnostics.
//!
//! Times are CPU time (user + system) of the command, or of the measuring thread for the
//! keystroke, where the platform reports it (Unix), else wall-clock time: on a machine shared
//! with other work the wall-clock time measures the other work as much as ours.
//!
//! `--count` measures executed instructions instead of time, with Valgrind (which must be
//! installed): `cachegrind` without cache simulation counts a command's instructions, and the
//! keystroke runs in a child process under `callgrind` that counts only the measured edit
//! (`--toggle-collect`). Counts do not depend on the machine's load or caches, so their growth
//! per doubling is the cost of the algorithms alone; runs take about 50 times longer.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use higraph_analysis::{AnalysisHost, FileContents, TextRange, TextSize, WorkspaceData};
use higraph_syntax::Edit;
use higraph_workload::scaling;

/// The most a doubling may cost.
const TARGET: f64 = 2.3;

struct Options {
    runs: usize,
    family: Option<String>,
    server: PathBuf,
    /// Count instructions with Valgrind instead of timing.
    count: bool,
}

/// What is run for one size, after its input has been written.
enum Job {
    /// The binary with these arguments, in this folder.
    Command { dir: PathBuf, args: Vec<String> },
    /// One keystroke in a file of the host.
    Keystroke(Keystroke),
}

/// A big file in a host, edited back and forth at one place.
struct Keystroke {
    host: Box<AnalysisHost>,
    path: String,
    at: TextSize,
    round: usize,
}

/// The keystroke family's input of size `n`, loaded and analysed once.
fn keystroke(n: usize) -> Result<Keystroke, String> {
    let text = scaling::items_in_one_file(n);
    // Inside the transition of the graph in the middle: `UN Start` ↔ `UX Start`.
    let middle = scaling::small_graph(n / 2);
    let item = text.find(&middle).ok_or("no middle graph")?;
    let at = item + middle.find("UN Start").ok_or("no UN")? + 1;
    let mut host = AnalysisHost::new();
    let path = "items.higraph".to_owned();
    host.load(WorkspaceData {
        files: vec![(path.clone(), FileContents::Text(text))],
        ..WorkspaceData::default()
    });
    host.analysis().diagnostics();
    Ok(Keystroke {
        host: Box::new(host),
        path,
        at: TextSize::from(at as u32),
        round: 0,
    })
}

impl Keystroke {
    /// One edit and all diagnostics after it; checks that the edit took effect.
    fn press(&mut self) -> Result<(), String> {
        self.round += 1;
        let edit = Edit {
            delete: TextRange::at(self.at, TextSize::from(1)),
            insert: if self.round % 2 == 1 { "X" } else { "N" }.to_owned(),
        };
        self.host
            .apply_edits(&self.path, &[edit])
            .ok_or("the analysis refused the edit")?;
        let diagnostics = self.host.analysis().diagnostics();
        let count: usize = diagnostics.iter().map(|(_, d)| d.len()).sum();
        if (self.round % 2 == 1) != (count > 0) {
            return Err(format!("round {}: {count} diagnostics", self.round));
        }
        Ok(())
    }
}

/// The keystroke counted by `callgrind --toggle-collect` in `--keystroke-child` (never
/// inlined, so that the tool sees the function).
#[inline(never)]
fn measured_keystroke(keystroke: &mut Keystroke) -> Result<(), String> {
    keystroke.press()
}

struct Family {
    name: &'static str,
    /// What `n` counts.
    unit: &'static str,
    sizes: [usize; 4],
    /// Writes the input of size `n` into the folder and says what to run.
    prepare: fn(usize, &Path) -> Result<Job, String>,
}

const KEYSTROKE_SIZES: [usize; 4] = [6_000, 12_000, 24_000, 48_000];

fn families() -> Vec<Family> {
    vec![
        Family {
            name: "items in one file (check)",
            unit: "graphs",
            sizes: [6_000, 12_000, 24_000, 48_000],
            prepare: |n, dir| {
                write(dir, "items.higraph", &scaling::items_in_one_file(n))?;
                Ok(check(dir))
            },
        },
        Family {
            name: "files in a workspace (check)",
            unit: "files",
            sizes: [2_500, 5_000, 10_000, 20_000],
            prepare: |n, dir| {
                for (path, text) in scaling::files_in_workspace(n) {
                    write(dir, &path, &text)?;
                }
                Ok(check(dir))
            },
        },
        Family {
            name: "unused declared symbols (check)",
            unit: "symbols",
            sizes: [2_500, 5_000, 10_000, 20_000],
            prepare: |n, dir| {
                write(dir, "symbols.higraph", &scaling::unused_symbols(n))?;
                Ok(check(dir))
            },
        },
        Family {
            // The indented file grows with the square of the depth: the file doubles from
            // one size to the next.
            name: "nested `alt` branches (fmt --check, 50 charts; the file doubles)",
            unit: "levels",
            sizes: [16, 24, 36, 52],
            prepare: |n, dir| {
                write(dir, "alt.higraph", &scaling::nested_alt(50, n))?;
                Ok(Job::Command {
                    dir: dir.to_owned(),
                    args: vec!["fmt".into(), "--check".into(), ".".into()],
                })
            },
        },
        Family {
            name: "errors on one line (check, human output)",
            unit: "errors",
            sizes: [2_000, 4_000, 8_000, 16_000],
            prepare: |n, dir| {
                write(dir, "line.higraph", &scaling::errors_on_one_line(n))?;
                Ok(check(dir))
            },
        },
        Family {
            name: "chart of a chain of steps (render SVG)",
            unit: "steps",
            sizes: [2_000, 4_000, 8_000, 16_000],
            prepare: |n, dir| {
                write(dir, "chain.higraph", &scaling::chart_chain(n))?;
                Ok(render(dir, "Chain"))
            },
        },
        Family {
            name: "graph of a chain of states (render SVG)",
            unit: "states",
            sizes: [2_000, 4_000, 8_000, 16_000],
            prepare: |n, dir| {
                write(dir, "chain.higraph", &scaling::graph_chain(n))?;
                Ok(render(dir, "Chain"))
            },
        },
        Family {
            name: "group of a chain of instances (render SVG)",
            unit: "instances",
            sizes: [1_000, 2_000, 4_000, 8_000],
            prepare: |n, dir| {
                write(dir, "group.higraph", &scaling::group_chain(n))?;
                Ok(render(dir, "Line"))
            },
        },
        Family {
            name: "one keystroke in a big file (in process)",
            unit: "graphs",
            sizes: KEYSTROKE_SIZES,
            prepare: |n, _| Ok(Job::Keystroke(keystroke(n)?)),
        },
        Family {
            name: "parentheses in a chart condition (check)",
            unit: "pairs",
            sizes: [2_500, 5_000, 10_000, 20_000],
            prepare: |n, dir| {
                write(dir, "parens.higraph", &scaling::nested_parens(n))?;
                Ok(check(dir))
            },
        },
        Family {
            name: "`not` chain in a chart condition (check)",
            unit: "nots",
            sizes: [2_500, 5_000, 10_000, 20_000],
            prepare: |n, dir| {
                write(dir, "not.higraph", &scaling::not_chain(n))?;
                Ok(check(dir))
            },
        },
    ]
}

fn check(dir: &Path) -> Job {
    Job::Command {
        dir: dir.to_owned(),
        args: vec!["check".into(), ".".into()],
    }
}

fn render(dir: &Path, name: &str) -> Job {
    Job::Command {
        dir: dir.to_owned(),
        args: vec!["render".into(), name.into(), "--dir".into(), ".".into()],
    }
}

fn write(dir: &Path, path: &str, text: &str) -> Result<(), String> {
    let path = dir.join(path);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
    }
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
}

impl Job {
    /// Runs once and returns the time it took.
    fn run(&mut self, server: &Path) -> Result<Duration, String> {
        match self {
            Job::Command { dir, args } => {
                let start = Clock::children();
                let output = Command::new(server)
                    .args(args.iter())
                    .current_dir(&*dir)
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .output()
                    .map_err(|e| format!("{}: {e}", server.display()))?;
                let elapsed = start.elapsed();
                let status = output.status;
                // 0 and 1 are results (clean, findings); anything else is a failure, and so
                // is a file `fmt` leaves alone (it would not have been formatted at all).
                let stderr = String::from_utf8_lossy(&output.stderr);
                match status.code() {
                    _ if stderr.contains("left unchanged") => {
                        Err(format!("`{}`: {}", args.join(" "), stderr.trim()))
                    }
                    Some(0 | 1) => Ok(elapsed),
                    _ => Err(format!("`{}` ended with {status}", args.join(" "))),
                }
            }
            Job::Keystroke(keystroke) => {
                let start = Clock::thread();
                keystroke.press()?;
                Ok(start.elapsed())
            }
        }
    }

    /// Runs once under Valgrind and returns the number of instructions executed.
    fn count(&self, server: &Path, n: usize) -> Result<u64, String> {
        match self {
            Job::Command { dir, args } => {
                let output = Command::new("valgrind")
                    .args([
                        "--tool=cachegrind",
                        "--cache-sim=no",
                        "--cachegrind-out-file=/dev/null",
                    ])
                    .arg(server)
                    .args(args.iter())
                    .current_dir(dir)
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .output()
                    .map_err(|e| format!("valgrind: {e} (is Valgrind installed?)"))?;
                valgrind_total(&output.stderr, "I   refs:")
                    .or_else(|| valgrind_total(&output.stderr, "I refs:"))
                    .ok_or_else(|| {
                        format!("`{}`: no instruction count from cachegrind", args.join(" "))
                    })
            }
            Job::Keystroke(_) => {
                let exe = std::env::current_exe().map_err(|e| e.to_string())?;
                let output = Command::new("valgrind")
                    .args([
                        "--tool=callgrind",
                        "--collect-atstart=no",
                        "--toggle-collect=*measured_keystroke*",
                        "--callgrind-out-file=/dev/null",
                    ])
                    .arg(exe)
                    .args(["--keystroke-child", &n.to_string()])
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .output()
                    .map_err(|e| format!("valgrind: {e} (is Valgrind installed?)"))?;
                if !output.status.success() {
                    return Err(format!(
                        "the keystroke child failed: {}",
                        String::from_utf8_lossy(&output.stderr).trim()
                    ));
                }
                valgrind_total(&output.stderr, "Collected :")
                    .ok_or_else(|| "no instruction count from callgrind".to_owned())
            }
        }
    }
}

/// The number after `label` in Valgrind's summary (`==123== I   refs:      1,234,567`).
fn valgrind_total(stderr: &[u8], label: &str) -> Option<u64> {
    let text = String::from_utf8_lossy(stderr);
    let line = text.lines().rev().find(|l| l.contains(label))?;
    let digits: String = line[line.find(label)? + label.len()..]
        .chars()
        .filter(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// `--keystroke-child N`: loads the keystroke input, warms it with one edit, then makes the
/// one edit that `callgrind` counts.
fn keystroke_child(n: &str) -> Result<(), String> {
    let n: usize = n.parse().map_err(|e| format!("--keystroke-child: {e}"))?;
    let mut keystroke = keystroke(n)?;
    keystroke.press()?;
    measured_keystroke(&mut keystroke)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let [_, flag, n] = args.as_slice()
        && flag == "--keystroke-child"
    {
        if let Err(message) = keystroke_child(n) {
            eprintln!("error: {message}");
            std::process::exit(1);
        }
        return;
    }
    let options = match options() {
        Ok(options) => options,
        Err(message) => {
            eprintln!("error: {message}");
            eprintln!("usage: scaling [--runs N] [--family NAME] [--server PATH] [--count]");
            std::process::exit(2);
        }
    };
    if !options.server.is_file() {
        eprintln!(
            "error: no server binary at {} (cargo build --release -p higraph-lsp)",
            options.server.display()
        );
        std::process::exit(2);
    }
    println!(
        "| Family | n (1×, 2×, 4×, 8×) | 1× | 2× | 4× | 8× | growth per doubling |\n\
         |---|---|--:|--:|--:|--:|---|"
    );
    let mut worst: f64 = 0.0;
    for family in families() {
        if options
            .family
            .as_ref()
            .is_some_and(|f| !family.name.contains(f.as_str()))
        {
            continue;
        }
        match measure(&family, &options) {
            Ok(costs) => {
                let ratios: Vec<f64> = costs
                    .windows(2)
                    .map(|w| w[1].value() / w[0].value().max(1e-9))
                    .collect();
                worst = ratios.iter().copied().fold(worst, f64::max);
                let sizes: Vec<String> = family.sizes.iter().map(|n| n.to_string()).collect();
                let cells: Vec<String> = costs.iter().map(Cost::to_string).collect();
                let growth: Vec<String> = ratios.iter().map(|r| format!("{r:.2}×")).collect();
                println!(
                    "| {} | {} {} | {} | {} |",
                    family.name,
                    sizes.join(", "),
                    family.unit,
                    cells.join(" | "),
                    growth.join(", ")
                );
            }
            Err(message) => println!("| {} | | failed: {message} | | | | |", family.name),
        }
    }
    println!();
    println!("Largest growth per doubling: {worst:.2}× (target ≤ {TARGET}×).");
}

/// What one size cost: the best time, or the instruction count.
#[derive(Clone, Copy)]
enum Cost {
    Time(Duration),
    Instructions(u64),
}

impl Cost {
    fn value(self) -> f64 {
        match self {
            Cost::Time(t) => t.as_secs_f64(),
            Cost::Instructions(n) => n as f64,
        }
    }
}

impl std::fmt::Display for Cost {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Cost::Time(t) => f.write_str(&seconds(t)),
            Cost::Instructions(n) => write!(f, "{:.1} M", n as f64 / 1e6),
        }
    }
}

/// The cost of each size.
fn measure(family: &Family, options: &Options) -> Result<Vec<Cost>, String> {
    let mut costs = Vec::new();
    for &n in &family.sizes {
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        let mut job = (family.prepare)(n, dir.path())?;
        if options.count {
            costs.push(Cost::Instructions(job.count(&options.server, n)?));
            continue;
        }
        // One untimed run warms the file cache (and, in process, the first revision).
        job.run(&options.server)?;
        // A keystroke takes milliseconds: more runs make its best time steady.
        let runs = match job {
            Job::Keystroke { .. } => options.runs.max(10),
            Job::Command { .. } => options.runs,
        };
        let mut best = Duration::MAX;
        for _ in 0..runs {
            best = best.min(job.run(&options.server)?);
        }
        costs.push(Cost::Time(best));
    }
    Ok(costs)
}

/// A start time: CPU time of the waited-for children or of this thread where the platform
/// reports it, else the wall clock.
enum Clock {
    #[cfg(unix)]
    Children(Duration),
    #[cfg(unix)]
    Thread(Duration),
    #[cfg_attr(unix, allow(dead_code))]
    Wall(Instant),
}

impl Clock {
    #[cfg(unix)]
    fn children() -> Clock {
        Clock::Children(children_cpu())
    }

    #[cfg(unix)]
    fn thread() -> Clock {
        Clock::Thread(thread_cpu())
    }

    #[cfg(not(unix))]
    fn children() -> Clock {
        Clock::Wall(Instant::now())
    }

    #[cfg(not(unix))]
    fn thread() -> Clock {
        Clock::Wall(Instant::now())
    }

    fn elapsed(&self) -> Duration {
        match self {
            #[cfg(unix)]
            Clock::Children(start) => children_cpu().saturating_sub(*start),
            #[cfg(unix)]
            Clock::Thread(start) => thread_cpu().saturating_sub(*start),
            Clock::Wall(start) => start.elapsed(),
        }
    }
}

/// User + system time of every child process waited for so far.
#[cfg(unix)]
fn children_cpu() -> Duration {
    // SAFETY: `getrusage` only writes the `rusage` it is given.
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage);
        usage
    };
    let time = |t: libc::timeval| {
        Duration::from_secs(t.tv_sec.max(0) as u64) + Duration::from_micros(t.tv_usec.max(0) as u64)
    };
    time(usage.ru_utime) + time(usage.ru_stime)
}

/// CPU time of the calling thread.
#[cfg(unix)]
fn thread_cpu() -> Duration {
    // SAFETY: `clock_gettime` only writes the `timespec` it is given.
    let time = unsafe {
        let mut time: libc::timespec = std::mem::zeroed();
        libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut time);
        time
    };
    Duration::from_secs(time.tv_sec.max(0) as u64)
        + Duration::from_nanos(time.tv_nsec.max(0) as u64)
}

fn seconds(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s < 1.0 {
        format!("{:.0} ms", s * 1000.0)
    } else {
        format!("{s:.2} s")
    }
}

fn options() -> Result<Options, String> {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target"));
    let mut options = Options {
        runs: 3,
        family: None,
        server: target.join("release/higraph-lsp"),
        count: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = || args.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--runs" => {
                options.runs = value()?.parse().map_err(|e| format!("--runs: {e}"))?;
                if options.runs == 0 {
                    return Err("--runs must be at least 1".into());
                }
            }
            "--family" => options.family = Some(value()?),
            "--server" => options.server = PathBuf::from(value()?),
            "--count" => options.count = true,
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(options)
}
