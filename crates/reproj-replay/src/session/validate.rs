//! Session validation: range and consistency checks, one message per fault naming the JSON
//! path of the field. Loading first puts every key-framed path in frame order
//! ([`Session::sort_keys`]); [`Session::validate`] takes `&self` and only checks, so the renderer
//! validates the very session it renders.

use glam::Vec3;

use super::*;

/// True for finite numbers > 0 (false for NaN).
fn positive(x: f32) -> bool {
    x.is_finite() && x > 0.0
}

/// True when the key frames are in non-decreasing order (as [`Session::sort_keys`] leaves them).
fn in_order(frames: impl Iterator<Item = f32>) -> bool {
    let frames: Vec<f32> = frames.collect();
    frames.windows(2).all(|w| w[0].total_cmp(&w[1]).is_le())
}

fn unordered(s: &Session, field: String) -> SessionError {
    s.invalid(
        field,
        "keys must be in frame order (Session::load sorts them)",
    )
}

impl Session {
    /// Sort every key-framed path (object transforms, camera, light, uniforms) by frame, as
    /// loading does before validation: key frames may be written in any order.
    pub fn sort_keys(&mut self) {
        for o in &mut self.geometry.objects {
            o.transform.keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
        }
        if let CameraPath::Keys(keys) = &mut self.camera {
            keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
        }
        if let PointPath::Keys(keys) = &mut self.light {
            keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
        }
        for u in self.uniforms.values_mut() {
            if let UniformValue::Keys { keys } = u {
                keys.sort_by(|a, b| a.frame.total_cmp(&b.frame));
            }
        }
    }

    fn invalid(&self, field: impl Into<String>, message: impl Into<String>) -> SessionError {
        SessionError::Invalid {
            path: self.path.clone(),
            field: field.into(),
            message: message.into(),
        }
    }

    /// Range and consistency checks (called by [`Session::load`], and by the renderer before a
    /// replay). Key frames must be in frame order: loading sorts them ([`Session::sort_keys`]);
    /// a session built in code whose keys are out of order is an error here.
    pub fn validate(&self) -> Result<(), SessionError> {
        if self.schema != SESSION_SCHEMA {
            return Err(self.invalid(
                "schema",
                format!("expected \"{SESSION_SCHEMA}\", found \"{}\"", self.schema),
            ));
        }
        if self.version != SESSION_VERSION {
            return Err(self.invalid(
                "version",
                format!(
                    "unsupported version {} (this reproj reads version {SESSION_VERSION})",
                    self.version
                ),
            ));
        }
        let [w, h] = self.resolution;
        if w == 0 || h == 0 || w > 8192 || h > 8192 {
            return Err(self.invalid(
                "resolution",
                format!("{w}×{h} is out of range (1..=8192 each)"),
            ));
        }
        if self.frames == 0 {
            return Err(self.invalid("frames", "must be at least 1"));
        }
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return Err(self.invalid("fps", "must be a positive number"));
        }
        if self.geometry.objects.is_empty() {
            return Err(self.invalid("geometry.objects", "the scene has no objects"));
        }
        for (i, o) in self.geometry.objects.iter().enumerate() {
            let f = format!("geometry.objects[{i}]");
            if o.transform.keys.is_empty() {
                return Err(SessionError::Invalid {
                    path: self.path.clone(),
                    field: format!("{f}.transform.keys"),
                    message: "needs at least one key".into(),
                });
            }
            if !in_order(o.transform.keys.iter().map(|k| k.frame)) {
                return Err(unordered(self, format!("{f}.transform.keys")));
            }
            let bad = |m: &str| SessionError::Invalid {
                path: self.path.clone(),
                field: format!("{f}.mesh"),
                message: m.to_owned(),
            };
            match &o.mesh {
                Mesh::Sphere {
                    radius,
                    segments,
                    rings,
                } => {
                    if !positive(*radius) || *segments < 3 || rings.is_some_and(|r| r < 2) {
                        return Err(bad("sphere needs radius > 0, segments ≥ 3, rings ≥ 2"));
                    }
                }
                Mesh::Torus {
                    major_radius,
                    minor_radius,
                    segments,
                    sides,
                } => {
                    if !(positive(*major_radius) && positive(*minor_radius))
                        || *segments < 3
                        || *sides < 3
                    {
                        return Err(bad("torus needs radii > 0, segments ≥ 3, sides ≥ 3"));
                    }
                }
                Mesh::Plane {
                    size, subdivisions, ..
                } => {
                    if !positive(*size) || *subdivisions == 0 || *subdivisions > 1024 {
                        return Err(bad("plane needs size > 0 and 1 ≤ subdivisions ≤ 1024"));
                    }
                }
                Mesh::Cube { size } => {
                    if size.iter().any(|s| !positive(*s)) {
                        return Err(bad("cube needs every size > 0"));
                    }
                }
                Mesh::Lathe { profile, segments } => {
                    if profile.len() < 2 || *segments < 3 || profile.iter().any(|p| p[0] < 0.0) {
                        return Err(bad(
                            "lathe needs ≥ 2 profile points with radius ≥ 0 and segments ≥ 3",
                        ));
                    }
                }
                Mesh::Obj { .. } => {}
            }
            if [
                matches!(&o.mesh, Mesh::Sphere { segments, rings, .. } if *segments > 4096 || rings.is_some_and(|r| r > 4096)),
                matches!(&o.mesh, Mesh::Torus { segments, sides, .. } if *segments > 4096 || *sides > 4096),
                matches!(&o.mesh, Mesh::Lathe { segments, .. } if *segments > 4096),
            ]
            .iter()
            .any(|b| *b)
            {
                return Err(bad("at most 4096 segments"));
            }
        }
        match &self.camera {
            CameraPath::Keys(keys) => {
                if keys.is_empty() {
                    return Err(self.invalid("camera.keys", "needs at least one key"));
                }
                if !in_order(keys.iter().map(|k| k.frame)) {
                    return Err(unordered(self, "camera.keys".into()));
                }
                for (i, k) in keys.iter().enumerate() {
                    if !(k.near > 0.0 && k.far > k.near && k.fov_y_deg > 0.0 && k.fov_y_deg < 180.0)
                    {
                        return Err(SessionError::Invalid {
                            path: self.path.clone(),
                            field: format!("camera.keys[{i}]"),
                            message: "needs 0 < near < far and 0 < fov_y_deg < 180".into(),
                        });
                    }
                    if Vec3::from(k.eye) == Vec3::from(k.target) {
                        return Err(SessionError::Invalid {
                            path: self.path.clone(),
                            field: format!("camera.keys[{i}]"),
                            message: "eye and target coincide".into(),
                        });
                    }
                }
            }
            CameraPath::Orbit(o) => {
                if !(o.near > 0.0 && o.far > o.near && o.fov_y_deg > 0.0 && o.fov_y_deg < 180.0) {
                    return Err(self.invalid(
                        "camera.orbit",
                        "needs 0 < near < far and 0 < fov_y_deg < 180",
                    ));
                }
                if !positive(o.radius) {
                    return Err(self.invalid("camera.orbit.radius", "must be > 0"));
                }
            }
        }
        if let PointPath::Keys(keys) = &self.light {
            if keys.is_empty() {
                return Err(self.invalid("light.keys", "needs at least one key"));
            }
            if !in_order(keys.iter().map(|k| k.frame)) {
                return Err(unordered(self, "light.keys".into()));
            }
        }
        for (name, u) in self.uniforms.iter() {
            if let UniformValue::Keys { keys } = u {
                if keys.is_empty() {
                    return Err(SessionError::Invalid {
                        path: self.path.clone(),
                        field: format!("uniforms.{name}.keys"),
                        message: "needs at least one key".into(),
                    });
                }
                if !in_order(keys.iter().map(|k| k.frame)) {
                    return Err(unordered(self, format!("uniforms.{name}.keys")));
                }
                let n = keys[0].value.flatten().len();
                if keys.iter().any(|k| k.value.flatten().len() != n) {
                    return Err(SessionError::Invalid {
                        path: self.path.clone(),
                        field: format!("uniforms.{name}.keys"),
                        message: "every key needs the same number of components".into(),
                    });
                }
            }
        }
        for (name, t) in &self.textures {
            let forms =
                t.kind.is_some() as u32 + t.file.is_some() as u32 + t.faces.is_some() as u32;
            if forms != 1 {
                return Err(self.invalid(
                    format!("textures.{name}"),
                    "give exactly one of `kind`, `file`, `faces`",
                ));
            }
            if let Some(f) = &t.faces
                && f.len() != 6
            {
                return Err(self.invalid(
                    format!("textures.{name}.faces"),
                    "needs six images (+X, −X, +Y, −Y, +Z, −Z)",
                ));
            }
            if t.size == 0 || t.size > 4096 {
                return Err(self.invalid(format!("textures.{name}.size"), "must be in 1..=4096"));
            }
        }
        for (name, s) in &self.samplers {
            if s.anisotropy == 0 || s.anisotropy > 16 {
                return Err(
                    self.invalid(format!("samplers.{name}.anisotropy"), "must be in 1..=16")
                );
            }
        }
        Ok(())
    }
}
