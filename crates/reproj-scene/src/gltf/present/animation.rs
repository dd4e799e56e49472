//! glTF animation, sampled: each channel's keyframes (step, linear, cubic spline) at a time,
//! the nodes' local transforms they drive, the world matrices down the node tree, and a world
//! matrix as a session transform key.

use glam::{Mat4, Quat, Vec3};
use gltf::animation::{Interpolation, Property, util::ReadOutputs};

use super::Imported;
use crate::session::{Rotation, Scale, TransformKey};

/// One node's local transform, as glTF stores it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Trs {
    t: Vec3,
    r: Quat,
    s: Vec3,
}

impl Trs {
    fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.s, self.r, self.t)
    }
}

/// One animation channel's keyframes.
pub(super) struct Channel {
    node: usize,
    times: Vec<f32>,
    /// One value per key (three per key, in-tangent / value / out-tangent, for CUBICSPLINE);
    /// translations and scales use the first three components.
    values: Vec<[f32; 4]>,
    property: Property,
    interpolation: Interpolation,
}

impl Channel {
    /// The value at `time` (held before the first key and after the last).
    fn sample(&self, time: f32) -> [f32; 4] {
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let value = |k: usize| {
            if cubic {
                self.values[3 * k + 1]
            } else {
                self.values[k]
            }
        };
        let n = self.times.len();
        if n == 0 {
            return [0.0, 0.0, 0.0, 1.0];
        }
        if time <= self.times[0] {
            return value(0);
        }
        if time >= self.times[n - 1] {
            return value(n - 1);
        }
        let k = self.times.partition_point(|&t| t <= time) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let dt = t1 - t0;
        let u = if dt > 0.0 { (time - t0) / dt } else { 0.0 };
        let rotation = self.property == Property::Rotation;
        match self.interpolation {
            Interpolation::Step => value(k),
            Interpolation::Linear => {
                let (a, b) = (value(k), value(k + 1));
                if rotation {
                    Quat::from_array(a)
                        .normalize()
                        .slerp(Quat::from_array(b).normalize(), u)
                        .to_array()
                } else {
                    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * u)
                }
            }
            Interpolation::CubicSpline => {
                let (p0, m0) = (value(k), self.values[3 * k + 2]);
                let (p1, m1) = (value(k + 1), self.values[3 * (k + 1)]);
                let (u2, u3) = (u * u, u * u * u);
                let h = [
                    2.0 * u3 - 3.0 * u2 + 1.0,
                    u3 - 2.0 * u2 + u,
                    -2.0 * u3 + 3.0 * u2,
                    u3 - u2,
                ];
                let v: [f32; 4] = std::array::from_fn(|i| {
                    h[0] * p0[i] + h[1] * m0[i] * dt + h[2] * p1[i] + h[3] * m1[i] * dt
                });
                if rotation {
                    Quat::from_array(v).normalize().to_array()
                } else {
                    v
                }
            }
        }
    }
}

/// The file's animation channels that move nodes (morph target weights are left out).
pub(super) fn channels(g: &Imported) -> Vec<Channel> {
    let mut out = Vec::new();
    for anim in g.doc.animations() {
        for ch in anim.channels() {
            let reader = ch.reader(|b| g.buffers.get(b.index()).map(|d| &d.0[..]));
            let (Some(times), Some(outputs)) = (reader.read_inputs(), reader.read_outputs()) else {
                continue;
            };
            let values: Vec<[f32; 4]> = match outputs {
                ReadOutputs::Translations(v) => v.map(|[x, y, z]| [x, y, z, 0.0]).collect(),
                ReadOutputs::Scales(v) => v.map(|[x, y, z]| [x, y, z, 0.0]).collect(),
                ReadOutputs::Rotations(v) => v.into_f32().collect(),
                ReadOutputs::MorphTargetWeights(_) => continue,
            };
            out.push(Channel {
                node: ch.target().node().index(),
                times: times.collect(),
                values,
                property: ch.target().property(),
                interpolation: ch.sampler().interpolation(),
            });
        }
    }
    out
}

/// Every node's local transform at `time`: the stored one with the animated parts replaced.
pub(super) fn locals_at(g: &Imported, channels: &[Channel], time: f32) -> Vec<Trs> {
    let mut locals: Vec<Trs> = g
        .doc
        .nodes()
        .map(|n| {
            let (t, r, s) = n.transform().decomposed();
            Trs {
                t: Vec3::from(t),
                r: Quat::from_array(r),
                s: Vec3::from(s),
            }
        })
        .collect();
    for c in channels {
        let v = c.sample(time);
        let l = &mut locals[c.node];
        match c.property {
            Property::Translation => l.t = Vec3::new(v[0], v[1], v[2]),
            Property::Rotation => l.r = Quat::from_array(v).normalize(),
            Property::Scale => l.s = Vec3::new(v[0], v[1], v[2]),
            Property::MorphTargetWeights => {}
        }
    }
    locals
}

/// World matrices of the scene's nodes (depth first from its roots), with their nodes.
pub(super) fn world<'a>(
    scene: &gltf::Scene<'a>,
    locals: &[Trs],
) -> Result<Vec<(gltf::Node<'a>, Mat4)>, String> {
    fn visit<'a>(
        node: gltf::Node<'a>,
        parent: Mat4,
        locals: &[Trs],
        depth: usize,
        out: &mut Vec<(gltf::Node<'a>, Mat4)>,
    ) -> Result<(), String> {
        if depth > 64 {
            return Err("the node hierarchy is deeper than 64 levels (a cycle?)".into());
        }
        let m = parent * locals[node.index()].matrix();
        out.push((node.clone(), m));
        for child in node.children() {
            visit(child, m, locals, depth + 1, out)?;
        }
        Ok(())
    }
    let mut out = Vec::new();
    for root in scene.nodes() {
        visit(root, Mat4::IDENTITY, locals, 0, &mut out)?;
    }
    Ok(out)
}

/// A transform key from a world matrix.
pub(super) fn key(frame: f32, m: Mat4) -> TransformKey {
    let (s, r, t) = m.to_scale_rotation_translation();
    let (axis, angle) = r.normalize().to_axis_angle();
    TransformKey {
        frame,
        translation: t.to_array(),
        rotation: (angle.abs() > 1e-7).then(|| Rotation::AxisAngle {
            axis: axis.to_array(),
            deg: angle.to_degrees(),
        }),
        scale: Scale::PerAxis(s.to_array()),
        matrix: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(interpolation: Interpolation, property: Property, values: Vec<[f32; 4]>) -> Channel {
        Channel {
            node: 0,
            times: vec![0.0, 1.0],
            values,
            property,
            interpolation,
        }
    }

    #[test]
    fn linear_step_and_cubic_channels_sample_their_keys_and_between() {
        let c = channel(
            Interpolation::Linear,
            Property::Translation,
            vec![[0.0, 0.0, 0.0, 0.0], [2.0, 4.0, 0.0, 0.0]],
        );
        assert_eq!(c.sample(0.0), [0.0; 4]);
        assert_eq!(c.sample(0.5), [1.0, 2.0, 0.0, 0.0]);
        assert_eq!(
            c.sample(9.0),
            [2.0, 4.0, 0.0, 0.0],
            "held after the last key"
        );
        let s = channel(
            Interpolation::Step,
            Property::Scale,
            vec![[1.0, 1.0, 1.0, 0.0], [3.0, 3.0, 3.0, 0.0]],
        );
        assert_eq!(s.sample(0.99), [1.0, 1.0, 1.0, 0.0]);
        assert_eq!(s.sample(1.0), [3.0, 3.0, 3.0, 0.0]);
        let q = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let r = channel(
            Interpolation::Linear,
            Property::Rotation,
            vec![Quat::IDENTITY.to_array(), q.to_array()],
        );
        let half = Quat::from_array(r.sample(0.5));
        assert!(half.angle_between(Quat::from_rotation_y(std::f32::consts::FRAC_PI_4)) < 1e-5);
        // Cubic spline with zero tangents: the values at the keys, smooth in between.
        let z = [0.0; 4];
        let cubic = Channel {
            values: vec![z, [0.0, 0.0, 0.0, 0.0], z, z, [1.0, 0.0, 0.0, 0.0], z],
            ..channel(Interpolation::CubicSpline, Property::Translation, vec![])
        };
        assert_eq!(cubic.sample(0.0)[0], 0.0);
        assert_eq!(cubic.sample(1.0)[0], 1.0);
        assert!((cubic.sample(0.5)[0] - 0.5).abs() < 1e-6);
    }

    #[test]
    fn a_world_matrix_round_trips_through_a_transform_key() {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(1.0, 2.0, 1.0),
            Quat::from_rotation_x(0.7),
            Vec3::new(1.0, -2.0, 3.0),
        );
        let k = key(3.0, m);
        let Some(Rotation::AxisAngle { axis, deg }) = k.rotation else {
            panic!("{k:?}")
        };
        let back = Mat4::from_scale_rotation_translation(
            match k.scale {
                Scale::PerAxis(s) => Vec3::from(s),
                Scale::Uniform(s) => Vec3::splat(s),
            },
            Quat::from_axis_angle(Vec3::from(axis), deg.to_radians()),
            Vec3::from(k.translation),
        );
        assert!(back.abs_diff_eq(m, 1e-5), "{back} vs {m}");
    }
}
