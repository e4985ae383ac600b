//! Find all references (go to usage): every use of the definition under the cursor across
//! the whole workspace — instructions, time values, CALL actuals, actual parameters (both
//! sides), message targets, transition endpoints, jump and loop targets — with or without its
//! declaration. Files need not be open: everything is in the database.

use super::{FilePosition, FileRange, defs};
use crate::{Analysis, Cancellable};

impl Analysis {
    /// The references of the name at `pos` in workspace order (the declaration first when
    /// `include_declaration`). Empty when the position names nothing.
    pub fn references(
        &self,
        pos: &FilePosition,
        include_declaration: bool,
    ) -> Cancellable<Vec<FileRange>> {
        self.with_db(|db, ws| {
            let Some(file) = self.file(&pos.path) else {
                return Vec::new();
            };
            let Some(at) = defs::definition_at(db, ws, file, pos.offset) else {
                return Vec::new();
            };
            let mut out: Vec<FileRange> = Vec::new();
            for reference in defs::references(db, ws, &at.definition) {
                if !include_declaration && reference.kind == defs::ReferenceKind::Declaration {
                    continue;
                }
                let range = FileRange {
                    path: reference.file.path(db).clone(),
                    range: reference.range,
                };
                if !out.contains(&range) {
                    out.push(range);
                }
            }
            out
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::ide::fixture;

    /// Renders the references as `path 'text'` lines, each with its line for context.
    fn check(text: &str, include_declaration: bool) -> String {
        let f = fixture::load(text);
        let refs = f
            .host
            .analysis()
            .references(&f.position, include_declaration)
            .unwrap_or_default();
        refs.iter()
            .map(|r| {
                let text = f.text(&r.path);
                let start = usize::from(r.range.start());
                let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
                let line_end = text[start..].find('\n').map_or(text.len(), |i| start + i);
                format!(
                    "{} '{}' in `{}`",
                    r.path,
                    f.slice(&r.path, r.range),
                    text[line_start..line_end].trim()
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    const MESSAGES: &str = r#"//- graphs/bohren.higraph
graph Bohren <
  in_out < IM_Oben : BOOL msg in; OM_Senken : BOOL msg out; >
  state 0 < C: U IM_Oben; R $0IM_Oben; S OM_Senken; >
  trans any->0 < U INIT_SD; >
>
//- graphs/ventil.higraph
graph Ventil <
  in_out < IM_Ab : BOOL msg in; OM_Oben : BOOL msg out; >
  state 0 < C: S OM_Oben; U IM_Ab; >
  trans any->0 < U INIT_SD; >
>
//- group.higraph
group Bohrmaschine fc FC 1 db DB 1 <
  instance Bohren : Bohren < OM_Senken := Vorschub.IM_Ab; >
  instance Vorschub : Ventil < OM_Oben := Bohren.IM_Oben; >
  instance Vorschub2 : Ventil < OM_Oben := Bohren.IM_Oben; >
>
"#;

    #[test]
    fn message_variables_across_files() {
        insta::assert_snapshot!(check(MESSAGES, true), @"
        graphs/bohren.higraph 'IM_Oben' in `in_out < IM_Oben : BOOL msg in; OM_Senken : BOOL msg out; >`
        graphs/bohren.higraph 'IM_Oben' in `state 0 < C: U IM_Oben; R IM_Oben; S OM_Senken; >`
        graphs/bohren.higraph 'IM_Oben' in `state 0 < C: U IM_Oben; R IM_Oben; S OM_Senken; >`
        group.higraph 'IM_Oben' in `instance Vorschub : Ventil < OM_Oben := Bohren.IM_Oben; >`
        group.higraph 'IM_Oben' in `instance Vorschub2 : Ventil < OM_Oben := Bohren.IM_Oben; >`
        ");
    }

    #[test]
    fn without_the_declaration() {
        insta::assert_snapshot!(check(MESSAGES, false), @"
        graphs/bohren.higraph 'IM_Oben' in `state 0 < C: U IM_Oben; R IM_Oben; S OM_Senken; >`
        graphs/bohren.higraph 'IM_Oben' in `state 0 < C: U IM_Oben; R IM_Oben; S OM_Senken; >`
        group.higraph 'IM_Oben' in `instance Vorschub : Ventil < OM_Oben := Bohren.IM_Oben; >`
        group.higraph 'IM_Oben' in `instance Vorschub2 : Ventil < OM_Oben := Bohren.IM_Oben; >`
        ");
    }

    #[test]
    fn wait_and_supervise_times_are_uses() {
        let text = r#"
graph G <
  in < Dauer : TIME; >
  state 0 < wait Dauer; supervise $0Dauer; >
  trans any->0 < U INIT_SD; >
>
"#;
        insta::assert_snapshot!(check(text, false), @"
        main.higraph 'Dauer' in `state 0 < wait Dauer; supervise Dauer; >`
        main.higraph 'Dauer' in `state 0 < wait Dauer; supervise Dauer; >`
        ");
    }

    #[test]
    fn nothing_at_a_constant() {
        assert_eq!(check("graph G < state 0 < C: L $0T#5S; > >", true), "");
    }
}
