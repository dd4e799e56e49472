//! What the instancer's tests share: the repository's sample shaders loaded and normalized, a
//! pass's text, nodes by their text, and the WGSL round-trip check.
#![allow(dead_code)] // each test module uses part of it

use std::path::{Path, PathBuf};

use reproj_front::{NodeTable, Normalized, Shader, enumerate, load_file, normalize};
use reproj_instance::{InstanceOptions, NodeSelector, PassKind, Strategy, Variant, instance};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `shaders/NAME` loaded, normalized and enumerated.
pub fn load(name: &str) -> (Shader, Normalized, NodeTable) {
    let shader = load_file(&root().join("shaders").join(name)).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    (shader, norm, table)
}

/// The file names of the sample shaders (`shaders/*.wgsl`), sorted.
pub fn samples() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(root().join("shaders"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "wgsl")
                .then(|| p.file_name().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    v.sort();
    v
}

/// Every pass's WGSL is a fixed point of parse → validate → write.
pub fn check_round_trip(v: &Variant) {
    for p in &v.passes {
        let m = naga::front::wgsl::parse_str(&p.wgsl).unwrap();
        let info = reproj_front::validator().validate(&m).unwrap();
        let again = reproj_instance::write_wgsl(&m, &info).unwrap();
        assert_eq!(
            again, p.wgsl,
            "{:?} pass is not a round-trip fixed point",
            p.kind
        );
    }
}

/// The id of the cacheable node whose source text is `text`.
pub fn node_by_text(table: &NodeTable, text: &str) -> u32 {
    table
        .cacheable()
        .find(|n| n.text == text)
        .unwrap_or_else(|| panic!("no cacheable node `{text}`"))
        .id
}

/// The WGSL of the variant's pass of `kind`.
pub fn pass(v: &Variant, kind: PassKind) -> &str {
    &v.passes.iter().find(|p| p.kind == kind).unwrap().wgsl
}

/// The root variant of the WGSL `src` in each strategy (panics naming the strategy that fails).
pub fn root_in_every_strategy(name: &str, src: &str) -> Vec<Variant> {
    let shader = reproj_front::parse_shader(Path::new(name), src.to_owned()).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    [Strategy::ThreePass, Strategy::TwoPass, Strategy::Fused]
        .into_iter()
        .map(|strategy| {
            let opts = InstanceOptions {
                strategy,
                ..Default::default()
            };
            instance(&shader, &norm, &table, NodeSelector::Root, &opts)
                .unwrap_or_else(|e| panic!("{strategy:?}: {e}"))
        })
        .collect()
}
