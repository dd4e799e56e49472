//! Session validation: range and consistency checks, one message per fault naming the JSON
//! path of the field. Loading first puts every key-framed path in frame order
//! ([`Session::sort_keys`]); [`Session::validate`] takes `&self` and only checks, so the renderer
//! validates the very session it renders.

use glam::Vec3;

use super::*;

/// Every number of `value` fits an `f32`: the GPU reads 32-bit values, and a larger one (1e39)
/// would silently become infinity. The error is (JSON path, message).
fn check_f32(value: &Value, field: &str) -> Result<(), (String, String)> {
    match value
        .flatten()
        .into_iter()
        .find(|x| x.abs() > f64::from(f32::MAX))
    {
        Some(x) => Err((
            field.to_owned(),
            format!(
                "{x:e} is out of range: uniform and buffer values are 32-bit floats (at most about ±3.4e38)"
            ),
        )),
        None => Ok(()),
    }
}

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

impl UniformValue {
    /// Sort the key frames of this value and of every value nested in it.
    pub(crate) fn sort_keys(&mut self) {
        match self {
            UniformValue::Keys { keys } => keys.sort_by(|a, b| a.frame.total_cmp(&b.frame)),
            UniformValue::Const(_) => {}
            UniformValue::Struct(m) => m.values_mut().for_each(UniformValue::sort_keys),
            UniformValue::Array(a) => a.iter_mut().for_each(UniformValue::sort_keys),
        }
    }

    /// Key frames of this value and every nested one: present, in order, all of one length.
    /// The error is (JSON path, message).
    pub(crate) fn check_keys(&self, field: &str) -> Result<(), (String, String)> {
        match self {
            UniformValue::Const(v) => check_f32(v, field),
            UniformValue::Struct(m) => m
                .iter()
                .try_for_each(|(k, v)| v.check_keys(&format!("{field}.{k}"))),
            UniformValue::Array(a) => a
                .iter()
                .enumerate()
                .try_for_each(|(i, v)| v.check_keys(&format!("{field}[{i}]"))),
            UniformValue::Keys { keys } => {
                let field = format!("{field}.keys");
                if keys.is_empty() {
                    return Err((field, "needs at least one key".into()));
                }
                if !in_order(keys.iter().map(|k| k.frame)) {
                    return Err((
                        field,
                        "keys must be in frame order (Session::load sorts them)".into(),
                    ));
                }
                let n = keys[0].value.flatten().len();
                if keys.iter().any(|k| k.value.flatten().len() != n) {
                    return Err((
                        field,
                        "every key needs the same number of components".into(),
                    ));
                }
                keys.iter()
                    .enumerate()
                    .try_for_each(|(i, k)| check_f32(&k.value, &format!("{field}[{i}].value")))
            }
        }
    }
}

impl TransformKey {
    /// What is wrong with the key's `matrix`, if anything: a number that is not finite, a last
    /// row other than (0, 0, 0, 1) (the model matrix is affine), or `translation`, `rotation` or
    /// `scale` given beside it.
    fn matrix_problem(&self) -> Option<String> {
        let m = self.matrix.as_ref()?;
        if let Some(i) = m.iter().position(|x| !x.is_finite()) {
            return Some(format!("element {i} is not a finite number"));
        }
        // Column-major: the last row is elements 3, 7, 11 and 15.
        let row = [m[3], m[7], m[11], m[15]];
        if row != [0.0, 0.0, 0.0, 1.0] {
            return Some(format!(
                "the last row (elements 3, 7, 11, 15: column-major) is {row:?}, expected [0, 0, 0, 1]: a model matrix is affine"
            ));
        }
        let default_scale = matches!(self.scale, Scale::Uniform(s) if s == 1.0);
        if self.translation != [0.0; 3] || self.rotation.is_some() || !default_scale {
            return Some(
                "`matrix` replaces `translation`, `rotation` and `scale`: give one or the others"
                    .into(),
            );
        }
        None
    }
}

impl Session {
    /// The session's value of the uniform leaf at `path` (`shininess`, `sun.color`,
    /// `lights[2].position`, as [`crate::reflect`] names the leaves).
    pub fn uniform(&self, path: &str) -> Option<&UniformValue> {
        let steps = path_steps(path);
        let (PathStep::Member(first), rest) = steps.split_first()? else {
            return None;
        };
        self.uniforms.get(*first)?.lookup(rest)
    }

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
        for u in self.uniforms.values_mut().chain(self.buffers.values_mut()) {
            u.sort_keys();
        }
        for d in self.depth_passes.values_mut() {
            if let ViewProj::Matrix(m) = &mut d.view_proj {
                m.sort_keys();
            }
        }
    }

    pub(crate) fn invalid(
        &self,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> SessionError {
        SessionError::Invalid {
            path: self.path.clone(),
            field: field.into(),
            message: message.into(),
        }
    }

    /// Range and consistency checks (called by [`Session::load`], and by the renderer before a
    /// replay). Key frames must be in frame order: loading sorts them ([`Session::sort_keys`]);
    /// a session built in code whose keys are out of order is an error here. The checks run in
    /// this order and the first fault is the error.
    pub fn validate(&self) -> Result<(), SessionError> {
        self.check_header()?;
        self.check_objects()?;
        self.check_camera()?;
        self.check_light()?;
        self.check_values()?;
        self.check_depth_passes()
    }

    /// Schema, version, resolution, frame count and rate.
    fn check_header(&self) -> Result<(), SessionError> {
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
        Ok(())
    }

    /// Every object: its transform keys and its mesh.
    fn check_objects(&self) -> Result<(), SessionError> {
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
            for (k, key) in o.transform.keys.iter().enumerate() {
                if let Some(message) = key.matrix_problem() {
                    return Err(SessionError::Invalid {
                        path: self.path.clone(),
                        field: format!("{f}.transform.keys[{k}].matrix"),
                        message,
                    });
                }
                // A zero axis has no direction: the rotation would silently be none at all.
                if let Some(Rotation::AxisAngle { axis, .. }) = &key.rotation
                    && !(axis.iter().all(|x| x.is_finite()) && Vec3::from(*axis).length() > 0.0)
                {
                    return Err(SessionError::Invalid {
                        path: self.path.clone(),
                        field: format!("{f}.transform.keys[{k}].rotation.axis_angle.axis"),
                        message: format!(
                            "{axis:?} is not a direction: a rotation axis needs a finite, non-zero length"
                        ),
                    });
                }
            }
            self.check_mesh(&f, &o.mesh)?;
        }
        Ok(())
    }

    /// One object's mesh (`field`: its JSON path): sizes and counts in range.
    fn check_mesh(&self, field: &str, mesh: &Mesh) -> Result<(), SessionError> {
        let bad = |m: &str| SessionError::Invalid {
            path: self.path.clone(),
            field: format!("{field}.mesh"),
            message: m.to_owned(),
        };
        match mesh {
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
            Mesh::Obj { .. } | Mesh::Gltf { .. } => {}
        }
        if [
            matches!(mesh, Mesh::Sphere { segments, rings, .. } if *segments > 4096 || rings.is_some_and(|r| r > 4096)),
            matches!(mesh, Mesh::Torus { segments, sides, .. } if *segments > 4096 || *sides > 4096),
            matches!(mesh, Mesh::Lathe { segments, .. } if *segments > 4096),
        ]
        .iter()
        .any(|b| *b)
        {
            return Err(bad("at most 4096 segments"));
        }
        Ok(())
    }

    /// The camera path: keys present and in order with a sound projection, or an orbit.
    fn check_camera(&self) -> Result<(), SessionError> {
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
            CameraPath::Gltf => {
                return Err(self.invalid("camera", "\"gltf\" needs a `gltf` scene with a camera"));
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
        Ok(())
    }

    /// The light path's keys: present and in order.
    fn check_light(&self) -> Result<(), SessionError> {
        if let PointPath::Keys(keys) = &self.light {
            if keys.is_empty() {
                return Err(self.invalid("light.keys", "needs at least one key"));
            }
            if !in_order(keys.iter().map(|k| k.frame)) {
                return Err(unordered(self, "light.keys".into()));
            }
        }
        Ok(())
    }

    /// Uniform values, textures, samplers and storage-buffer values.
    fn check_values(&self) -> Result<(), SessionError> {
        for (name, u) in self.uniforms.iter() {
            u.check_keys(&format!("uniforms.{name}"))
                .map_err(|(field, message)| self.invalid(field, message))?;
        }
        for (name, t) in &self.textures {
            self.check_texture(&format!("textures.{name}"), t, true)?;
        }
        for (name, s) in &self.samplers {
            if s.anisotropy == 0 || s.anisotropy > 16 {
                return Err(
                    self.invalid(format!("samplers.{name}.anisotropy"), "must be in 1..=16")
                );
            }
        }
        for (name, b) in &self.buffers {
            b.check_keys(&format!("buffers.{name}"))
                .map_err(|(field, message)| self.invalid(field, message))?;
        }
        Ok(())
    }

    /// Depth passes: their size, and a view-projection that resolves to 16 numbers.
    fn check_depth_passes(&self) -> Result<(), SessionError> {
        for (name, d) in &self.depth_passes {
            let field = format!("depth_passes.{name}");
            if let Some([w, h]) = d.size
                && (w == 0 || h == 0 || w > 8192 || h > 8192)
            {
                return Err(self.invalid(
                    format!("{field}.size"),
                    format!("{w}×{h} is out of range (1..=8192 each)"),
                ));
            }
            let matrix = match &d.view_proj {
                ViewProj::Camera => None,
                ViewProj::Uniform(u) => Some(self.uniform(u).ok_or_else(|| {
                    self.invalid(
                        format!("{field}.view_proj.uniform"),
                        format!("the session's `uniforms` has no `{u}`"),
                    )
                })?),
                ViewProj::Matrix(m) => {
                    m.check_keys(&format!("{field}.view_proj.matrix"))
                        .map_err(|(f, message)| self.invalid(f, message))?;
                    Some(m)
                }
            };
            if let Some(m) = matrix
                && m.len() != 16
            {
                return Err(self.invalid(
                    format!("{field}.view_proj"),
                    format!(
                        "a view-projection is a mat4x4 (16 numbers, column-major); this value has {}",
                        m.len()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// One texture spec at JSON path `field`; `layers` are allowed at the top level only.
    fn check_texture(&self, field: &str, t: &TextureSpec, top: bool) -> Result<(), SessionError> {
        let forms = t.kind.is_some() as u32
            + t.file.is_some() as u32
            + t.faces.is_some() as u32
            + t.layers.is_some() as u32
            + t.gltf.is_some() as u32;
        if forms != 1 {
            return Err(self.invalid(
                field,
                "give exactly one of `kind`, `file`, `faces`, `layers`, `gltf`",
            ));
        }
        if let Some(layers) = &t.layers {
            if !top {
                return Err(self.invalid(
                    format!("{field}.layers"),
                    "a layer cannot have layers of its own",
                ));
            }
            if layers.is_empty() || layers.len() > 256 {
                return Err(self.invalid(format!("{field}.layers"), "needs 1..=256 layers"));
            }
            for (i, l) in layers.iter().enumerate() {
                self.check_texture(&format!("{field}.layers[{i}]"), l, false)?;
            }
        }
        if let Some(f) = &t.faces
            && f.len() != 6
        {
            return Err(self.invalid(
                format!("{field}.faces"),
                "needs six images (+X, −X, +Y, −Y, +Z, −Z)",
            ));
        }
        if t.size == 0 || t.size > 4096 {
            return Err(self.invalid(format!("{field}.size"), "must be in 1..=4096"));
        }
        Ok(())
    }
}
