//! Fuzzes the level loader: any bytes (UTF-8 or not) must give a level or a positioned error,
//! never a panic; and any level that loads must save and load back to itself, and through a
//! scene (parents resolved) give its rows back.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use texel_scene::{Level, LevelError};

fuzz_target!(|data: &[u8]| {
    let path = Path::new("fuzz.ron");
    match Level::from_ron_bytes(data, path) {
        Ok(level) => {
            let saved = level.to_ron_string(path).expect("a loaded level is valid");
            let back = Level::from_ron_str(&saved, path).expect("a saved level loads");
            assert_eq!(back, level);
            // Parents resolved into world transforms give the file's local ones back.
            assert_eq!(texel_scene::Scene::from_level(&level).to_level(), level);
        }
        Err(LevelError::Parse { line, column, .. }) => assert!(line >= 1 && column >= 1),
        // A wrong `parent` is found after the whole file is read: named by entity.
        Err(LevelError::Parent { entity, .. }) => assert!(entity < data.len()),
        Err(e) => panic!("unexpected error kind: {e}"),
    }
});
