//! `--lang`: the passes written in GLSL, HLSL, MSL and SPIR-V through naga's backends, beside the
//! WGSL, with every resource bound where the manifest lists it.

use reproj_instance::{InstanceOptions, NodeSelector, Strategy, instance};

use crate::common::load;

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

/// A runtime-sized texture array (WGSL `binding_array<texture_2d<f32>>`, GLSL `sampler2D t[]`):
/// its SPIR-V declares `RuntimeDescriptorArray` and `SPV_EXT_descriptor_indexing`, and spirv-val
/// accepts it for Vulkan 1.2 where SPIRV-Tools is installed (under CI it must be).
#[test]
fn a_runtime_sized_texture_array_declares_its_capability_in_spirv() {
    use reproj_instance::backends::{OutputLang, Outputs, pass_file_in};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("layers.wgsl");
    std::fs::write(
        &path,
        "enable wgpu_binding_array;\n\
         struct In { @location(0) world_pos: vec3<f32>, @location(2) uv: vec2<f32> };\n\
         struct Params { layer: u32, gain: f32 };\n\
         @group(0) @binding(0) var<uniform> params: Params;\n\
         @group(0) @binding(1) var layers: binding_array<texture_2d<f32>>;\n\
         @group(0) @binding(2) var samp: sampler;\n\
         @fragment\nfn fs_main(in: In) -> @location(0) vec4<f32> {\n    \
         let c = textureSample(layers[params.layer], samp, in.uv).rgb;\n    \
         let w = sin(in.world_pos.x * 7.0) * cos(in.world_pos.y * 5.0);\n    \
         return vec4<f32>(c * params.gain + vec3<f32>(w * 0.1), 1.0);\n}\n",
    )
    .unwrap();
    let shader = reproj_front::load_file(&path).unwrap();
    let norm = reproj_front::normalize(&shader, &Default::default()).unwrap();
    let table = reproj_front::enumerate(&shader, &norm);
    let opts = InstanceOptions {
        strategy: Strategy::TwoPass,
        ..Default::default()
    };
    let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
    let out = dir.path().join("v");
    reproj_instance::write_variant_in(&v, &out, &Outputs::langs(&[OutputLang::SpirV])).unwrap();
    let spirv_val = std::process::Command::new("spirv-val")
        .arg("--version")
        .output()
        .is_ok();
    assert!(
        spirv_val || std::env::var_os("CI").is_none(),
        "CI is set and spirv-val is missing: scripts/ensure-tools.sh installs it"
    );
    let mut checked = 0;
    for p in &v.passes {
        let file = out.join(pass_file_in(p, OutputLang::SpirV));
        let bytes = std::fs::read(&file).unwrap();
        let words: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let uses_array = p.module.global_variables.iter().any(|(_, g)| {
            matches!(
                p.module.types[g.ty].inner,
                naga::TypeInner::BindingArray { .. }
            )
        });
        if !uses_array {
            continue;
        }
        // OpCapability (17) RuntimeDescriptorArray (5302); OpExtension (10) naming the extension.
        let mut at = 5;
        let (mut capability, mut extension) = (false, false);
        while at < words.len() {
            let (count, op) = ((words[at] >> 16) as usize, words[at] & 0xffff);
            if op == 17 && words.get(at + 1) == Some(&5302) {
                capability = true;
            }
            if op == 10 {
                let text: Vec<u8> = words[at + 1..at + count]
                    .iter()
                    .flat_map(|w| w.to_le_bytes())
                    .take_while(|&b| b != 0)
                    .collect();
                extension |= text == b"SPV_EXT_descriptor_indexing";
            }
            at += count.max(1);
        }
        assert!(
            capability && extension,
            "{:?}: {capability} {extension}",
            p.kind
        );
        if spirv_val {
            let r = std::process::Command::new("spirv-val")
                .args(["--target-env", "vulkan1.2"])
                .arg(&file)
                .output()
                .unwrap();
            assert!(
                r.status.success(),
                "{:?}: {}",
                p.kind,
                String::from_utf8_lossy(&r.stderr)
            );
        }
        checked += 1;
    }
    assert!(checked > 0, "no pass reads the texture array");
}

/// Whether `program` runs; under CI it must (`scripts/ensure-tools.sh` installs it).
fn tool(program: &str) -> bool {
    let found = std::process::Command::new(program)
        .arg("--version")
        .output()
        .is_ok();
    assert!(
        found || std::env::var_os("CI").is_none(),
        "CI is set and {program} is missing: scripts/ensure-tools.sh installs it"
    );
    found
}

/// Run `program args… file`; its status and its output (stdout then stderr).
fn run_on(program: &str, args: &[&str], file: &std::path::Path) -> (bool, String) {
    let out = std::process::Command::new(program)
        .args(args)
        .arg(file)
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

/// Push constants (GLSL `layout(push_constant)`, WGSL `var<immediate>`; `fixtures/push_constants/`)
/// in every language, in every strategy: the manifest lists them (name, type, size) and where
/// each language reads them; the SPIR-V passes spirv-val for Vulkan 1.0 and 1.2; the GLSL compiles
/// for Vulkan (`glslangValidator -V`: a `layout(push_constant)` block) and for OpenGL
/// (`glslangValidator -G`: a std140 uniform block at the binding the manifest lists), or, where
/// std140 cannot hold the bytes (an array of scalars), refuses OpenGL by its `#error`. Each
/// check runs where its tool is installed; under CI every tool must be.
#[test]
fn push_constants_are_listed_and_valid_in_every_language() {
    use reproj_instance::backends::{OutputLang, Outputs, pass_file_in};
    let langs = [
        OutputLang::Glsl,
        OutputLang::Hlsl,
        OutputLang::Msl,
        OutputLang::SpirV,
    ];
    let (glslang, spirv_val) = (tool("glslangValidator"), tool("spirv-val"));
    if !glslang {
        eprintln!("skipped: glslangValidator is not installed (GLSL inputs, GLSL outputs)");
        return;
    }
    let dir =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/push_constants");
    // (fixture, its push constants' size, whether std140 holds them)
    let cases = [
        ("tinted.frag", 32, true),
        ("tinted.wgsl", 32, true),
        ("weights.frag", 32, false),
        // tint at 64, gain at 96: padding members keep them there in every language.
        ("offsets.frag", 112, false),
    ];
    for (file, size, gl) in cases {
        let shader = reproj_front::load_file(&dir.join(file)).unwrap();
        let norm = reproj_front::normalize(&shader, &Default::default()).unwrap();
        let table = reproj_front::enumerate(&shader, &norm);
        for strategy in Strategy::ALL {
            let opts = InstanceOptions {
                strategy,
                ..Default::default()
            };
            let v = instance(&shader, &norm, &table, NodeSelector::Root, &opts).unwrap();
            let out = tempfile::tempdir().unwrap();
            reproj_instance::write_variant_in(&v, out.path(), &Outputs::langs(&langs)).unwrap();
            let manifest: reproj_instance::Manifest =
                serde_json::from_slice(&std::fs::read(out.path().join("manifest.json")).unwrap())
                    .unwrap();
            let push = manifest
                .immediates
                .as_ref()
                .unwrap_or_else(|| panic!("{file} {strategy}: no immediates in the manifest"));
            assert_eq!((push.name.as_str(), push.size), ("pc", size), "{file}");
            if file == "offsets.frag" {
                // The Vulkan GLSL block states each member's offset as the GLSL input did.
                let reads = |p: &&reproj_instance::PassModule| {
                    p.module
                        .global_variables
                        .iter()
                        .any(|(_, g)| g.space == naga::AddressSpace::Immediate)
                };
                let pass = v.passes.iter().find(reads).unwrap();
                let frag = out.path().join(pass_file_in(pass, OutputLang::Glsl));
                let text = std::fs::read_to_string(frag).unwrap();
                assert!(text.contains("layout(offset = 64) vec4 tint;"), "{text}");
                assert!(text.contains("layout(offset = 96) float gain;"), "{text}");
            }
            for l in &manifest.languages {
                let at = l
                    .immediates
                    .as_ref()
                    .unwrap_or_else(|| panic!("{file} {strategy}: {} does not say where", l.lang));
                if l.lang == "glsl" {
                    assert_eq!(at.slot.is_some(), gl, "{file}: {at:?}");
                    // The OpenGL block's binding is nobody else's.
                    assert!(l.bindings.iter().all(|b| Some(b.slot) != at.slot));
                }
            }
            for p in &v.passes {
                let reads = p
                    .module
                    .global_variables
                    .iter()
                    .any(|(_, g)| g.space == naga::AddressSpace::Immediate);
                let spv = out.path().join(pass_file_in(p, OutputLang::SpirV));
                for env in ["vulkan1.0", "vulkan1.2"] {
                    if spirv_val {
                        let (ok, text) = run_on("spirv-val", &["--target-env", env], &spv);
                        assert!(ok, "{file} {strategy} {:?} {env}: {text}", p.kind);
                    }
                }
                let frag = out.path().join(pass_file_in(p, OutputLang::Glsl));
                let text = std::fs::read_to_string(&frag).unwrap();
                assert_eq!(
                    text.contains("layout(push_constant) uniform"),
                    reads,
                    "{file} {strategy} {:?}:\n{text}",
                    p.kind
                );
                let vk = frag.with_extension("vk.spv");
                let (ok, log) = run_on(
                    "glslangValidator",
                    &["-V", "-S", "frag", "-o", vk.to_str().unwrap()],
                    &frag,
                );
                assert!(ok, "{file} {strategy} {:?} -V:\n{log}\n{text}", p.kind);
                if spirv_val {
                    let (ok, log) = run_on("spirv-val", &["--target-env", "vulkan1.0"], &vk);
                    assert!(ok, "{file} {strategy} {:?}: {log}", p.kind);
                }
                let glsp = frag.with_extension("gl.spv");
                let (ok, log) = run_on(
                    "glslangValidator",
                    &["-G", "-S", "frag", "-o", glsp.to_str().unwrap()],
                    &frag,
                );
                if gl || !reads {
                    assert!(ok, "{file} {strategy} {:?} -G:\n{log}\n{text}", p.kind);
                } else {
                    assert!(!ok && log.contains("no OpenGL form"), "{file} -G:\n{log}");
                }
            }
        }
    }
}
