//! Record a session from a running app: [`SessionCapture`].
//!
//! `reproj analyze` measures a shader over a *session* (a JSON file: the scene, its motion, the
//! shader's uniform values). Writing one by hand describes a motion someone imagined; an engine
//! that uses this crate can record the motion it really draws instead. Start from a base session
//! that describes what does not move (resolution, meshes, textures, samplers: `reproj session init
//! SHADER` writes one), then give [`SessionCapture::frame`] what moves, once per drawn frame — the
//! camera, each object's model matrix, the light, the uniform values by name — and
//! [`SessionCapture::write`] the result. The written session keeps the base's fields and replaces
//! `frames`, `camera`, `light`, each object's `transform` and the recorded `uniforms` entries with
//! key frames, one per frame where a value changes (a run of equal values keeps its first and last
//! key: between them the value is the same), so `reproj render` of it draws the frames the app
//! drew: keys are reproduced exactly and model matrices are written as they are (`matrix` keys).
//!
//! The runtime depends on no reproj crate, so the session is built as JSON here; `reproj render`
//! and `reproj analyze` validate it when they read it (the schema: `docs/session.schema.json`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value, json};

/// The camera of one frame, as a look-at camera (right-handed, depth range [0, 1]; the aspect
/// ratio is the session's resolution's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CapturedCamera {
    pub eye: [f32; 3],
    pub target: [f32; 3],
    pub up: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
}

/// What moves in one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct CapturedFrame {
    pub camera: CapturedCamera,
    /// Each object's model matrix, column-major (`glam::Mat4::to_cols_array`), in the base
    /// session's `geometry.objects` order: one per object.
    pub objects: Vec<[f32; 16]>,
    /// The light's position (the session's `light` path, which fills `light_pos`), if the app
    /// has one.
    pub light: Option<[f32; 3]>,
    /// Uniform values by leaf name (`shininess`, or a struct member's path `sun.color`), numbers
    /// in order (column-major for matrices). A leaf not given keeps the base session's entry.
    pub uniforms: Vec<(String, Vec<f64>)>,
}

/// What went wrong reading the base, recording a frame or writing the session.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CaptureError {
    /// The base session was not read: missing, not a regular file, past its
    /// [`crate::ReadLimits`] limit, or not text.
    #[error(transparent)]
    File(#[from] crate::FileError),
    /// The base session is not a JSON object of a reproj session.
    #[error("{path}: {message}")]
    Base { path: PathBuf, message: String },
    /// A recorded frame does not fit the base or holds a value a session cannot.
    #[error("frame {frame}: {message}")]
    Frame { frame: usize, message: String },
    /// Nothing to write: no frame was recorded.
    #[error("no frame was recorded: call SessionCapture::frame once per drawn frame first")]
    Empty,
    /// The session file could not be written.
    #[error("writing {path}: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// A session being recorded: a base session and the frames given so far.
#[derive(Debug, Clone)]
pub struct SessionCapture {
    base: Map<String, Value>,
    /// Where the base came from, for messages and the written session's description.
    origin: String,
    objects: usize,
    frames: Vec<CapturedFrame>,
}

impl SessionCapture {
    /// Start from the session file at `path` (its file references, such as meshes and textures,
    /// are relative to its folder: write the recording beside it, or make them absolute).
    /// Only a regular file within the default [`crate::ReadLimits`] is read, as the reproj CLI
    /// reads a session.
    pub fn from_file(path: impl AsRef<Path>) -> Result<SessionCapture, CaptureError> {
        SessionCapture::from_file_with(path, &crate::ReadLimits::default())
    }

    /// [`SessionCapture::from_file`] within `limits` (`json_bytes`).
    pub fn from_file_with(
        path: impl AsRef<Path>,
        limits: &crate::ReadLimits,
    ) -> Result<SessionCapture, CaptureError> {
        let path = path.as_ref();
        let text = crate::files::read_text(path, crate::files::FileKind::Json, limits)?;
        let base: Value = serde_json::from_str(&text).map_err(|e| CaptureError::Base {
            path: path.to_owned(),
            message: format!("not JSON: {e}"),
        })?;
        SessionCapture::from_json(base, &path.display().to_string())
    }

    /// Start from a session already in memory; `origin` names it in messages.
    pub fn from_json(base: Value, origin: &str) -> Result<SessionCapture, CaptureError> {
        let bad = |message: &str| CaptureError::Base {
            path: PathBuf::from(origin),
            message: message.to_owned(),
        };
        let Value::Object(base) = base else {
            return Err(bad("a session is a JSON object"));
        };
        if base.get("schema").and_then(Value::as_str) != Some("reproj.session") {
            return Err(bad(
                "`schema` is not \"reproj.session\": not a reproj session",
            ));
        }
        let objects = base
            .get("geometry")
            .and_then(|g| g.get("objects"))
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
        Ok(SessionCapture {
            base,
            origin: origin.to_owned(),
            objects,
            frames: Vec::new(),
        })
    }

    /// The number of objects of the base session: each frame gives that many model matrices.
    pub fn object_count(&self) -> usize {
        self.objects
    }

    /// The frames recorded so far.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// True before the first frame.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Record the next frame (frame indices count from 0 in call order).
    pub fn frame(&mut self, frame: CapturedFrame) -> Result<(), CaptureError> {
        let index = self.frames.len();
        let bad = |message: String| CaptureError::Frame {
            frame: index,
            message,
        };
        if frame.objects.len() != self.objects {
            return Err(bad(format!(
                "{} model matrices for the base session's {} objects (geometry.objects)",
                frame.objects.len(),
                self.objects
            )));
        }
        let c = &frame.camera;
        let camera = c.eye.iter().chain(&c.target).chain(&c.up);
        if camera
            .chain([&c.fov_y_deg, &c.near, &c.far])
            .any(|x| !x.is_finite())
        {
            return Err(bad("the camera holds a number that is not finite".into()));
        }
        if !(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0 && c.near > 0.0 && c.far > c.near) {
            return Err(bad(format!(
                "the camera needs 0 < fov_y_deg < 180 and 0 < near < far (fov {}, near {}, far {})",
                c.fov_y_deg, c.near, c.far
            )));
        }
        for (i, m) in frame.objects.iter().enumerate() {
            if m.iter().any(|x| !x.is_finite()) {
                return Err(bad(format!(
                    "object {i}'s model matrix holds a number that is not finite"
                )));
            }
        }
        if frame
            .light
            .is_some_and(|l| l.iter().any(|x| !x.is_finite()))
        {
            return Err(bad("the light position is not finite".into()));
        }
        if let Some(previous) = self.frames.last()
            && previous.light.is_some() != frame.light.is_some()
        {
            return Err(bad(
                "a light in some frames and not in others: give it in every frame or in none"
                    .into(),
            ));
        }
        for (name, values) in &frame.uniforms {
            if name.is_empty() || name.split('.').any(str::is_empty) || name.contains('[') {
                return Err(bad(format!(
                    "uniform `{name}`: a leaf name is a member path such as `shininess` or `sun.color`"
                )));
            }
            if values.is_empty() || values.iter().any(|x| !x.is_finite()) {
                return Err(bad(format!(
                    "uniform `{name}`: needs one or more finite numbers"
                )));
            }
        }
        self.frames.push(frame);
        Ok(())
    }

    /// The recorded session as JSON.
    pub fn to_json(&self) -> Result<Value, CaptureError> {
        let last = self
            .frames
            .len()
            .checked_sub(1)
            .ok_or(CaptureError::Empty)?;
        let mut s = self.base.clone();
        s.insert(
            "description".into(),
            json!(format!(
                "Recorded with reproj-runtime's SessionCapture from {}: {} frames",
                self.origin,
                last + 1
            )),
        );
        s.insert("frames".into(), json!(last + 1));
        let camera = keys(
            &self.frames,
            |f| f.camera,
            |c| {
                json!({
                    "eye": c.eye, "target": c.target, "up": c.up,
                    "fov_y_deg": c.fov_y_deg, "near": c.near, "far": c.far,
                })
            },
        );
        s.insert("camera".into(), json!({ "keys": camera }));
        if self.frames[0].light.is_some() {
            let light = keys(&self.frames, |f| f.light, |p| json!({ "position": p }));
            s.insert("light".into(), json!({ "keys": light }));
        }
        if let Some(objects) = s
            .get_mut("geometry")
            .and_then(|g| g.get_mut("objects"))
            .and_then(Value::as_array_mut)
        {
            for (i, object) in objects.iter_mut().enumerate() {
                let transform = keys(&self.frames, |f| f.objects[i], |m| json!({ "matrix": m }));
                if let Some(o) = object.as_object_mut() {
                    o.insert("transform".into(), json!({ "keys": transform }));
                }
            }
        }
        let uniforms = s
            .entry("uniforms")
            .or_insert_with(|| Value::Object(Map::new()));
        if let Value::Object(uniforms) = uniforms {
            for (name, value) in self.uniform_values() {
                set_path(uniforms, &name, value);
            }
        }
        Ok(Value::Object(s))
    }

    /// Write the recorded session to `path` (a temporary file beside it, then renamed, so no
    /// half-written session is ever left).
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), CaptureError> {
        let path = path.as_ref();
        let text = serde_json::to_string_pretty(&self.to_json()?).expect("JSON values serialize");
        let error = |source| CaptureError::Write {
            path: path.to_owned(),
            source,
        };
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
        let tmp = path.with_file_name(format!(".{}.tmp", name.unwrap_or_default()));
        std::fs::write(&tmp, text + "\n").map_err(error)?;
        std::fs::rename(&tmp, path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            error(e)
        })
    }

    /// Each recorded uniform leaf's session value: a constant where every frame gave the same
    /// numbers, else key frames. A leaf given in some frames only holds its last value where it
    /// was not given.
    fn uniform_values(&self) -> BTreeMap<String, Value> {
        let mut names: Vec<&str> = Vec::new();
        for f in &self.frames {
            for (name, _) in &f.uniforms {
                if !names.contains(&name.as_str()) {
                    names.push(name);
                }
            }
        }
        let mut out = BTreeMap::new();
        for name in names {
            let mut held: Option<&Vec<f64>> = None;
            let per_frame: Vec<Option<&Vec<f64>>> = self
                .frames
                .iter()
                .map(|f| {
                    if let Some((_, v)) = f.uniforms.iter().find(|(n, _)| n == name) {
                        held = Some(v);
                    }
                    held
                })
                .collect();
            // Frames before the leaf was first given take its first value.
            let first = per_frame.iter().flatten().next().copied();
            let values: Vec<&Vec<f64>> = per_frame
                .iter()
                .map(|v| v.or(first).expect("the leaf was given in some frame"))
                .collect();
            let value = if values.iter().all(|v| *v == values[0]) {
                number_or_list(values[0])
            } else {
                let keys = keys(&values, |v| *v, |v| json!({ "value": number_or_list(v) }));
                json!({ "keys": keys })
            };
            out.insert(name.to_owned(), value);
        }
        out
    }
}

/// A leaf's numbers as a session value: one number, or a list.
fn number_or_list(v: &[f64]) -> Value {
    match v {
        [x] => json!(x),
        _ => json!(v),
    }
}

/// Key frames of the value `get` takes from each frame, written by `write` with its `frame`:
/// one key per frame, except inside a run of equal values, which keeps its first and last key.
fn keys<F, T: PartialEq>(
    frames: &[F],
    get: impl Fn(&F) -> T,
    write: impl Fn(T) -> Value,
) -> Vec<Value> {
    let values: Vec<T> = frames.iter().map(&get).collect();
    let n = values.len();
    let mut out = Vec::new();
    for (i, v) in values.into_iter().enumerate() {
        let same_before = i > 0 && get(&frames[i - 1]) == v;
        let same_after = i + 1 < n && get(&frames[i + 1]) == v;
        if same_before && same_after {
            continue;
        }
        let mut key = write(v);
        if let Value::Object(k) = &mut key {
            k.insert("frame".into(), json!(i));
        }
        out.push(key);
    }
    out
}

/// Set `value` at the member path `name` (`sun.color`) inside `uniforms`, making the structs on
/// the way (a non-object in the way is replaced).
fn set_path(uniforms: &mut Map<String, Value>, name: &str, value: Value) {
    match name.split_once('.') {
        None => {
            uniforms.insert(name.to_owned(), value);
        }
        Some((head, rest)) => {
            let member = uniforms
                .entry(head)
                .or_insert_with(|| Value::Object(Map::new()));
            // A number, a list or key frames where a struct is recorded: the struct wins.
            let keyed = member
                .as_object()
                .is_some_and(|m| m.len() == 1 && m.contains_key("keys"));
            if !member.is_object() || keyed {
                *member = Value::Object(Map::new());
            }
            if let Value::Object(m) = member {
                set_path(m, rest, value);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> Value {
        json!({
            "schema": "reproj.session", "version": 1, "resolution": [64, 64], "frames": 150,
            "geometry": {"objects": [{"mesh": {"sphere": {"radius": 1}}}, {"mesh": {"plane": {"size": 4}}}]},
            "camera": {"orbit": {"radius": 3}},
            "uniforms": {"shininess": 60, "sun": {"color": [1, 1, 1], "intensity": 2}}
        })
    }

    fn frame(i: usize) -> CapturedFrame {
        let mut moving = [0.0f32; 16];
        for d in [0, 5, 10, 15] {
            moving[d] = 1.0;
        }
        moving[12] = i as f32 * 0.5;
        let mut still = moving;
        still[12] = 0.0;
        CapturedFrame {
            camera: CapturedCamera {
                eye: [0.0, 1.0, 3.0],
                target: [0.0; 3],
                up: [0.0, 1.0, 0.0],
                fov_y_deg: 40.0,
                near: 0.1,
                far: 20.0,
            },
            objects: vec![moving, still],
            light: Some([1.0, i as f32, 2.0]),
            uniforms: vec![
                ("shininess".into(), vec![60.0]),
                ("sun.intensity".into(), vec![1.0 + i as f64]),
            ],
        }
    }

    /// What changes gets a key per frame; what does not, two keys (first and last) or a
    /// constant; struct members keep their siblings; the rest of the base stays.
    #[test]
    fn a_capture_keys_what_moves_and_keeps_the_rest() {
        let mut c = SessionCapture::from_json(base(), "base.json").unwrap();
        assert_eq!(c.object_count(), 2);
        for i in 0..4 {
            c.frame(frame(i)).unwrap();
        }
        let s = c.to_json().unwrap();
        assert_eq!(s["frames"], 4);
        assert_eq!(s["resolution"], json!([64, 64]));
        let camera = s["camera"]["keys"].as_array().unwrap();
        assert_eq!(
            camera.len(),
            2,
            "a still camera keeps its first and last key"
        );
        assert_eq!(
            (camera[0]["frame"].clone(), camera[1]["frame"].clone()),
            (json!(0), json!(3))
        );
        assert_eq!(s["light"]["keys"].as_array().unwrap().len(), 4);
        let objects = s["geometry"]["objects"].as_array().unwrap();
        assert_eq!(objects[0]["transform"]["keys"].as_array().unwrap().len(), 4);
        assert_eq!(objects[0]["transform"]["keys"][3]["matrix"][12], json!(1.5));
        assert_eq!(objects[1]["transform"]["keys"].as_array().unwrap().len(), 2);
        assert_eq!(objects[1]["mesh"], json!({"plane": {"size": 4}}));
        assert_eq!(s["uniforms"]["shininess"], json!(60.0));
        assert_eq!(s["uniforms"]["sun"]["color"], json!([1, 1, 1]));
        let intensity = s["uniforms"]["sun"]["intensity"]["keys"]
            .as_array()
            .unwrap();
        assert_eq!(intensity.len(), 4);
        assert_eq!(intensity[2], json!({"frame": 2, "value": 3.0}));
    }

    /// A frame that does not fit is refused with what is wrong, and nothing is recorded.
    #[test]
    fn frames_that_do_not_fit_are_refused() {
        let mut c = SessionCapture::from_json(base(), "base.json").unwrap();
        let mut f = frame(0);
        f.objects.pop();
        let e = c.frame(f).unwrap_err().to_string();
        assert!(
            e.contains("1 model matrices for the base session's 2 objects"),
            "{e}"
        );
        let mut f = frame(0);
        f.camera.near = f32::NAN;
        assert!(c.frame(f).unwrap_err().to_string().contains("not finite"));
        let mut f = frame(0);
        f.uniforms.push(("lights[0].color".into(), vec![1.0]));
        assert!(c.frame(f).unwrap_err().to_string().contains("member path"));
        assert!(c.is_empty());
        assert!(matches!(c.to_json(), Err(CaptureError::Empty)));
        c.frame(frame(0)).unwrap();
        let mut f = frame(1);
        f.light = None;
        assert!(
            c.frame(f)
                .unwrap_err()
                .to_string()
                .contains("every frame or in none")
        );
        let e = SessionCapture::from_json(json!({"schema": "x"}), "x.json").unwrap_err();
        assert!(e.to_string().contains("not a reproj session"), "{e}");
    }

    /// `write` leaves the session and nothing else.
    #[test]
    fn write_renames_a_whole_file_into_place() {
        let mut c = SessionCapture::from_json(base(), "base.json").unwrap();
        c.frame(frame(0)).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("captured.json");
        c.write(&path).unwrap();
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("captured.json")]);
        let back: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert_eq!(back, c.to_json().unwrap());
    }
}
