//! The built page (`web/dist`, made by `npm run build`) goes into the binary, so a release
//! `oficina serve` works anywhere: `page.rs` lists every file with `include_bytes!`. Without a
//! built page the list is empty and the server says how to build it.

use std::path::{Path, PathBuf};

fn files(dir: &Path, base: &Path, out: &mut Vec<(String, PathBuf)>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            files(&p, base, out);
        } else if let Ok(rel) = p.strip_prefix(base) {
            out.push((rel.to_string_lossy().replace('\\', "/"), p));
        }
    }
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let dist = manifest.join("../../web/dist");
    // A folder that does not exist yet makes cargo run this again on every build, so the
    // page is picked up as soon as it is built; once it exists, any change to it does.
    println!("cargo:rerun-if-changed={}", dist.display());
    let mut list = Vec::new();
    if dist.join("index.html").is_file() {
        files(&dist, &dist, &mut list);
    }
    list.sort();
    let mut code = String::from("/// The built page: (path under web/dist, contents).\npub(crate) static PAGE: &[(&str, &[u8])] = &[\n");
    for (rel, path) in &list {
        println!("cargo:rerun-if-changed={}", path.display());
        code += &format!(
            "    ({rel:?}, include_bytes!({:?})),\n",
            path.display().to_string()
        );
    }
    code += "];\n";
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap()).join("page.rs");
    std::fs::write(out, code).unwrap();
}
