//! Times `parse` on a file: `cargo run --release --example time -- FILE [N]`.
fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("path");
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(20);
    let text = std::fs::read_to_string(path).expect("read");
    let start = std::time::Instant::now();
    let mut errors = 0;
    for _ in 0..n {
        errors += higraph_syntax::parse(&text).errors().len();
    }
    let per = start.elapsed() / n as u32;
    let mb = text.len() as f64 / 1e6;
    println!(
        "{per:?} per parse, {:.1} MB/s, {errors} errors",
        mb / per.as_secs_f64()
    );
}
