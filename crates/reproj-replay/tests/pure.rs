//! Without a GPU: the generated vertex stage's WGSL validates and feeds every fragment input, and
//! what it cannot feed is an error naming each input; a variant folder whose pass is over the GPU
//! memory budget is refused when it is read, naming the pass's file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use reproj_replay::ReplayError;
use reproj_replay::vertex::{merge_inputs, vertex_wgsl};
use reproj_scene::reflect;
use reproj_scene::session::Attribute;

fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(p)
}

fn tiny_interface() -> reflect::Interface {
    let shader = reproj_front::load_file(&data("tiny.wgsl")).unwrap();
    let entry = shader.fragment_entry(None).unwrap();
    reflect::reflect(&shader.module, &shader.info, entry).unwrap()
}

#[test]
fn vertex_stage_validates_and_feeds_every_input() {
    let iface = tiny_interface();
    let mapping = BTreeMap::from([
        (0, Attribute::Position),
        (1, Attribute::Normal),
        (2, Attribute::Uv),
    ]);
    for prev_clip in [None, Some(5)] {
        // A variant's fragment stage reads the previous clip position as one more input, which the
        // session does not map: the vertex stage computes it.
        let mut inputs = iface.inputs.clone();
        inputs.extend(prev_clip.map(|location| reflect::FragInput {
            location,
            components: 4,
            scalar: reflect::InputScalar::F32,
            interpolation: None,
            sampling: None,
            name: "prev_clip".into(),
        }));
        let text = vertex_wgsl(2, &inputs, &mapping, prev_clip).unwrap();
        let module = naga::front::wgsl::parse_str(&text).unwrap();
        reproj_front::validator().validate(&module).unwrap();
        let ep = &module.entry_points[0];
        assert_eq!(ep.stage, naga::ShaderStage::Vertex);
        let naga::TypeInner::Struct { members, .. } =
            &module.types[ep.function.result.as_ref().unwrap().ty].inner
        else {
            panic!("the vertex stage returns a struct")
        };
        let mut locations: Vec<u32> = members
            .iter()
            .filter_map(|m| match m.binding {
                Some(naga::Binding::Location { location, .. }) => Some(location),
                _ => None,
            })
            .collect();
        locations.sort_unstable();
        let mut want = vec![0, 1, 2];
        want.extend(prev_clip);
        assert_eq!(locations, want);
        // The transforms live in the group it was given.
        assert!(
            module
                .global_variables
                .iter()
                .any(|(_, g)| g.binding.as_ref().is_some_and(|b| b.group == 2))
        );
    }
}

#[test]
fn vertex_stage_names_unmapped_inputs() {
    let iface = tiny_interface();
    let mapping = BTreeMap::from([(0, Attribute::Position)]);
    match vertex_wgsl(2, &iface.inputs, &mapping, None) {
        Err(ReplayError::MissingResources { names, .. }) => {
            assert_eq!(names, ["@location(1) `normal`", "@location(2) `uv`"]);
        }
        other => panic!("expected MissingResources, got {other:?}"),
    }
}

#[test]
fn merging_inputs_refuses_disagreeing_types() {
    let iface = tiny_interface();
    let mut other = iface.inputs.clone();
    other[0].components = 4;
    assert!(merge_inputs(&[&iface.inputs, &iface.inputs]).is_ok());
    let e = merge_inputs(&[&iface.inputs, &other]).unwrap_err();
    assert!(e.to_string().contains("@location(0)"), "{e}");
}

/// A variant folder is read through `VariantInput::from_dir`, not the front end's loader: its
/// passes are held to the same GPU memory budget, and a pass over it is refused naming its file.
#[test]
fn a_variant_pass_past_the_gpu_memory_budget_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let from = data("variant_tiny");
    for e in std::fs::read_dir(&from).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.path().join(p.file_name().unwrap())).unwrap();
    }
    reproj_replay::VariantInput::from_dir(dir.path(), 2).expect("the variant as written");
    let pass = dir.path().join("pass2_recompute.wgsl");
    std::fs::write(
        &pass,
        "var<private> big: array<f32, 16777216>;\n@fragment\nfn main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    big[u32(p.x)] = p.y;\n    return vec4<f32>(big[u32(p.y)]);\n}\n",
    )
    .unwrap();
    let e = reproj_replay::VariantInput::from_dir(dir.path(), 2).unwrap_err();
    assert!(matches!(e, ReplayError::Memory(_)), "{e:?}");
    assert!(e.is_user_error());
    let m = e.to_string();
    assert!(
        m.starts_with(&format!("{}: `big` (private)", pass.display()))
            && m.contains("over the GPU memory budget")
            && m.contains("REPROJ_MAX_SHADER_MEMORY_MB"),
        "{m}"
    );
}
