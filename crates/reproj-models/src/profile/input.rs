//! How the profiled shader file was read ([`ShaderInputRecord`], profile version 12).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// How `analyze` read the shader file (`reproj_front::ShaderInput`): what `--def`,
/// `--defs-preset`, `--import-path` and `--include-dir` gave.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShaderInputRecord {
    /// Shader defs given one by one, each value spelled as `--def` takes it (`true`, `false`, an
    /// integer).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub defs: BTreeMap<String, String>,
    /// The defs preset under them (`bevy`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub defs_preset: Option<String>,
    /// Folders searched for `#import`ed WGSL modules, relative to the profile's directory as
    /// `shader.path` is.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub import_paths: Vec<String>,
    /// Folders searched for GLSL `#include`s, relative to the profile's directory.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub include_dirs: Vec<String>,
}

impl ShaderInputRecord {
    /// Whether the shader was read as by default (then the field is left out of the file).
    pub fn is_empty(&self) -> bool {
        *self == ShaderInputRecord::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Left out of the file when empty, read back equal when not; a profile without it reads the
    /// shader as by default.
    #[test]
    fn the_record_is_additive() {
        let empty = ShaderInputRecord::default();
        assert!(empty.is_empty());
        assert_eq!(serde_json::to_string(&empty).unwrap(), "{}");
        let record = ShaderInputRecord {
            defs: [("PREPASS_FRAGMENT".to_owned(), "true".to_owned())].into(),
            defs_preset: Some("bevy".into()),
            import_paths: vec!["../assets".into()],
            include_dirs: Vec::new(),
        };
        let json = serde_json::to_string(&record).unwrap();
        assert_eq!(
            json,
            r#"{"defs":{"PREPASS_FRAGMENT":"true"},"defs_preset":"bevy","import_paths":["../assets"]}"#
        );
        let back: ShaderInputRecord = serde_json::from_str(&json).unwrap();
        assert_eq!(back, record);
    }
}
