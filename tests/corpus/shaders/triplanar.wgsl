// Triplanar mapping for meshes without usable uvs (rocks, cliffs, voxel terrain), as in engine
// triplanar material functions: albedo and normal maps projected along X, Y and Z with sharpened
// blend weights; normals combined with the "whiteout" blend per axis (Ben Golus) and swizzled back
// to world space; Lambert + Blinn–Phong.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    texture_scale: f32,
    light_color: vec3<f32>,
    blend_sharpness: f32,
    ambient_color: vec3<f32>,
    shininess: f32,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var albedo_map: texture_2d<f32>;
@group(1) @binding(1) var normal_map: texture_2d<f32>;
@group(1) @binding(2) var linear_sampler: sampler;

fn unpack(uv: vec2<f32>) -> vec3<f32> {
    return textureSample(normal_map, linear_sampler, uv).xyz * 2.0 - 1.0;
}

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let geo_n = normalize(in.normal);
    let p = in.world_pos * scene.texture_scale;
    var w = pow(abs(geo_n), vec3<f32>(scene.blend_sharpness));
    w = w / (w.x + w.y + w.z);
    let uv_x = p.zy;
    let uv_y = p.xz;
    let uv_z = p.xy;
    let col = textureSample(albedo_map, linear_sampler, uv_x).rgb * w.x
        + textureSample(albedo_map, linear_sampler, uv_y).rgb * w.y
        + textureSample(albedo_map, linear_sampler, uv_z).rgb * w.z;
    let tn_x = unpack(uv_x);
    let tn_y = unpack(uv_y);
    let tn_z = unpack(uv_z);
    let wx = vec3<f32>(tn_x.xy + geo_n.zy, abs(tn_x.z) * geo_n.x);
    let wy = vec3<f32>(tn_y.xy + geo_n.xz, abs(tn_y.z) * geo_n.y);
    let wz = vec3<f32>(tn_z.xy + geo_n.xy, abs(tn_z.z) * geo_n.z);
    let n = normalize(wx.zyx * w.x + wy.xzy * w.y + wz.xyz * w.z);
    let l = normalize(scene.light_pos - in.world_pos);
    let v = normalize(scene.camera_pos - in.world_pos);
    let h = normalize(l + v);
    let diffuse = col * max(dot(n, l), 0.0);
    let spec = pow(max(dot(n, h), 0.0), scene.shininess) * 0.15;
    let color = scene.ambient_color * col + (diffuse + vec3<f32>(spec)) * scene.light_color;
    return vec4<f32>(clamp(color, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}
