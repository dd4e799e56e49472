// Point and spot lights through helpers that return early, as hand-written engine shaders do:
// no light behind the surface or past its range, a cone test that returns before its smooth
// edge, and a tone curve that leaves a loop with `return`. reproj rewrites each helper to one
// exit before inlining it (the early returns become stores and guarded code).

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    light_range: f32,
    light_color: vec3<f32>,
    spot_cos_outer: f32,
    spot_dir: vec3<f32>,
    spot_cos_inner: f32,
    albedo: vec3<f32>,
    exposure: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;

fn range_falloff(dist: f32, range: f32) -> f32 {
    if dist >= range {
        return 0.0;
    }
    let x = dist / range;
    let s = clamp(1.0 - x * x * x * x, 0.0, 1.0);
    return s * s / (dist * dist + 1.0);
}

fn spot_factor(l: vec3<f32>) -> f32 {
    let cos_angle = dot(-l, normalize(scene.spot_dir));
    if cos_angle <= scene.spot_cos_outer {
        return 0.0;
    }
    if cos_angle >= scene.spot_cos_inner {
        return 1.0;
    }
    return smoothstep(scene.spot_cos_outer, scene.spot_cos_inner, cos_angle);
}

fn blinn_phong(n: vec3<f32>, l: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let n_dot_l = dot(n, l);
    if n_dot_l <= 0.0 {
        return vec3<f32>(0.0);
    }
    let h = normalize(l + v);
    let spec = pow(max(dot(n, h), 0.0), 64.0) * 0.5;
    return scene.albedo * n_dot_l + vec3<f32>(spec);
}

// A stepped tone curve: the first band the value falls under.
fn banded(x: f32) -> f32 {
    for (var i = 1; i <= 4; i++) {
        let edge = f32(i) * 0.25;
        if x < edge {
            return edge - 0.125;
        }
    }
    return 1.0;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let to_light = scene.light_pos - in.world_pos;
    let dist = length(to_light);
    let l = to_light / dist;
    let v = normalize(scene.camera_pos - in.world_pos);
    let light = scene.light_color * range_falloff(dist, scene.light_range) * spot_factor(l);
    let lit = blinn_phong(n, l, v) * light * 8.0 + scene.albedo * 0.05;
    let mapped = vec3<f32>(1.0) - exp(-lit * scene.exposure);
    let luma = dot(mapped, vec3<f32>(0.2126, 0.7152, 0.0722));
    let toon = mapped * (banded(luma) / max(luma, 1e-3));
    return vec4<f32>(mix(mapped, toon, 0.35), 1.0);
}
