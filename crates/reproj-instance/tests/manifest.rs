//! The manifest as a contract: its published JSON Schema is current, every manifest the instancer
//! writes validates against it and is self-consistent (every role, sampler and attachment it names
//! is declared), and the integration options (`group`, `frame_load`, `depth_load`,
//! `reprojection`) land in it.

use std::path::PathBuf;

use reproj_front::{enumerate, load_file, normalize};
use reproj_instance::{
    BindingResource, DepthLoad, FrameLoad, InstanceError, InstanceOptions, LayoutEntry, LoadOp,
    Manifest, NodeSelector, Reconstruct, Reprojection, Strategy, instance, manifest_schema,
};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn schema_path() -> PathBuf {
    root().join("docs/manifest.schema.json")
}

fn manifests() -> Vec<Manifest> {
    let mut out = Vec::new();
    for name in [
        "marble.wgsl",
        "ambient_occlusion.wgsl",
        "envmap.wgsl",
        "sh_lighting.wgsl",
    ] {
        let shader = load_file(&root().join("shaders").join(name)).unwrap();
        let norm = normalize(&shader, &Default::default()).unwrap();
        let table = enumerate(&shader, &norm);
        let node = table
            .cacheable()
            .max_by_key(|n| n.components)
            .map(|n| n.id)
            .unwrap();
        for strategy in Strategy::ALL {
            for (reconstruct, frame_load, depth_load, reprojection) in [
                (
                    Reconstruct::Bilinear,
                    FrameLoad::Clear,
                    DepthLoad::Clear,
                    Reprojection::Vertex,
                ),
                (
                    Reconstruct::Nearest,
                    FrameLoad::Load,
                    DepthLoad::Load,
                    Reprojection::MotionVectors,
                ),
                (
                    Reconstruct::CatmullRom,
                    FrameLoad::Clear,
                    DepthLoad::Clear,
                    Reprojection::MotionVectors,
                ),
                (
                    Reconstruct::Bilinear,
                    FrameLoad::Load,
                    DepthLoad::Load,
                    Reprojection::Vertex,
                ),
            ] {
                for sel in [NodeSelector::Root, NodeSelector::Id(node)] {
                    let opts = InstanceOptions {
                        strategy,
                        reconstruct,
                        frame_load,
                        depth_load,
                        reprojection,
                        ..Default::default()
                    };
                    out.push(
                        instance(&shader, &norm, &table, sel, &opts)
                            .unwrap()
                            .manifest,
                    );
                }
            }
        }
    }
    out
}

/// `docs/manifest.schema.json` is what the types generate. It is published at that path (hosts and
/// editors read it), so it is not an insta snapshot, but it is updated the way snapshots are:
/// after changing the manifest types, `INSTA_UPDATE=always cargo test -p reproj-instance --test
/// manifest` rewrites it, and `git diff` reviews it.
#[test]
fn published_schema_is_current() {
    let mut text = serde_json::to_string_pretty(&manifest_schema()).unwrap();
    text.push('\n');
    if std::env::var("INSTA_UPDATE").as_deref() == Ok("always") {
        std::fs::write(schema_path(), &text).unwrap();
    }
    let published = std::fs::read_to_string(schema_path()).unwrap_or_default();
    assert!(
        published == text,
        "docs/manifest.schema.json is out of date: run `INSTA_UPDATE=always cargo test -p \
         reproj-instance --test integration manifest::` and review the diff"
    );
}

#[test]
fn every_manifest_validates_against_the_published_schema() {
    let schema: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(schema_path()).unwrap()).unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    let all = manifests();
    assert!(all.len() >= 40);
    for m in &all {
        let value = serde_json::to_value(m).unwrap();
        let errors: Vec<String> = validator
            .iter_errors(&value)
            .map(|e| format!("{} at {}", e, e.instance_path()))
            .collect();
        assert!(errors.is_empty(), "{} {}: {errors:?}", m.shader, m.node.id);
        let back: Manifest = serde_json::from_value(value).unwrap();
        assert_eq!(&back, m);
    }
}

/// The schema is strict enough to catch the prose of manifest version 2.
#[test]
fn the_schema_rejects_prose_where_numbers_belong() {
    let schema = manifest_schema();
    let validator = jsonschema::validator_for(&schema).unwrap();
    let mut value = serde_json::to_value(&manifests()[0]).unwrap();
    value["passes"][0]["depth"]["load"] = serde_json::json!("clear 1.0");
    assert!(!validator.is_valid(&value));
    let mut value = serde_json::to_value(&manifests()[0]).unwrap();
    value["passes"][0]["bindings"][0]["layout"] = serde_json::json!({"type": "texture"});
    assert!(!validator.is_valid(&value));
}

/// Every name a manifest uses is declared in it: roles in every ping-pong entry, textures in the
/// texture list, samplers in the sampler list; params fields fit the buffer.
#[test]
fn every_manifest_is_self_consistent() {
    for m in manifests() {
        let what = format!("{} node {} {}", m.shader, m.node.id, m.strategy);
        assert_eq!(m.frames.ping_pong.len(), 2, "{what}");
        for plan in &m.frames.ping_pong {
            for texture in plan.values() {
                assert!(
                    m.textures.iter().any(|t| &t.name == texture),
                    "{what}: texture {texture} is not declared"
                );
            }
        }
        let has_role = |role: &str| m.frames.ping_pong.iter().all(|p| p.contains_key(role));
        for p in &m.passes {
            for b in &p.bindings {
                assert_eq!(b.added, b.group == m.group, "{what}: {}", b.name);
                match &b.resource {
                    BindingResource::Own => assert!(!b.added),
                    BindingResource::Params => match &b.layout {
                        LayoutEntry::Buffer {
                            min_binding_size, ..
                        } => assert_eq!(*min_binding_size, u64::from(m.params.size)),
                        other => panic!("{what}: params bound as {other:?}"),
                    },
                    BindingResource::Texture { role } => {
                        assert!(has_role(role), "{what}: role {role}");
                        if b.name == "reproj_prev_payload" {
                            let LayoutEntry::Texture { sample_type, .. } = &b.layout else {
                                panic!("{what}: payload layout {:?}", b.layout);
                            };
                            let filterable = m.reconstruct.filters();
                            assert_eq!(sample_type == "float", filterable, "{what}");
                        }
                    }
                    BindingResource::Sampler { name } => {
                        assert!(m.samplers.iter().any(|s| &s.name == name), "{what}: {name}");
                    }
                    BindingResource::Motion => {
                        assert_eq!(m.reprojection, Reprojection::MotionVectors, "{what}");
                        assert_eq!(m.vertex.prev_clip_location, None, "{what}");
                    }
                }
            }
            for c in &p.colors {
                assert!(c.attachment == "frame" || has_role(&c.attachment), "{what}");
                assert_eq!(c.format.is_none(), c.attachment == "frame", "{what}");
            }
            assert!(has_role(&p.depth.attachment), "{what}");
        }
        let end = m.params.fields.iter().map(|f| f.offset + 4).max().unwrap();
        assert_eq!(end, m.params.size, "{what}");
        // The first pass that writes the frame starts it as asked; later ones load it.
        let frame_loads: Vec<&LoadOp> = m
            .passes
            .iter()
            .flat_map(|p| &p.colors)
            .filter(|c| c.attachment == "frame")
            .map(|c| &c.load)
            .collect();
        assert!(frame_loads[1..].iter().all(|l| l.is_load()), "{what}");
        let first_load = frame_loads[0].is_load();
        assert_eq!(
            first_load,
            m.notes.iter().any(|n| n.contains("loaded, not cleared")),
            "{what}"
        );
        // The first pass starts the depth as asked (clear to 1, or the engine's); later ones load.
        let depth_loads: Vec<&LoadOp> = m.passes.iter().map(|p| &p.depth.load).collect();
        assert!(depth_loads[1..].iter().all(|l| l.is_load()), "{what}");
        assert_eq!(
            depth_loads[0].is_load(),
            m.notes
                .iter()
                .any(|n| n.contains("keeps what the depth target holds")),
            "{what}"
        );
        // The lookup reads its previous position from exactly one place.
        let reads_motion = m.passes.iter().any(|p| {
            p.bindings.iter().any(|b| {
                b.resource == BindingResource::Motion
                    && b.binding
                        == m.added_place()
                            .binding(reproj_instance::contract::MOTION_BINDING)
            })
        });
        assert_eq!(
            reads_motion,
            m.reprojection == Reprojection::MotionVectors,
            "{what}"
        );
        assert_eq!(
            m.vertex.prev_clip_location.is_some(),
            !reads_motion,
            "{what}"
        );
        assert_eq!(
            m.bytes_per_pixel,
            Some(
                m.textures
                    .iter()
                    .filter(|t| t.name != "depth")
                    .map(|t| match t.format.as_str() {
                        "r16float" => 2,
                        "rg16float" | "r32float" => 4,
                        "rgba16float" | "rg32float" => 8,
                        "rgba32float" => 16,
                        other => panic!("{what}: format {other}"),
                    })
                    .sum::<u32>()
            ),
            "{what}"
        );
    }
}

#[test]
fn the_added_group_can_be_chosen() {
    let shader = load_file(&root().join("shaders/marble.wgsl")).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let at = |group: Option<u32>| {
        let opts = InstanceOptions {
            group,
            ..Default::default()
        };
        instance(&shader, &norm, &table, NodeSelector::Root, &opts)
    };
    let default = at(None).unwrap();
    let chosen = at(Some(3)).unwrap();
    assert_eq!(chosen.manifest.group, 3);
    assert_ne!(default.manifest.group, 3);
    assert_eq!(default.manifest.group, 1, "marble binds group 0 only");
    for p in &chosen.passes {
        assert!(!p.wgsl.contains("@group(1)"), "{:?}", p.kind);
    }
    assert!(chosen.passes[0].wgsl.contains("@group(3)"));
    assert_eq!(
        (default.manifest.binding_base, chosen.manifest.binding_base),
        (0, 0)
    );
    // The shader's own group: the variant's bindings join it past the shader's.
    let joined = at(Some(0)).unwrap();
    assert_eq!(joined.manifest.group, 0);
    assert!(joined.manifest.binding_base > 0);
    assert!(
        joined.manifest.passes[0]
            .bindings
            .iter()
            .all(|b| b.added == (b.binding >= joined.manifest.binding_base))
    );
    // Beyond WebGPU's four groups: a clear error.
    match at(Some(4)) {
        Err(e @ InstanceError::GroupTaken { .. }) => {
            assert!(e.to_string().contains("bind group 4"), "{e}")
        }
        other => panic!("group 4: {other:?}"),
    }
}

/// The schema names itself (`$id`) and holds `schema` and `version` to this writer's (`const`), so
/// a validator tells a manifest of another kind or version from a malformed one.
#[test]
fn the_schema_has_an_id_and_constant_schema_and_version() {
    let schema = manifest_schema();
    assert_eq!(schema["$id"], reproj_instance::MANIFEST_SCHEMA_ID);
    assert_eq!(
        schema["properties"]["schema"]["const"],
        reproj_instance::MANIFEST_KIND.schema
    );
    assert_eq!(
        schema["properties"]["version"]["const"],
        reproj_instance::MANIFEST_VERSION
    );
    let validator = jsonschema::validator_for(&schema).unwrap();
    let mut manifest = serde_json::to_value(&manifests()[0]).unwrap();
    assert!(validator.is_valid(&manifest));
    manifest["version"] = 99.into();
    assert!(!validator.is_valid(&manifest), "another version is refused");
}

/// Whole-number parameters (every `u32` one: Δn, the block size, the frame index's first value)
/// are written as JSON integers (`13`, not `13.0`) and read back as the same numbers.
#[test]
fn whole_number_params_are_written_as_integers() {
    let m = &manifests()[0];
    let text = serde_json::to_string_pretty(m).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut u32_values = 0;
    for field in json["params"]["fields"].as_array().unwrap() {
        if field["type"] != "u32" {
            continue;
        }
        for key in ["value", "first"] {
            if let Some(v) = field["value"].get(key) {
                assert!(
                    v.is_u64(),
                    "{}: {key} = {v} is not an integer",
                    field["name"]
                );
                u32_values += 1;
            }
        }
    }
    assert!(u32_values > 0, "the params have u32 values");
    let back: Manifest = serde_json::from_str(&text).unwrap();
    assert_eq!(&back, m);
}

/// A shader has one IR hash however it was read: a GLSL shader read from its file (`instance`,
/// `render --variant`, `bench`) and its WGSL form (`Shader::to_wgsl`: what `analyze` profiles
/// and `emit` instances) hash alike, so the variant `emit` writes from a GLSL shader is accepted
/// with that shader; its manifest names the hash. Over the GLSL corpus and marble's GLSL twin,
/// where glslang is installed (under CI it must be).
#[test]
fn a_glsl_shader_has_one_ir_hash_however_it_was_read() {
    let found = std::process::Command::new("glslangValidator")
        .arg("--version")
        .output()
        .is_ok();
    assert!(
        found || std::env::var_os("CI").is_none(),
        "CI is set and glslangValidator is missing: scripts/ensure-tools.sh installs it"
    );
    if !found {
        eprintln!("skipped: glslangValidator is not installed");
        return;
    }
    let dir = root().join("tests/corpus/shaders/glsl");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "frag"))
        .collect();
    files.push(root().join("shaders/glsl/marble.frag"));
    files.sort();
    let (mut checked, mut renamed) = (0, 0);
    for file in &files {
        let Ok(shader) = load_file(file) else {
            continue;
        };
        let wgsl = shader.to_wgsl().unwrap();
        let hash = reproj_instance::ir_hash(&shader);
        // Hashing the WGSL form's IR written again, as before, differs where naga renames.
        let rewritten = reproj_instance::write_wgsl(&wgsl.module, &wgsl.info).unwrap();
        renamed += usize::from(reproj_io::content_hash(rewritten.as_bytes()) != hash);
        assert_eq!(reproj_instance::ir_hash(&wgsl), hash, "{}", file.display());
        assert_eq!(
            reproj_instance::ir_hash(&wgsl.to_wgsl().unwrap()),
            hash,
            "{}",
            file.display()
        );
        // `emit` instances the WGSL form with the GLSL shader's nodes.
        let norm = normalize(&shader, &Default::default()).unwrap();
        let table = enumerate(&shader, &norm);
        if table.cacheable().next().is_some() {
            let opts = InstanceOptions::default();
            let v = instance(&wgsl, &norm, &table, NodeSelector::Root, &opts).unwrap();
            assert_eq!(v.manifest.shader_ir_hash.as_deref(), Some(hash.as_str()));
        }
        checked += 1;
    }
    assert!(checked >= 10, "{checked} GLSL shaders loaded");
    eprintln!("{renamed} of {checked} would hash apart if the WGSL form's IR were written again");
}
