//! Generators of the scaling families: inputs whose size is one number `n`, for measuring how
//! the cost of a command grows when `n` doubles (`crates/lsp/examples/scaling.rs`) and for
//! tests that count work at two sizes. Each family is a shape of input that once cost more
//! than linear time; every generated text is syntactically valid unless the family is about
//! errors or nesting.

/// One small graph (about 170 bytes), clean for the rules; `i` makes its name unique.
pub fn small_graph(i: usize) -> String {
    format!(
        "graph G{i} <\n  in < Start : BOOL; >\n  state 0 < >\n  state 1 < >\n  \
         trans any->0 < U INIT_SD; >\n  trans 0->1 < U Start; >\n  trans 1->0 < UN Start; >\n>\n"
    )
}

/// Items in one file: `n` small graphs, one after the other.
pub fn items_in_one_file(n: usize) -> String {
    let mut text = String::with_capacity(n * 180);
    for i in 0..n {
        text.push_str(&small_graph(i));
    }
    text
}

/// Files in a workspace: `n` files of one small graph each, as (path, text).
pub fn files_in_workspace(n: usize) -> Vec<(String, String)> {
    (0..n)
        .map(|i| (format!("g{:02}/g{i}.higraph", i % 64), small_graph(i)))
        .collect()
}

/// Unused declared symbols: one `symbols` table of `n` symbols (bit memory, distinct
/// addresses) that nothing uses (each is HG6004).
pub fn unused_symbols(n: usize) -> String {
    let mut text = String::with_capacity(n * 40 + 16);
    text.push_str("symbols <\n");
    for i in 0..n {
        text.push_str(&format!("  S{i} : M {}.{} BOOL;\n", i / 8, i % 8));
    }
    text.push_str(">\n");
    text
}

/// `alt` branches nested `depth` deep in one chart named `C{i}`, indented as `fmt` lays it
/// out (two spaces per `<`), so the text grows with the square of `depth` just as its
/// formatted form does.
pub fn nested_alt_chart(i: usize, depth: usize) -> String {
    let pad = |level: usize| "  ".repeat(level);
    let mut text =
        format!("chart C{i} <\n  sequencer Seq <\n    start < TRUE; >\n    step A < >\n");
    for d in 0..depth {
        let level = 2 + 2 * d;
        text.push_str(&format!(
            "{}alt <\n{}branch <\n{}trans T{d} < TRUE; >\n{}step S{d} < >\n",
            pad(level),
            pad(level + 1),
            pad(level + 2),
            pad(level + 2)
        ));
    }
    text.push_str(&format!("{}trans TE < TRUE; >\n", pad(2 + 2 * depth)));
    for d in (0..depth).rev() {
        let level = 2 + 2 * d;
        text.push_str(&format!(
            "{}>\n{}branch <\n{}trans U{d} < FALSE; >\n{}>\n{}>\n",
            pad(level + 1),
            pad(level + 1),
            pad(level + 2),
            pad(level + 1),
            pad(level)
        ));
    }
    text.push_str("    step B < >\n  >\n>\n");
    text
}

/// `fmt` of nested `alt` branches: `charts` charts whose `alt` branches nest `depth` deep.
/// Each level is indented once more, so the file grows with the square of `depth`; a
/// formatter that re-reads a subtree at every level of it grows faster than the file.
pub fn nested_alt(charts: usize, depth: usize) -> String {
    (0..charts).map(|i| nested_alt_chart(i, depth)).collect()
}

/// Many errors on one line: a graph whose one transition holds `n` statements on a single
/// line, each an operation on an operand nobody declares (one error each).
pub fn errors_on_one_line(n: usize) -> String {
    let mut line = String::with_capacity(n * 10);
    for i in 0..n {
        line.push_str(&format!("U X{i}; "));
    }
    format!(
        "graph Line <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n  trans 0->0 < {line}>\n>\n"
    )
}

/// A chart whose one sequencer is a chain of `n` steps (`n - 1` transitions between them).
pub fn chart_chain(n: usize) -> String {
    let mut text = String::with_capacity(n * 40 + 64);
    text.push_str("chart Chain <\n  sequencer Seq <\n    start < TRUE; >\n");
    for i in 0..n {
        if i > 0 {
            text.push_str(&format!("    trans T{i} < TRUE; >\n"));
        }
        text.push_str(&format!("    step S{i} < >\n"));
    }
    text.push_str("  >\n>\n");
    text
}

/// A graph whose `n` states form a chain (`0->1->…->n-1->0`).
pub fn graph_chain(n: usize) -> String {
    let mut text = String::with_capacity(n * 50 + 64);
    text.push_str("graph Chain <\n  in < Go : BOOL; >\n");
    for i in 0..n {
        text.push_str(&format!("  state {i} < >\n"));
    }
    text.push_str("  trans any->0 < U INIT_SD; >\n");
    for i in 0..n {
        text.push_str(&format!("  trans {i}->{} < U Go; >\n", (i + 1) % n.max(1)));
    }
    text.push_str(">\n");
    text
}

/// A group of `n` instances of one graph, each wired to the next.
pub fn group_chain(n: usize) -> String {
    let mut text = String::from(
        "graph Stage <\n  in_out < IM_Go : BOOL msg in; OM_Go : BOOL msg out; >\n  \
         state 0 < >\n  state 1 < C: S OM_Go; >\n  trans any->0 < U INIT_SD; >\n  \
         trans 0->1 < U IM_Go; !: R IM_Go; >\n>\n\ngroup Line fc FC 1 db DB 1 <\n",
    );
    for i in 0..n {
        text.push_str(&format!(
            "  instance I{i} : Stage < OM_Go := I{}.IM_Go; >\n",
            (i + 1) % n.max(1)
        ));
    }
    text.push_str(">\n");
    text
}

/// A chart condition nested in `n` pairs of parentheses.
pub fn nested_parens(n: usize) -> String {
    format!(
        "chart C <\n  sequencer Seq <\n    start < TRUE; >\n    step A < >\n    trans T < {}x{}; >\n    step B < >\n  >\n>\n",
        "(".repeat(n),
        ")".repeat(n)
    )
}

/// A chart condition that is a chain of `n` `not`s.
pub fn not_chain(n: usize) -> String {
    format!(
        "chart C <\n  sequencer Seq <\n    start < TRUE; >\n    step A < >\n    trans T < {}x; >\n    step B < >\n  >\n>\n",
        "not ".repeat(n)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn valid_families_parse_cleanly() {
        for text in [
            items_in_one_file(3),
            unused_symbols(20),
            nested_alt(2, 3),
            chart_chain(5),
            graph_chain(5),
            group_chain(4),
        ] {
            let parse = higraph_syntax::parse(&text);
            assert!(parse.errors().is_empty(), "{:?}\n{text}", parse.errors());
        }
        for (_, text) in files_in_workspace(3) {
            assert!(higraph_syntax::parse(&text).errors().is_empty());
        }
    }
}
