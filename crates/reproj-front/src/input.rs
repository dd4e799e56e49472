//! How a shader file is read beyond its language: the shader defs of naga_oil's preprocessor (and
//! glslang's `-D`), the folders searched for `#import`ed modules, the folders searched for GLSL
//! `#include`s. Engine shaders as they sit in their repositories need them: Bevy's
//! `#ifdef PREPASS_FRAGMENT`, `#if AVAILABLE_STORAGE_BUFFER_BINDINGS >= 6`,
//! `#import "shaders/common.wgsl"`. One value, [`ShaderInput`], carried in
//! [`crate::LoadOptions`] so that every command reads a shader the same way, and recorded in the
//! profile so that `emit`, `report` and `compare` read it again as `analyze` did.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::{Path, PathBuf};

/// The value of a shader def, as naga_oil's `ShaderDefValue` has it: `#ifdef` asks only whether a
/// def is there, `#if NAME op VALUE` compares its value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DefValue {
    Bool(bool),
    /// A negative integer.
    Int(i32),
    /// A non-negative integer.
    UInt(u32),
}

impl std::str::FromStr for DefValue {
    type Err = String;
    /// `true`/`false`, or an integer: non-negative ones are `UInt`, negative ones `Int` (the order
    /// naga_oil's own `#define` reads them in).
    fn from_str(s: &str) -> Result<DefValue, String> {
        if let Ok(v) = s.parse::<u32>() {
            Ok(DefValue::UInt(v))
        } else if let Ok(v) = s.parse::<i32>() {
            Ok(DefValue::Int(v))
        } else if let Ok(v) = s.parse::<bool>() {
            Ok(DefValue::Bool(v))
        } else {
            Err(format!(
                "`{s}` is not a shader def value: expected true, false or an integer"
            ))
        }
    }
}

impl fmt::Display for DefValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DefValue::Bool(v) => write!(f, "{v}"),
            DefValue::Int(v) => write!(f, "{v}"),
            DefValue::UInt(v) => write!(f, "{v}"),
        }
    }
}

/// `NAME` or `NAME=VALUE` (no value: `true`), as `--def` takes it.
pub fn parse_def(s: &str) -> Result<(String, DefValue), String> {
    let (name, value) = match s.split_once('=') {
        Some((name, value)) => (name.trim(), value.trim().parse()?),
        None => (s.trim(), DefValue::Bool(true)),
    };
    let word = !name.is_empty()
        && !name.starts_with(|c: char| c.is_ascii_digit())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !word {
        return Err(format!(
            "`{name}` is not a shader def name: letters, digits and `_`, not starting with a digit"
        ));
    }
    Ok((name.to_owned(), value))
}

/// A ready set of shader defs an engine puts in front of every shader it compiles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DefsPreset {
    /// What Bevy's renderer defines for a desktop (Vulkan, Metal, DX12) target: see
    /// [`DefsPreset::defs`].
    Bevy,
}

impl DefsPreset {
    pub const ALL: [DefsPreset; 1] = [DefsPreset::Bevy];

    pub fn as_str(self) -> &'static str {
        match self {
            DefsPreset::Bevy => "bevy",
        }
    }

    /// The preset's defs. Bevy: `AVAILABLE_STORAGE_BUFFER_BINDINGS` is the device's
    /// `max_storage_buffers_per_shader_stage`, which `PipelineCache` adds to every shader (8:
    /// wgpu's default limit, what desktop adapters give at least); `MeshPipeline` adds
    /// `MAX_DIRECTIONAL_LIGHTS` (10) and `MAX_CASCADES_PER_LIGHT` (4 off WebGL), Bevy 0.19's
    /// `MeshRenderPlugin` builds `bevy_pbr::mesh_view_types` with `MAX_RECT_LIGHTS` (8; its
    /// `array<RectLight, #{MAX_RECT_LIGHTS}u>` does not parse without it, so every shader that
    /// imports the view bindings needs it), and materials get `MATERIAL_BIND_GROUP` (3 from Bevy
    /// 0.17; 2 before: override it with a def of its own).
    pub fn defs(self) -> &'static [(&'static str, DefValue)] {
        match self {
            DefsPreset::Bevy => &[
                ("AVAILABLE_STORAGE_BUFFER_BINDINGS", DefValue::UInt(8)),
                ("MAX_DIRECTIONAL_LIGHTS", DefValue::UInt(10)),
                ("MAX_CASCADES_PER_LIGHT", DefValue::UInt(4)),
                ("MAX_RECT_LIGHTS", DefValue::UInt(8)),
                ("MATERIAL_BIND_GROUP", DefValue::UInt(3)),
            ],
        }
    }
}

impl std::str::FromStr for DefsPreset {
    type Err = String;
    fn from_str(s: &str) -> Result<DefsPreset, String> {
        DefsPreset::ALL
            .into_iter()
            .find(|p| p.as_str() == s)
            .ok_or_else(|| format!("no shader defs preset `{s}` (known: bevy)"))
    }
}

/// How a shader file is read beyond its language (the module docs). The default reads it as
/// before: no defs, modules beside the shader and in `REPROJ_WGSL_IMPORTS`, includes beside it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ShaderInput {
    /// Shader defs given one by one; they override the preset's.
    pub defs: BTreeMap<String, DefValue>,
    /// An engine's usual defs, under [`ShaderInput::defs`].
    pub preset: Option<DefsPreset>,
    /// Further folders searched (with their subfolders) for `#import`ed WGSL modules, and the
    /// roots asset-path imports (`#import "shaders/x.wgsl"`) are resolved against.
    pub import_paths: Vec<PathBuf>,
    /// Further folders searched for GLSL `#include "x"` (after the shader's own folder).
    pub include_dirs: Vec<PathBuf>,
}

impl ShaderInput {
    /// Every def the shader is read with: the preset's, then the ones given (which win).
    pub fn all_defs(&self) -> BTreeMap<String, DefValue> {
        let mut all: BTreeMap<String, DefValue> = self
            .preset
            .map(|p| p.defs())
            .unwrap_or_default()
            .iter()
            .map(|(n, v)| ((*n).to_owned(), *v))
            .collect();
        all.extend(self.defs.iter().map(|(n, v)| (n.clone(), *v)));
        all
    }

    /// Whether it reads a shader as the default does.
    pub fn is_default(&self) -> bool {
        *self == ShaderInput::default()
    }
}

/// Something about how a shader was read that does not stop it but should be said: returned as
/// data with the [`crate::Shader`], printed by the CLI.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InputWarning {
    /// A def given by name that no `#ifdef`, `#ifndef`, `#if` or `#NAME` substitution of the
    /// shader or of a module it imports reads (a typo would otherwise pass silently).
    #[error("shader def `{name}` is read by no `#ifdef`/`#ifndef`/`#if` of {path} or its imports")]
    UnreadDef { name: String, path: PathBuf },
    /// A resource declared without `@group`/`@binding` (Blade's WGSL: its host binds by name),
    /// given a binding so that the module validates ([`crate::fill_in`]).
    #[error(
        "`{name}` in {path} has no @group/@binding (its host binds it by name): read as @group({group}) @binding({binding})"
    )]
    BindingAssigned {
        name: String,
        group: u32,
        binding: u32,
        path: PathBuf,
    },
}

/// A warning for each def given by name (not a preset's) that is not in `read`, the defs the
/// shader's text and its modules read.
pub(crate) fn unread_defs(
    path: &Path,
    input: &ShaderInput,
    read: &BTreeSet<String>,
) -> Vec<InputWarning> {
    input
        .defs
        .keys()
        .filter(|n| !read.contains(*n))
        .map(|name| InputWarning::UnreadDef {
            name: name.clone(),
            path: path.to_owned(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defs_parse_as_naga_oil_reads_them() {
        assert_eq!(
            parse_def("FOO").unwrap(),
            ("FOO".into(), DefValue::Bool(true))
        );
        assert_eq!(parse_def("FOO=false").unwrap().1, DefValue::Bool(false));
        assert_eq!(parse_def("N=3").unwrap().1, DefValue::UInt(3));
        assert_eq!(parse_def("N=-2").unwrap().1, DefValue::Int(-2));
        assert!(parse_def("N=1.5").is_err());
        assert!(parse_def("1N").is_err());
        assert!(parse_def("A-B").is_err());
        assert!(parse_def("=3").is_err());
    }

    #[test]
    fn given_defs_override_the_preset() {
        let input = ShaderInput {
            defs: [("MATERIAL_BIND_GROUP".to_owned(), DefValue::UInt(2))].into(),
            preset: Some(DefsPreset::Bevy),
            ..Default::default()
        };
        let all = input.all_defs();
        assert_eq!(all["MATERIAL_BIND_GROUP"], DefValue::UInt(2));
        assert_eq!(all["AVAILABLE_STORAGE_BUFFER_BINDINGS"], DefValue::UInt(8));
    }
}
