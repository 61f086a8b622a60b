//! Warnings: features a file uses that the importer does not implement but can do without
//! (the mesh still imports), each reported once per file however often it is used.

use std::collections::HashSet;

use gltf::{Document, Primitive};

use super::convert::{Importer, Site};

/// Distinct warnings in the order they were first raised.
#[derive(Debug, Default)]
pub(super) struct Warnings {
    /// What each warning is about: a second warning with a key already seen is dropped, so a
    /// feature used by many primitives or materials is reported once (at its first use).
    keys: HashSet<String>,
    messages: Vec<String>,
}

impl Warnings {
    /// Records `message()` unless a warning about `key` was already recorded.
    pub(super) fn add(&mut self, key: &str, message: impl FnOnce() -> String) {
        if self.keys.insert(key.to_owned()) {
            self.messages.push(message());
        }
    }

    /// The messages, first raised first.
    pub(super) fn into_messages(self) -> Vec<String> {
        self.messages
    }
}

/// `1 thing` or `3 things`.
fn count(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

impl Importer<'_> {
    /// Records a warning (once per `key`).
    pub(super) fn warn(&self, key: &str, message: impl FnOnce() -> String) {
        self.warnings.borrow_mut().add(key, message);
    }

    /// Warnings about the document as a whole: skins, animations, cameras, extensions used.
    pub(super) fn document_warnings(&self, doc: &Document) {
        let root = doc.as_json();
        if !root.skins.is_empty() {
            self.warn("skins", || {
                format!(
                    "{} ignored: skinned meshes are imported unposed, placed by their nodes' \
                     transforms",
                    count(root.skins.len(), "skin")
                )
            });
        }
        if !root.animations.is_empty() {
            self.warn("animations", || {
                format!(
                    "{} ignored: the scene is imported as it stands",
                    count(root.animations.len(), "animation")
                )
            });
        }
        if !root.cameras.is_empty() {
            self.warn("cameras", || {
                format!("{} ignored", count(root.cameras.len(), "camera"))
            });
        }
        for extension in &root.extensions_used {
            self.warn(&format!("extension {extension}"), || {
                match extension.as_str() {
                    "KHR_texture_transform" => "extension KHR_texture_transform ignored: texture \
                                            offsets, rotations and scales are not applied"
                        .to_owned(),
                    other => format!("extension {other} ignored: not implemented"),
                }
            });
        }
    }

    /// Warnings about one primitive's own data: morph targets.
    pub(super) fn primitive_warnings(&self, prim: &Primitive<'_>, site: Site) {
        if prim.morph_targets().len() > 0 {
            self.warn("morph targets", || {
                format!("morph targets ignored (first in {site}): meshes keep their base shape")
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_key_is_reported_once_with_its_first_message() {
        let mut w = Warnings::default();
        w.add("a", || "first a".into());
        w.add("b", || "b".into());
        w.add("a", || unreachable!("a second `a` is not even formatted"));
        assert_eq!(w.into_messages(), ["first a", "b"]);
        assert_eq!(count(1, "skin"), "1 skin");
        assert_eq!(count(2, "skin"), "2 skins");
    }
}
