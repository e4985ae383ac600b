//! Document highlights: the uses of the name under the cursor in the current file, marked
//! Read or Write by their access kind (Appendix E: an operand of `= S R T`, a timer or counter
//! start, an assignment target or a qualifier operand is written; read-write accesses such as
//! `FP` count as writes). The declaration and uses that are no access (endpoints,
//! `instance X : G`, formals, `Inst.` prefixes, jump targets) are plain text.

use higraph_syntax::TextRange;

use super::{
    FilePosition,
    defs::{self, ReferenceKind},
};
use crate::{Analysis, Cancellable};

/// How a highlighted range uses the name (the kinds of LSP's document highlights).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HighlightKind {
    /// A declaration, or a use that neither reads nor writes.
    Text,
    Read,
    Write,
}

impl HighlightKind {
    fn of(kind: ReferenceKind) -> HighlightKind {
        match kind {
            ReferenceKind::Read => HighlightKind::Read,
            ReferenceKind::Write | ReferenceKind::ReadWrite => HighlightKind::Write,
            ReferenceKind::Declaration | ReferenceKind::Unknown | ReferenceKind::Name => {
                HighlightKind::Text
            }
        }
    }
}

impl Analysis {
    /// The references in the file of `pos` to the name at `pos`, in text order.
    pub fn highlights(&self, pos: &FilePosition) -> Cancellable<Vec<(TextRange, HighlightKind)>> {
        self.with_db(|db, ws| {
            let Some(file) = self.file(&pos.path) else {
                return Vec::new();
            };
            let Some(at) = defs::definition_at(db, ws, file, pos.offset) else {
                return Vec::new();
            };
            let mut out: Vec<(TextRange, HighlightKind)> = defs::references(db, ws, &at.definition)
                .into_iter()
                .filter(|r| r.file == file)
                .map(|r| (r.range, HighlightKind::of(r.kind)))
                .collect();
            out.sort_by_key(|(range, _)| range.start());
            out.dedup_by_key(|(range, _)| *range);
            out
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::ide::fixture;

    /// Renders the highlights as `'text' Kind` lines.
    fn check(text: &str) -> String {
        let f = fixture::load(text);
        let highlights = f
            .host
            .analysis()
            .highlights(&f.position)
            .unwrap_or_default();
        highlights
            .iter()
            .map(|(range, kind)| {
                format!(
                    "{:?} '{}' {kind:?}",
                    range,
                    f.slice(&f.position.path, *range)
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    #[test]
    fn test_paths_in_their_file() {
        let text = r#"//- plant.higraph
graph Ventil <
  in < Oben : BOOL; >
  state 0 < C: U Oben; >
  trans any->0 < U INIT_SD; >
>
group Anlage < instance V1 : Ventil < > >
//- tests.higraph
test T <
  run Anlage;
  set V1.$0Oben := TRUE;
  step;
  expect Anlage.V1.Oben;
>
"#;
        insta::assert_snapshot!(check(text), @"
        32..36 'Oben' Write
        73..77 'Oben' Read
        ");
    }

    #[test]
    fn reads_and_writes_in_a_graph() {
        let text = r#"
graph G <
  in < Start : BOOL; >
  stat < Merker : BOOL; Flanke : BOOL; Zeit : TIMER; Zahl : INT; >
  state 0 < C: U Start; = $0Merker; U Merker; S Merker; R Merker; FP Merker; >
  trans any->0 < U INIT_SD; >
>
"#;
        insta::assert_snapshot!(check(text), @"
        43..49 'Merker' Text
        127..133 'Merker' Write
        137..143 'Merker' Read
        147..153 'Merker' Write
        157..163 'Merker' Write
        168..174 'Merker' Write
        ");
    }

    #[test]
    fn timers_loads_and_transfers() {
        let text = r#"
graph G <
  stat < Zeit : TIMER; Zahl : INT; >
  state 0 < C: L S5T#2S; SE $0Zeit; U Zeit; R Zeit; L Zahl; T Zahl; >
  trans any->0 < U INIT_SD; >
>
"#;
        insta::assert_snapshot!(check(text), @"
        20..24 'Zeit' Text
        76..80 'Zeit' Write
        84..88 'Zeit' Read
        92..96 'Zeit' Write
        ");
        let zahl = text.replace("$0Zeit", "Zeit").replace("L Zahl", "L $0Zahl");
        insta::assert_snapshot!(check(&zahl), @"
        34..38 'Zahl' Text
        100..104 'Zahl' Read
        108..112 'Zahl' Write
        ");
    }

    #[test]
    fn chart_assignments_and_qualifiers_write() {
        let text = r#"
chart C <
  in < Pumpe : BOOL; Voll : BOOL; >
  sequencer S <
    start < not $0Pumpe; >
    step A < init < Pumpe := Voll; > N Pumpe; >
    trans T < Pumpe and Voll; >
    step B < >
  >
>
"#;
        insta::assert_snapshot!(check(text), @"
        18..23 'Pumpe' Text
        79..84 'Pumpe' Read
        108..113 'Pumpe' Write
        127..132 'Pumpe' Write
        150..155 'Pumpe' Read
        ");
    }

    #[test]
    fn only_the_current_file() {
        let text = r#"//- a.higraph
graph G < in < $0X : BOOL; > state 0 < C: U X; > trans any->0 < U INIT_SD; > >
//- b.higraph
group Gr fc FC 1 db DB 1 < instance I : G < X := M 0.0; > >
"#;
        insta::assert_snapshot!(check(text), @"
        15..16 'X' Text
        42..43 'X' Read
        ");
    }
}
