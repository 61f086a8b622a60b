//! Entities on the system clipboard: the copied rows as the text of a level holding just
//! them (canonical RON, so another editor, a text editor or a level file takes them), read
//! back with the level loader's checks, so text that is not entities is refused with the
//! loader's message (line and column) and changes nothing.

use std::path::Path;

use texel_scene::{EntityRow, Level};

/// The first line of copied text, saying what it is.
const HEADER: &str = "// Texel entities, copied from the editor: paste them into a Texel editor.\n";
/// How pasted text is named in messages.
const NAME: &str = "clipboard";

/// The text copied for `rows`, or why they cannot be written (a value a level refuses).
pub fn to_text(rows: Vec<EntityRow>) -> Result<String, String> {
    let level = Level {
        entities: rows,
        ..Level::default()
    };
    let text = level
        .to_ron_string(Path::new(NAME))
        .map_err(|e| e.to_string())?;
    Ok(format!("{HEADER}{text}"))
}

/// The entities `text` holds: copied entities or a whole level's. Anything else is an error
/// for people: what the clipboard holds and where the loader stopped.
pub fn from_text(text: &str) -> Result<Vec<EntityRow>, String> {
    let refuse = |why: String| format!("the clipboard holds no Texel entities ({why})");
    if text.trim().is_empty() {
        return Err(refuse("it is empty".into()));
    }
    let level = Level::from_ron_str(text, Path::new(NAME)).map_err(|e| refuse(e.to_string()))?;
    if level.entities.is_empty() {
        return Err(refuse("a level with no entities".into()));
    }
    Ok(level.entities)
}

#[cfg(test)]
mod tests {
    use super::*;
    use texel_scene::{Name, Transform};

    #[test]
    fn rows_round_trip_and_other_text_is_refused() {
        let level_path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/levels/stone_circle.ron");
        let rows = Level::load(&level_path).expect("stone_circle").entities;
        let text = to_text(rows.clone()).expect("text");
        assert!(text.starts_with("//"));
        assert_eq!(from_text(&text).expect("rows"), rows);
        let one = EntityRow {
            name: Some(Name("a".into())),
            transform: Some(Transform::default()),
            ..EntityRow::default()
        };
        assert_eq!(
            from_text(&to_text(vec![one.clone()]).expect("text")),
            Ok(vec![one])
        );
        for bad in [
            "",
            "hello",
            "(version: 1, entities: [(nme: \"x\")])",
            "[1, 2]",
        ] {
            let e = from_text(bad).expect_err(bad);
            assert!(
                e.starts_with("the clipboard holds no Texel entities"),
                "{e}"
            );
        }
    }
}
