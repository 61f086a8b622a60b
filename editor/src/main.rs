//! `texel-editor`: the egui level editor. It is a thin shell for now; the editor issue
//! builds it out on top of `texel_runtime`.

fn main() {
    eprintln!("texel-editor is not built yet; use `texel-run check <level>`");
    std::process::exit(1);
}
