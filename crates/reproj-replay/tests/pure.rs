//! The generated vertex stage, without a GPU: its WGSL validates and feeds every fragment input,
//! and what it cannot feed is an error naming each input.

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
