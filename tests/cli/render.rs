//! `higraph-lsp render` end to end (`tooling.md` §2, §6).

use crate::support::TempTree;

const VENTIL: &str = "graph Ventil <\n  state 0 < >\n  trans any->0 < U INIT_SD; >\n>\n";

#[test]
fn a_name_several_items_share_is_an_error_naming_them() {
    let tree = TempTree::new();
    tree.file("plc/higraph.toml", "")
        .file("plc/a.higraph", VENTIL)
        .file("plc/sub/b.higraph", format!("// second\n{VENTIL}"))
        .file("plc/c.higraph", "group Anlage <\n>\n");
    let run = tree.run("", &["render", "--dir", "plc", "VENTIL"]);
    assert_eq!(run.status, 2, "{run:?}");
    assert!(run.stdout.is_empty(), "{run:?}");
    // Files are named from the current directory, with the line of each name.
    assert!(
        run.stderr.contains("graph Ventil at plc/a.higraph:1")
            && run.stderr.contains("graph Ventil at plc/sub/b.higraph:2"),
        "{run:?}"
    );
    // A unique name still renders.
    let run = tree.run("plc", &["render", "Anlage", "--format", "dot"]);
    assert_eq!(run.status, 0, "{run:?}");
    assert!(run.stdout.contains("digraph"), "{run:?}");
}
