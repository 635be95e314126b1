//! The layers of the workspace, read from each crate's `Cargo.toml`: every dependency between
//! the toolkit's crates goes down, never up or sideways between faces.
//!
//! From the bottom: the libraries of the physics (pim-core, pim-crush, pim-runout, pim-fit,
//! pim-reconstruct); the case (pim-case: case files to typed cases); the documents
//! (pim-documents: the typed answers); the studies (pim-studies: one entry per question, a
//! case in, a document out); the rendering (pim-render: tables, reports, figures) and, beside
//! it, the case file on disk (pim-store: read with its version, checked by the studies'
//! check, written atomically under the file's lock; the one crate below the faces that does
//! file I/O, for them); and on top
//! the faces: the scene editor's server (pim-serve), and pim-cli (which serves it with `pim
//! serve`) and pim-py, which import from every layer below and never from each other.

use std::path::Path;

/// Each crate with its layer (0 the bottom).
const LAYERS: [(&str, u8); 13] = [
    ("pim-core", 0),
    ("pim-crush", 1),
    ("pim-runout", 1),
    ("pim-fit", 1),
    ("pim-reconstruct", 2),
    ("pim-case", 3),
    ("pim-documents", 4),
    ("pim-studies", 5),
    ("pim-render", 6),
    ("pim-store", 6),
    ("pim-serve", 7),
    ("pim-cli", 8),
    ("pim-py", 8),
];

/// The toolkit crates a crate's manifest depends on (normal dependencies, not dev).
fn dependencies(krate: &str) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("crates").join(krate).join("Cargo.toml"))
        .unwrap_or_else(|e| panic!("{krate}: {e}"));
    let mut in_deps = false;
    let mut out = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            in_deps = line == "[dependencies]";
            continue;
        }
        if let Some((name, _)) = line.split_once(['=', '.']) {
            let name = name.trim();
            if in_deps && name.starts_with("pim-") {
                out.push(name.to_string());
            }
        }
    }
    out
}

#[test]
fn every_dependency_goes_down_a_layer() {
    let layer = |name: &str| {
        LAYERS
            .iter()
            .find(|(n, _)| *n == name)
            .unwrap_or_else(|| panic!("{name} has no layer: add it to LAYERS"))
            .1
    };
    let mut wrong = Vec::new();
    for (krate, l) in LAYERS {
        for dep in dependencies(krate) {
            if layer(&dep) >= l {
                wrong.push(format!(
                    "{krate} (layer {l}) depends on {dep} (layer {})",
                    layer(&dep)
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn every_crate_of_the_workspace_has_a_layer() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates");
    let mut found: Vec<String> = std::fs::read_dir(root)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("pim-"))
        .collect();
    found.sort();
    let mut listed: Vec<String> = LAYERS.iter().map(|(n, _)| n.to_string()).collect();
    listed.sort();
    assert_eq!(found, listed);
}

#[test]
fn the_faces_stand_on_the_studies() {
    // The command and the Python package answer through the studies, never around them.
    for face in ["pim-cli", "pim-py"] {
        let deps = dependencies(face);
        assert!(deps.iter().any(|d| d == "pim-studies"), "{face}: {deps:?}");
    }
}
