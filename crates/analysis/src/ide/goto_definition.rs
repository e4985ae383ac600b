//! Go to definition: from any use to its declaration — an operand to its variable or symbol,
//! a transition endpoint to its state, `instance X : G` to graph `G`, the formal of an actual
//! to the formal's declaration, `Inst.Msg` to the message variable, a jump or loop target to
//! its step, a CALL target to the symbol and the block's interface. On a declaration it goes
//! to the declaration itself. Predefined variables have no declaration to go to.

use super::{
    FilePosition, NavigationTarget,
    defs::{self, Declaration},
};
use crate::{Analysis, Cancellable};

impl Analysis {
    /// The declarations the name at `pos` refers to (usually one; a symbolic CALL target also
    /// gives the callee's `block` interface).
    pub fn goto_definition(&self, pos: &FilePosition) -> Cancellable<Vec<NavigationTarget>> {
        self.with_db(|db, ws| {
            let Some(file) = self.file(&pos.path) else {
                return Vec::new();
            };
            let mut targets: Vec<NavigationTarget> = Vec::new();
            for at in defs::definitions_at(db, ws, file, pos.offset) {
                let Some(decl) = defs::declaration(db, ws, &at.definition) else {
                    continue;
                };
                let target = navigation_target(db, decl);
                if !targets.contains(&target) {
                    targets.push(target);
                }
            }
            targets
        })
    }
}

/// A declaration as a navigation target.
pub(crate) fn navigation_target(db: &dyn salsa::Database, decl: Declaration) -> NavigationTarget {
    NavigationTarget {
        path: decl.file.path(db).clone(),
        full_range: decl.full_range,
        focus_range: decl.focus_range,
        name: decl.name,
        kind: decl.kind,
    }
}

#[cfg(test)]
mod tests {
    use crate::ide::fixture;

    /// Renders the targets as `path: 'focus' (kind)`.
    fn check(text: &str) -> String {
        let f = fixture::load(text);
        let targets = f
            .host
            .analysis()
            .goto_definition(&f.position)
            .unwrap_or_default();
        targets
            .iter()
            .map(|t| {
                format!(
                    "{}: '{}' in '{}' ({:?})",
                    t.path,
                    f.slice(&t.path, t.focus_range),
                    f.slice(&t.path, t.full_range),
                    t.kind
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    const WORKSPACE: &str = r#"//- a.higraph
graph Ventil <
  in < Oben : BOOL; >
  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
  state 0 < C: U Oben; U "Taster"; U #IM_Ab; >
  state 1 "Oben" fault < >
  trans any->0 < U INIT_SD; >
  trans 0->1 < U Oben; >
>
//- b.higraph
group Anlage fc FC 1 db DB 1 <
  instance V1 : Ventil < Oben := Taster; OM_Oben := V2.IM_Ab; >
  instance V2 : Ventil < >
>
symbols < Taster : E 0.0 BOOL "start"; >
chart Mischer <
  sequencer S <
    step A < >
    trans T < Taster; >
    step B < >
    loop L -> A < TRUE; >
  >
>
//- t.higraph
test T <
  run Anlage, Mischer;
  set V1.Oben := TRUE;
  expect Mischer.S.A and V2.IM_Ab and Taster;
  command Mischer start;
  confirm Mischer.B;
>
"#;

    fn at(needle: &str, path: &str) -> String {
        let marker = format!("//- {path}\n");
        let start = WORKSPACE.find(&marker).map_or(0, |i| i + marker.len());
        let at = WORKSPACE[start..].find(needle).map_or(start, |i| start + i);
        check(&format!("{}$0{}", &WORKSPACE[..at], &WORKSPACE[at..]))
    }

    #[test]
    fn operands_go_to_variables_and_symbols() {
        assert_eq!(
            at("Oben; U \"", "a.higraph"),
            "a.higraph: 'Oben' in 'Oben : BOOL;' (Variable)"
        );
        assert_eq!(
            at("Taster\"; U", "a.higraph"),
            "b.higraph: 'Taster' in 'Taster : E 0.0 BOOL \"start\";' (Symbol)"
        );
        assert_eq!(
            at("IM_Ab; >\n  state 1", "a.higraph"),
            "a.higraph: 'IM_Ab' in 'IM_Ab : BOOL msg in;' (Message)"
        );
    }

    #[test]
    fn endpoints_go_to_states() {
        assert_eq!(
            at("1 < U Oben", "a.higraph"),
            "a.higraph: '1' in 'state 1 \"Oben\" fault < >' (State)"
        );
    }

    #[test]
    fn group_names_go_to_graphs_formals_and_messages() {
        assert_eq!(
            at("Ventil < Oben", "b.higraph"),
            "a.higraph: 'Ventil' in 'graph Ventil <\n  in < Oben : BOOL; >\n  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >\n  state 0 < C: U Oben; U \"Taster\"; U #IM_Ab; >\n  state 1 \"Oben\" fault < >\n  trans any->0 < U INIT_SD; >\n  trans 0->1 < U Oben; >\n>' (Graph)"
        );
        assert_eq!(
            at("Oben := Taster", "b.higraph"),
            "a.higraph: 'Oben' in 'Oben : BOOL;' (Variable)"
        );
        assert_eq!(
            at("IM_Ab; >", "b.higraph"),
            "a.higraph: 'IM_Ab' in 'IM_Ab : BOOL msg in;' (Message)"
        );
        assert_eq!(
            at("V2.IM_Ab", "b.higraph"),
            "b.higraph: 'V2' in 'instance V2 : Ventil < >' (Instance)"
        );
        assert_eq!(
            at("Taster; OM", "b.higraph"),
            "b.higraph: 'Taster' in 'Taster : E 0.0 BOOL \"start\";' (Symbol)"
        );
    }

    #[test]
    fn loop_targets_go_to_steps() {
        assert_eq!(
            at("A < TRUE", "b.higraph"),
            "b.higraph: 'A' in 'step A < >' (Step)"
        );
    }

    #[test]
    fn calls_go_to_the_symbol_and_the_interface() {
        let text = r#"//- a.higraph
graph G <
  state 0 < C: CALL "Do$0sieren" (Menge := MW 2); >
  trans any->0 < U INIT_SD; >
>
block "Dosieren" < in < Menge : INT; > >
symbols < Dosieren : FC 10; >
"#;
        assert_eq!(
            check(text),
            "a.higraph: 'Dosieren' in 'Dosieren : FC 10;' (Symbol)\n\
             a.higraph: '\"Dosieren\"' in 'block \"Dosieren\" < in < Menge : INT; > >' (BlockInterface)"
        );
    }

    #[test]
    fn test_paths_and_run_entries_go_to_declarations() {
        assert_eq!(
            at("Anlage,", "t.higraph"),
            "b.higraph: 'Anlage' in 'group Anlage fc FC 1 db DB 1 <\n  instance V1 : Ventil < Oben := Taster; OM_Oben := V2.IM_Ab; >\n  instance V2 : Ventil < >\n>' (Group)"
        );
        assert_eq!(
            at("V1.Oben", "t.higraph"),
            "b.higraph: 'V1' in 'instance V1 : Ventil < Oben := Taster; OM_Oben := V2.IM_Ab; >' (Instance)"
        );
        assert_eq!(
            at("Oben :=", "t.higraph"),
            "a.higraph: 'Oben' in 'Oben : BOOL;' (Variable)"
        );
        assert_eq!(
            at("IM_Ab and", "t.higraph"),
            "a.higraph: 'IM_Ab' in 'IM_Ab : BOOL msg in;' (Message)"
        );
        assert_eq!(
            at("S.A", "t.higraph"),
            "b.higraph: 'S' in 'sequencer S <\n    step A < >\n    trans T < Taster; >\n    step B < >\n    loop L -> A < TRUE; >\n  >' (Sequencer)"
        );
        assert_eq!(
            at("A and", "t.higraph"),
            "b.higraph: 'A' in 'step A < >' (Step)"
        );
        assert_eq!(
            at("Taster;", "t.higraph"),
            "b.higraph: 'Taster' in 'Taster : E 0.0 BOOL \"start\";' (Symbol)"
        );
        assert_eq!(
            at("Mischer start", "t.higraph")
                .lines()
                .next()
                .unwrap_or(""),
            "b.higraph: 'Mischer' in 'chart Mischer <"
        );
        assert_eq!(
            at("B;", "t.higraph"),
            "b.higraph: 'B' in 'step B < >' (Step)"
        );
        // `start` is a command, no name.
        assert_eq!(at("start;", "t.higraph"), "");
    }

    #[test]
    fn predefined_variables_and_keywords_go_nowhere() {
        assert_eq!(at("INIT_SD", "a.higraph"), "");
        assert_eq!(at("state 0", "a.higraph"), "");
    }
}
