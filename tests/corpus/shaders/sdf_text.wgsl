// Signed-distance-field text (Valve's "Improved Alpha-Tested Magnification"), as in engine UI and
// world-space label shaders: the glyph atlas stores distance in R (0.5 = edge); the edge is
// antialiased over one screen pixel with `fwidth`, plus an outline band, a soft drop shadow from a
// second offset lookup, and glyphs composited over a panel color.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    outline_width: f32,
    text_color: vec3<f32>,
    shadow_softness: f32,
    outline_color: vec3<f32>,
    atlas_scale: f32,
    panel_color: vec3<f32>,
    shadow_offset: vec2<f32>,
};

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var glyph_atlas: texture_2d<f32>;
@group(1) @binding(1) var atlas_sampler: sampler;

@fragment
fn fs_main(in: FragmentInput) -> @location(0) vec4<f32> {
    let uv = in.uv * scene.atlas_scale;
    let dist = textureSample(glyph_atlas, atlas_sampler, uv).r;
    let width = fwidth(dist) * 0.7;
    let fill = smoothstep(0.5 - width, 0.5 + width, dist);
    let outline_edge = 0.5 - scene.outline_width;
    let outline = smoothstep(outline_edge - width, outline_edge + width, dist);
    let shadow_dist = textureSample(glyph_atlas, atlas_sampler, uv - scene.shadow_offset).r;
    let shadow = smoothstep(0.5 - scene.shadow_softness, 0.5 + scene.shadow_softness, shadow_dist) * 0.6;
    let n = normalize(in.normal);
    let l = normalize(scene.light_pos - in.world_pos);
    let panel = scene.panel_color * (0.4 + 0.6 * max(dot(n, l), 0.0));
    let behind = panel * (1.0 - shadow);
    let glyph = mix(scene.outline_color, scene.text_color, fill);
    let color = mix(behind, glyph, outline);
    return vec4<f32>(color, 1.0);
}
