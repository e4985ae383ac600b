//! Times `parse` on a file: `cargo run --release --example time -- FILE [N]`.
//! Prints the fastest and the median of N parses (each including dropping its tree) and the
//! same for a bare logos pass over the same text, with the ratio of the two.
use logos::Logos;

fn stats(mut samples: Vec<std::time::Duration>) -> (std::time::Duration, std::time::Duration) {
    samples.sort();
    (samples[0], samples[samples.len() / 2])
}

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("path");
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(20);
    let text = std::fs::read_to_string(path).expect("read");
    let mut parse = Vec::with_capacity(n);
    let mut logos = Vec::with_capacity(n);
    let mut errors = 0;
    for _ in 0..n {
        let start = std::time::Instant::now();
        errors += higraph_syntax::parse(&text).errors().len();
        parse.push(start.elapsed());
        let start = std::time::Instant::now();
        let mut lexer = higraph_syntax::SyntaxKind::lexer(std::hint::black_box(&text));
        let mut tokens = 0usize;
        while lexer.next().is_some() {
            tokens += 1;
        }
        std::hint::black_box(tokens);
        logos.push(start.elapsed());
    }
    let (p_min, p_med) = stats(parse);
    let (l_min, l_med) = stats(logos);
    println!(
        "parse min {p_min:?} median {p_med:?}; logos min {l_min:?} median {l_med:?}; ratio min {:.2} median {:.2}; {errors} errors",
        p_min.as_secs_f64() / l_min.as_secs_f64(),
        p_med.as_secs_f64() / l_med.as_secs_f64()
    );
}
