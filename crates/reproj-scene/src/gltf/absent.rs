//! glTF in a build without the `gltf` feature (the light build: `reproj-cli
//! --no-default-features`): a session that names a glTF file anywhere (its `gltf` scene,
//! `"camera": "gltf"`, an object's mesh, a texture) is refused when it is loaded, naming the field,
//! so nothing downstream quietly measures a scene with objects missing.

use std::path::Path;

use crate::geometry::MeshData;
use crate::session::{CameraPath, GltfTexture, Mesh, Session, SessionError};

/// What the refusal says after the field.
const MISSING: &str = "names a glTF file, and this reproj was built without glTF support (the \
    `gltf` feature of reproj-cli, on by default; the light build leaves it out)";

/// Refuse a session that uses glTF (see the module docs); any other is left as it is.
pub(crate) fn expand(session: &mut Session) -> Result<(), SessionError> {
    if session.gltf.is_some() {
        return Err(session.invalid("gltf", MISSING));
    }
    if matches!(session.camera, CameraPath::Gltf) {
        return Err(session.invalid("camera", MISSING));
    }
    if let Some(i) =
        (session.geometry.objects.iter()).position(|o| matches!(o.mesh, Mesh::Gltf { .. }))
    {
        return Err(session.invalid(format!("geometry.objects[{i}].mesh"), MISSING));
    }
    if let Some(name) = (session.textures.iter()).find_map(|(n, t)| t.gltf.as_ref().map(|_| n)) {
        return Err(session.invalid(format!("textures.{name}.gltf"), MISSING));
    }
    Ok(())
}

/// Never reached: [`expand`] refused the session.
pub(crate) fn mesh(_: &Session, path: &Path, _: usize, _: usize) -> Result<MeshData, String> {
    Err(format!("{}: {MISSING}", path.display()))
}

/// Never reached: [`expand`] refused the session.
pub(crate) fn texture(_: &Session, t: &GltfTexture) -> Result<(u32, u32, Vec<[f32; 4]>), String> {
    Err(format!("{}: {MISSING}", t.path.display()))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::{Session, SessionError};

    /// `extra` spliced into a small valid session.
    fn load(extra: &str) -> Result<Session, SessionError> {
        let text = format!(
            r#"{{"schema": "reproj.session", "version": 1, "resolution": [8, 8], "frames": 2,
                "fps": 30, "camera": {{"orbit": {{"center": [0, 0, 0], "radius": 3,
                "height": 0, "start_deg": 0, "end_deg": 10, "fov_y_deg": 40}}}},
                "light": {{"orbit": {{"center": [0, 0, 0], "radius": 3, "height": 2,
                "start_deg": 0, "end_deg": 0}}}}{extra}}}"#
        );
        Session::from_json(&text, Path::new("s.json"), Path::new("."))
    }

    fn field(r: Result<Session, SessionError>) -> String {
        match r {
            Err(SessionError::Invalid { field, message, .. }) => {
                assert!(message.contains("`gltf` feature"), "{message}");
                field
            }
            other => panic!("expected a refusal, got {other:?}"),
        }
    }

    #[test]
    fn absent_gltf_refuses_each_place_a_session_names_a_gltf_file() {
        let sphere = r#"{"mesh": {"sphere": {"radius": 1}}}"#;
        load(&format!(r#", "geometry": {{"objects": [{sphere}]}}"#)).expect("no glTF: loads");
        assert_eq!(field(load(r#", "gltf": {"path": "a.gltf"}"#)), "gltf");
        let gltf_mesh = r#"{"mesh": {"gltf": {"path": "a.gltf", "mesh": 0, "primitive": 0}}}"#;
        assert_eq!(
            field(load(&format!(
                r#", "geometry": {{"objects": [{sphere}, {gltf_mesh}]}}"#
            ))),
            "geometry.objects[1].mesh"
        );
        assert_eq!(
            field(load(
                r#", "textures": {"albedo": {"gltf": {"path": "a.gltf", "material": 0, "slot": "base_color"}}}"#
            )),
            "textures.albedo.gltf"
        );
    }
}
