//! Instancer invariants over every sample shader, snapshots of chosen variants, and bad input.

use std::path::{Path, PathBuf};

use reproj_front::{NodeTable, Normalized, Shader, enumerate, load_file, normalize};
use reproj_instance::{
    InstanceError, InstanceOptions, NodeSelector, PassKind, Strategy, Variant, instance,
    write_variant,
};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn load(name: &str) -> (Shader, Normalized, NodeTable) {
    let shader = load_file(&root().join("shaders").join(name)).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    (shader, norm, table)
}

fn samples() -> Vec<String> {
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

fn check_round_trip(v: &Variant) {
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

/// Every cacheable node of every sample, in every strategy: each pass validates (inside
/// `instance`, before and after compaction) and its WGSL is a fixed point of parse → validate →
/// write.
#[test]
fn every_cacheable_node_of_every_sample_instances() {
    let mut count = 0;
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        let passes = match strategy {
            Strategy::ThreePass => 3,
            Strategy::TwoPass => 2,
            Strategy::Fused => 1,
        };
        for name in samples() {
            let (shader, norm, table) = load(&name);
            let ids: Vec<u32> = table.cacheable().map(|n| n.id).collect();
            assert!(!ids.is_empty());
            for id in ids {
                let v = instance(&shader, &norm, &table, NodeSelector::Id(id), &opts)
                    .unwrap_or_else(|e| panic!("{name} node {id} ({strategy}): {e}"));
                assert_eq!(v.passes.len(), passes);
                assert_eq!(v.manifest.passes.len(), passes);
                assert_eq!(v.manifest.strategy, strategy);
                check_round_trip(&v);
                count += 1;
            }
            let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
            check_round_trip(&v);
        }
    }
    assert!(count > 300);
}

/// The payload format is the narrowest that holds the node unless one is asked for, and a format
/// too narrow for the node is a clear error.
#[test]
fn cache_formats_fit_the_node() {
    use reproj_instance::{CacheFormat, CacheFormatChoice};
    let (shader, norm, table) = load("marble.wgsl");
    let scalar = NodeSelector::Id(node_by_text(&table, "s3 + n4"));
    let v = instance(&shader, &norm, &table, scalar, &Default::default()).unwrap();
    assert_eq!(v.manifest.cache_format, CacheFormat::R32float);
    let half = InstanceOptions {
        cache_format: CacheFormatChoice::Narrowest16,
        ..Default::default()
    };
    let v = instance(&shader, &norm, &table, NodeSelector::Root, &half).unwrap();
    assert_eq!(v.manifest.cache_format, CacheFormat::Rgba16float);
    assert!(v.manifest.required_features.is_empty());
    let narrow = InstanceOptions {
        cache_format: CacheFormatChoice::Exact(CacheFormat::Rg32float),
        ..Default::default()
    };
    let e = instance(&shader, &norm, &table, NodeSelector::Root, &narrow).unwrap_err();
    assert!(matches!(e, InstanceError::FormatTooNarrow { .. }), "{e}");
}

/// Nearest reconstruction reads the previous payload with `textureLoad` and needs no sampler for
/// it, so no `float32-filterable` feature either.
#[test]
fn nearest_reconstruction_needs_no_filtering() {
    let (shader, norm, table) = load("marble.wgsl");
    let opts = InstanceOptions {
        reconstruct: reproj_instance::Reconstruct::Nearest,
        ..Default::default()
    };
    let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
    let p1 = pass(&v, PassKind::Reproject);
    assert!(p1.contains("textureLoad(reproj_prev_payload"), "{p1}");
    assert!(!p1.contains("reproj_linear_sampler"), "{p1}");
    assert!(v.manifest.required_features.is_empty());
}

#[test]
fn output_is_deterministic() {
    for name in samples() {
        let (shader, norm, table) = load(&name);
        let id = table
            .cacheable()
            .nth(table.cacheable().count() / 2)
            .unwrap()
            .id;
        let a = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Id(id),
            &Default::default(),
        )
        .unwrap();
        let (shader, norm, table) = load(&name);
        let b = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Id(id),
            &Default::default(),
        )
        .unwrap();
        for (x, y) in a.passes.iter().zip(&b.passes) {
            assert_eq!(x.wgsl, y.wgsl);
        }
        assert_eq!(a.manifest, b.manifest);
    }
}

fn node_by_text(table: &NodeTable, text: &str) -> u32 {
    table
        .cacheable()
        .find(|n| n.text == text)
        .unwrap_or_else(|| panic!("no cacheable node `{text}`"))
        .id
}

fn pass(v: &Variant, kind: PassKind) -> &str {
    &v.passes.iter().find(|p| p.kind == kind).unwrap().wgsl
}

#[test]
fn shade_pass_drops_the_cached_noise_and_keeps_the_overlap() {
    let (shader, norm, table) = load("marble.wgsl");
    // The whole turbulence sum: no noise left in pass 3, but `p` (also used by the vein stripes) is.
    let id = node_by_text(&table, "s3 + n4");
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(id),
        &Default::default(),
    )
    .unwrap();
    let shade = pass(&v, PassKind::Shade);
    assert!(shade.contains("textureLoad(reproj_cur_payload"));
    // Each octave hashes its 8 lattice corners with `sin`; only the vein stripes' `sin` is left.
    assert_eq!(
        shade.matches("sin(").count(),
        1,
        "noise still in pass 3:\n{shade}"
    );
    assert!(
        !shade.contains("floor("),
        "noise lattice still in pass 3:\n{shade}"
    );
    assert!(
        shade.contains("object_pos"),
        "the shared input was removed:\n{shade}"
    );
    let recompute = pass(&v, PassKind::Recompute);
    assert_eq!(
        recompute.matches("sin(").count(),
        5 * 8,
        "pass 2 computes the five octaves"
    );
    assert!(
        !recompute.contains("pow("),
        "pass 2 computes more than the node:\n{recompute}"
    );

    // An overlap node: `p` is shared between the noise and the stripes; caching the first octave
    // keeps `p` and the other four octaves in pass 3.
    let id = node_by_text(&table, "abs(gradient_noise(p))");
    let node = table.get(id).unwrap();
    assert!(node.overlap > 0.0);
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(id),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(
        pass(&v, PassKind::Shade).matches("sin(").count(),
        4 * 8 + 1,
        "four of five octaves remain"
    );
}

#[test]
fn ambient_occlusion_post_loop_sum_removes_its_loops_from_pass_3() {
    let (shader, norm, table) = load("ambient_occlusion.wgsl");
    let original_loops = {
        let v = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Root,
            &Default::default(),
        )
        .unwrap();
        pass(&v, PassKind::Recompute).matches("loop {").count()
    };
    assert!(original_loops >= 3, "{original_loops}");
    let static_sum = table
        .cacheable()
        .find(|n| n.text.contains("static"))
        .expect("a cacheable node reading the static occluders' sum");
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(static_sum.id),
        &Default::default(),
    )
    .unwrap();
    let shade = pass(&v, PassKind::Shade);
    assert!(shade.matches("loop {").count() < original_loops, "{shade}");
}

#[test]
fn snapshots_of_chosen_variants() {
    let picks: &[(&str, &str, Strategy)] = &[
        ("marble.wgsl", "s3 + n4", Strategy::ThreePass),
        ("marble.wgsl", "root", Strategy::ThreePass),
        ("ambient_occlusion.wgsl", "root", Strategy::ThreePass),
        ("marble.wgsl", "s3 + n4", Strategy::TwoPass),
        ("marble.wgsl", "s3 + n4", Strategy::Fused),
    ];
    for (name, text, strategy) in picks {
        let (shader, norm, table) = load(name);
        let sel = if *text == "root" {
            NodeSelector::Root
        } else {
            NodeSelector::Id(node_by_text(&table, text))
        };
        let opts = InstanceOptions {
            strategy: *strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        let v = instance(&shader, &norm, &table, sel, &opts).unwrap();
        let suffix = match strategy {
            Strategy::ThreePass => String::new(),
            s => format!("_{s}"),
        };
        let stem = format!(
            "{}_{}{suffix}",
            name.trim_end_matches(".wgsl"),
            text.replace(|c: char| !c.is_ascii_alphanumeric(), "_")
        );
        for p in &v.passes {
            insta::assert_snapshot!(format!("{stem}_{:?}", p.kind).to_lowercase(), p.wgsl);
        }
        insta::assert_json_snapshot!(format!("{stem}_manifest"), v.manifest);
    }
}

#[test]
fn bad_input_gives_clear_errors() {
    let (shader, norm, table) = load("marble.wgsl");
    let e = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(99_999),
        &Default::default(),
    )
    .unwrap_err();
    assert!(matches!(e, InstanceError::UnknownNode { .. }), "{e}");
    let culled = table
        .nodes
        .iter()
        .find(|n| !n.cacheable)
        .map(|n| n.id)
        .expect("marble has culled nodes");
    let e = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Id(culled),
        &Default::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("culled as"), "{e}");

    let full = "
        @group(0) @binding(0) var<uniform> a: vec4<f32>;
        @group(1) @binding(0) var<uniform> b: vec4<f32>;
        @group(2) @binding(0) var<uniform> c: vec4<f32>;
        @group(3) @binding(0) var<uniform> d: vec4<f32>;
        @fragment fn fs(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> { return sin(a + b + c + d) * p.x; }";
    let shader = reproj_front::parse_shader(Path::new("full.wgsl"), full.into()).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let e = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Root,
        &Default::default(),
    )
    .unwrap_err();
    assert!(matches!(e, InstanceError::NoFreeGroup { .. }), "{e}");
}

#[test]
fn write_variant_into_unwritable_place_fails_cleanly() {
    let (shader, norm, table) = load("marble.wgsl");
    let v = instance(
        &shader,
        &norm,
        &table,
        NodeSelector::Root,
        &Default::default(),
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a_file");
    std::fs::write(&file, "x").unwrap();
    let e = write_variant(&v, &file.join("sub")).unwrap_err();
    assert!(matches!(e, InstanceError::Write(_)), "{e}");
    let out = dir.path().join("out");
    write_variant(&v, &out).unwrap();
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "manifest.json",
            "pass1_reproject.wgsl",
            "pass2_recompute.wgsl",
            "pass3_shade.wgsl"
        ]
    );
}

/// Every pass that writes the frame color also writes the depth copy: `@builtin(position).z`, or
/// the shader's own `@builtin(frag_depth)` when it writes one. No pass declares a depth texture.
#[test]
fn color_passes_write_the_depth_copy() {
    let src = "
        struct Out {
            @location(0) color: vec4<f32>,
            @builtin(frag_depth) depth: f32,
        }
        @group(0) @binding(0) var<uniform> k: vec4<f32>;
        @fragment fn fs(@location(0) p: vec3<f32>, @builtin(position) pos: vec4<f32>) -> Out {
            let s = sin(p * k.xyz);
            return Out(vec4<f32>(s, 1.0), pos.z * 0.5);
        }";
    let shader = reproj_front::parse_shader(Path::new("depth.wgsl"), src.into()).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    for strategy in Strategy::ALL {
        let v = instance(
            &shader,
            &norm,
            &table,
            NodeSelector::Root,
            &InstanceOptions {
                strategy,
                block: strategy.default_block(),
                ..Default::default()
            },
        )
        .unwrap();
        check_round_trip(&v);
        for (p, m) in v.passes.iter().zip(&v.manifest.passes) {
            assert!(!p.wgsl.contains("texture_depth"), "{:?}", p.kind);
            let writes_color = m.colors.iter().any(|c| c.attachment == "frame");
            let copy = m
                .colors
                .iter()
                .find(|c| c.attachment == reproj_instance::ROLE_CUR_DEPTH_COPY);
            assert_eq!(writes_color, copy.is_some(), "{strategy} {:?}", p.kind);
            if writes_color {
                assert!(p.wgsl.contains("reproj_depth: f32"), "{}", p.wgsl);
                // The shader's own depth, not the rasterized one, ends the output.
                let ret = p
                    .wgsl
                    .lines()
                    .find(|l| l.contains("return ReprojOutput("))
                    .unwrap();
                assert!(ret.trim_end().ends_with(".depth);"), "{ret}");
            }
        }
    }
}

/// The GLSL twin of marble (`shaders/glsl/marble.frag`): its root and a spread of its cacheable
/// nodes instance in every strategy, every pass validates (inside `instance`) and survives a WGSL
/// round trip.
#[test]
fn glsl_marble_instances_in_every_strategy() {
    let shader = load_file(&root().join("shaders/glsl/marble.frag")).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let ids: Vec<u32> = table.cacheable().map(|n| n.id).collect();
    assert!(ids.len() > 300, "{}", ids.len());
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        for &id in ids.iter().step_by(37) {
            let v = instance(&shader, &norm, &table, NodeSelector::Id(id), &opts)
                .unwrap_or_else(|e| panic!("node {id} ({strategy}): {e}"));
            check_round_trip(&v);
        }
        let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
        check_round_trip(&v);
    }
}

/// `--lang`: every pass of marble's variants in GLSL, HLSL, MSL and SPIR-V, beside the WGSL.
#[test]
fn passes_are_written_in_every_output_language() {
    use reproj_instance::backends::{OutputLang, Outputs, pass_file_in};
    let (shader, norm, table) = load("marble.wgsl");
    let langs = [
        OutputLang::Glsl,
        OutputLang::Hlsl,
        OutputLang::Msl,
        OutputLang::SpirV,
    ];
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
        let dir = tempfile::tempdir().unwrap();
        reproj_instance::write_variant_in(&v, dir.path(), &Outputs::langs(&langs)).unwrap();
        for p in &v.passes {
            for lang in langs {
                let bytes = std::fs::read(dir.path().join(pass_file_in(p, lang))).unwrap();
                let entry = &p.module.entry_points[0].name;
                match lang {
                    OutputLang::SpirV => {
                        // SPIR-V magic number, and naga reads it back as a valid module.
                        assert_eq!(bytes[..4], 0x0723_0203u32.to_le_bytes());
                        let m = naga::front::spv::parse_u8_slice(&bytes, &Default::default())
                            .unwrap_or_else(|e| panic!("{strategy} {:?}: {e}", p.kind));
                        reproj_front::validator().validate(&m).unwrap();
                    }
                    OutputLang::Glsl => {
                        let text = String::from_utf8(bytes).unwrap();
                        assert!(text.starts_with("#version 450"), "{text}");
                        assert!(text.contains("void main()"), "{text}");
                    }
                    OutputLang::Hlsl | OutputLang::Msl => {
                        let text = String::from_utf8(bytes).unwrap();
                        assert!(text.contains(entry.as_str()), "{lang:?} lacks {entry}");
                    }
                }
            }
        }
    }
}

/// `--lang`: the manifest lists each language's files and every resource's binding there, the
/// same slot in every pass; each text file writes the binding as listed (`layout(binding = N)`,
/// `register(t3, space1)`, `[[texture(0)]]`: no `[[user(fake…)]]`); the SPIR-V keeps WebGPU's
/// set and binding; and the GLSL compiles for Vulkan (`glslangValidator -V`, which refuses a
/// resource without a binding), where glslang is installed — under CI it must be.
#[test]
fn every_language_binds_what_the_manifest_lists() {
    use reproj_instance::backends::{OutputLang, Outputs};
    let (shader, norm, table) = load("marble.wgsl");
    let langs = [
        OutputLang::Glsl,
        OutputLang::Hlsl,
        OutputLang::Msl,
        OutputLang::SpirV,
    ];
    let glslang = std::process::Command::new("glslangValidator")
        .arg("--version")
        .output()
        .is_ok();
    assert!(
        glslang || std::env::var_os("CI").is_none(),
        "CI is set and glslangValidator is missing: scripts/ensure-tools.sh installs it"
    );
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            ..Default::default()
        };
        let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
        let dir = tempfile::tempdir().unwrap();
        reproj_instance::write_variant_in(&v, dir.path(), &Outputs::langs(&langs)).unwrap();
        let manifest: reproj_instance::Manifest =
            serde_json::from_slice(&std::fs::read(dir.path().join("manifest.json")).unwrap())
                .unwrap();
        assert_eq!(
            manifest
                .languages
                .iter()
                .map(|l| l.lang.as_str())
                .collect::<Vec<_>>(),
            ["glsl", "hlsl", "msl", "spirv"]
        );
        // Every WGSL binding of every pass is in every table (GLSL folds samplers into textures).
        let wgsl: std::collections::BTreeSet<(u32, u32, String)> = manifest
            .passes
            .iter()
            .flat_map(|p| &p.bindings)
            .map(|b| (b.group, b.binding, b.ty.clone()))
            .collect();
        for l in &manifest.languages {
            assert_eq!(
                l.files.len(),
                manifest.passes.len(),
                "{strategy} {}",
                l.lang
            );
            for (g, b, ty) in &wgsl {
                let listed = l.bindings.iter().any(|x| (x.group, x.binding) == (*g, *b));
                let folded = l.lang == "glsl" && ty.starts_with("sampler");
                assert!(listed != folded, "{strategy} {}: ({g}, {b}) {ty}", l.lang);
            }
            let mut slots: Vec<(&str, u32, Option<u32>)> = l
                .bindings
                .iter()
                .map(|b| {
                    (
                        if l.lang == "msl" { b.kind.as_str() } else { "" },
                        b.slot,
                        b.space,
                    )
                })
                .collect();
            slots.sort();
            let n = slots.len();
            slots.dedup();
            if l.lang != "hlsl" {
                assert_eq!(
                    slots.len(),
                    n,
                    "{strategy} {}: two resources share a slot",
                    l.lang
                );
            }
            for file in &l.files {
                let bytes = std::fs::read(dir.path().join(file)).unwrap();
                if l.lang == "spirv" {
                    continue;
                }
                let text = String::from_utf8(bytes).unwrap();
                assert!(!text.contains("fake"), "{file}: an unassigned binding");
                // Each binding the file declares is written as the table says.
                for b in &l.bindings {
                    let target = match l.lang.as_str() {
                        "hlsl" if b.kind == "sampler" => format!(
                            "nagaGroup{}SamplerIndexArray : register(t{}, space255)",
                            b.group, b.group
                        ),
                        // `layout(std140, binding = 1)` for a uniform block.
                        "glsl" => format!("binding = {})", b.slot),
                        _ => b.target.clone(),
                    };
                    let declared = text.contains(&b.name)
                        || text.contains(&format!("_group_{}_binding_{}_", b.group, b.binding));
                    if declared {
                        assert!(text.contains(&target), "{file}: {} not at {target}", b.name);
                    }
                }
            }
            if l.lang == "glsl" && glslang {
                for file in &l.files {
                    let path = dir.path().join(file);
                    let out = std::process::Command::new("glslangValidator")
                        .args(["-V", "-S", "frag"])
                        .arg(&path)
                        .arg("-o")
                        .arg(path.with_extension("vk.spv"))
                        .output()
                        .unwrap();
                    assert!(
                        out.status.success(),
                        "{strategy} {file}: glslangValidator -V:\n{}",
                        String::from_utf8_lossy(&out.stdout)
                    );
                }
            }
        }
    }
}

/// The manifest's `params` layout (size, field names and offsets) is the contract's
/// `#[repr(C)]` `ReprojParams`, and its added bindings are the contract's, by name and number,
/// in every strategy.
#[test]
fn manifest_params_and_bindings_match_the_contract() {
    use reproj_instance::contract::{ADDED_BINDINGS, PARAMS_OFFSETS, PARAMS_SIZE, ReprojParams};
    let (shader, norm, table) = load("marble.wgsl");
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
        let params = &v.manifest.params;
        assert_eq!(params.size, PARAMS_SIZE);
        assert_eq!(params.size as usize, std::mem::size_of::<ReprojParams>());
        let fields: Vec<(&str, u32)> = params
            .fields
            .iter()
            .map(|f| (f.name.as_str(), f.offset))
            .collect();
        assert_eq!(fields, PARAMS_OFFSETS.to_vec(), "{strategy:?}");
        for pass in &v.manifest.passes {
            for b in pass.bindings.iter().filter(|b| b.added) {
                assert!(
                    ADDED_BINDINGS.contains(&(b.name.as_str(), b.binding)),
                    "{strategy:?} {:?}: added binding {} at {} is not in the contract",
                    pass.kind,
                    b.name,
                    b.binding
                );
            }
        }
    }
}

/// Two nodes cached together: their floats packed one after the other (the manifest says where),
/// the recompute pass returns both, the shade pass reads both from the payload and no longer
/// computes either; more than four floats, or a node twice, is refused.
#[test]
fn two_nodes_share_one_payload() {
    use reproj_instance::instance_nodes;
    let (shader, norm, table) = load("ambient_occlusion.wgsl");
    let (s, m) = (
        node_by_text(&table, "static_ao"),
        node_by_text(&table, "moving_ao"),
    );
    let pair = [NodeSelector::Id(s), NodeSelector::Id(m)];
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        let v = instance_nodes(&shader, &norm, &table, &pair, &opts).unwrap();
        check_round_trip(&v);
        let manifest = &v.manifest;
        assert_eq!(manifest.node.id, s.to_string());
        assert_eq!((manifest.node.offset, manifest.also.len()), (0, 1));
        assert_eq!(manifest.also[0].id, m.to_string());
        assert_eq!(manifest.also[0].offset, 1);
        assert_eq!(manifest.cache_format.channels(), 2);
        if strategy == Strategy::ThreePass {
            // Pass 3 reads both from the cache: neither loop is left.
            assert!(!pass(&v, PassKind::Shade).contains("loop"));
            assert!(pass(&v, PassKind::Recompute).contains("loop"));
        }
    }
    let (_, envmap_norm, envmap_table) = load("envmap.wgsl");
    let vec3s: Vec<u32> = envmap_table
        .cacheable()
        .filter(|n| n.components == 3 && !n.root)
        .map(|n| n.id)
        .take(2)
        .collect();
    let envmap = load_file(&root().join("shaders/envmap.wgsl")).unwrap();
    let wide = [NodeSelector::Id(vec3s[0]), NodeSelector::Id(vec3s[1])];
    let e = instance_nodes(
        &envmap,
        &envmap_norm,
        &envmap_table,
        &wide,
        &InstanceOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(e, InstanceError::PayloadTooWide { components: 6, .. }),
        "{e}"
    );
    let twice = [NodeSelector::Id(s), NodeSelector::Id(s)];
    let e =
        instance_nodes(&shader, &norm, &table, &twice, &InstanceOptions::default()).unwrap_err();
    assert!(matches!(e, InstanceError::RepeatedNode { .. }), "{e}");
}

/// `enable f16;` survives the passes of every strategy: each pass of each cacheable node of a
/// shader computing in f16 parses and validates again (it failed to parse without the directive).
#[test]
fn f16_shaders_keep_their_enable_directive() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/f16.wgsl");
    let shader = load_file(&path).unwrap();
    let norm = normalize(&shader, &Default::default()).unwrap();
    let table = enumerate(&shader, &norm);
    let ids: Vec<u32> = table.cacheable().map(|n| n.id).collect();
    assert!(
        table.cacheable().any(|n| n.text == "f32(h.x * h.y + h.z)"),
        "{:#?}",
        table.nodes
    );
    for strategy in Strategy::ALL {
        let opts = InstanceOptions {
            strategy,
            block: strategy.default_block(),
            ..Default::default()
        };
        for &id in &ids {
            let v = instance(&shader, &norm, &table, NodeSelector::Id(id), &opts)
                .unwrap_or_else(|e| panic!("node {id} ({strategy}): {e}"));
            // The passes that compute in f16 say so (the others need not ask for the feature).
            assert!(
                v.passes.iter().any(|p| p.wgsl.contains("enable f16;\n")),
                "node {id} ({strategy}): no pass enables f16"
            );
            check_round_trip(&v);
        }
    }
}

/// Names naga's namer changes on every trip (`a`, `a` and `a_1` in one function after inlining:
/// `a_1` becomes `a_1_`, then the second `a` takes `a_1`, …) once made "the WGSL round trip does
/// not reach a fixed point": the passes are now a fixed point up to those renamings, and still
/// parse and validate.
#[test]
fn names_naga_renames_on_every_trip_still_instance() {
    let src = "
fn h(x: f32) -> f32 {
    let a = x * 3.0 + 0.25;
    return a;
}
@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
    let a = sin(p.x * 5.0);
    let b = h(a);
    let a_1 = cos(b * 2.0) + a;
    return vec4<f32>(a_1, b, a, 1.0);
}
";
    for v in root_in_every_strategy("names.wgsl", src) {
        for p in &v.passes {
            let m = naga::front::wgsl::parse_str(&p.wgsl).unwrap();
            reproj_front::validator().validate(&m).unwrap();
        }
    }
}

/// The root variant of the WGSL `src` in each strategy (panics naming the strategy that fails).
fn root_in_every_strategy(name: &str, src: &str) -> Vec<Variant> {
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

/// A helper inlined with literal arguments leaves constants nested in its body (`(1 + w) * (1 +
/// w)` with `w = 0.3`), and naga folds one more level of them on each WGSL round trip: that once
/// made "the WGSL round trip does not reach a fixed point" (an internal error) on a real shader.
/// The passes now reach the fixed point after as many trips as the nesting needs.
#[test]
fn constants_folded_over_several_trips_still_instance() {
    let src = "
fn soften(d: f32, w: f32) -> f32 {
    return d / (((1.0 + w) * (1.0 + w)) * (2.0 - w));
}
@fragment fn fs_main(@location(0) p: vec3<f32>) -> @location(0) vec4<f32> {
    let d = soften(p.y, 0.3);
    return vec4<f32>(vec3<f32>(d * sin(p.x * 7.0)), 1.0);
}
";
    for v in root_in_every_strategy("nested.wgsl", src) {
        for p in &v.passes {
            // A fixed point: written again, the text does not change.
            let m = naga::front::wgsl::parse_str(&p.wgsl).unwrap();
            let info = reproj_front::validator().validate(&m).unwrap();
            assert_eq!(reproj_instance::write_wgsl(&m, &info).unwrap(), p.wgsl);
        }
    }
}
