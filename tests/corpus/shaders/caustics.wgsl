// Stylized pool-floor caustics: two layers of animated Voronoi cells (the bright web between cells
// is the light the waves focus), slightly shifted per color channel for dispersion, projected
// from the light onto the floor tiles and faded with water depth. The number of layers, the
// chromatic split and the tile grout are pipeline `override` constants with defaults; the entry
// point returns an output struct with its one `@location`, filled field by field.

struct FragmentInput {
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

struct FragmentOutput {
    @location(0) color: vec4<f32>,
};

struct Scene {
    camera_pos: vec3<f32>,
    time: f32,
    light_pos: vec3<f32>,
    water_height: f32,
    water_color: vec3<f32>,
    caustic_scale: f32,
    light_color: vec3<f32>,
    caustic_speed: f32,
    caustic_intensity: f32,
    tiles_per_unit: f32,
    absorption: f32,
    _pad: f32,
};

override caustic_layers: u32 = 2u;
override dispersion: f32 = 0.012;
override grout_width: f32 = 0.04;

@group(0) @binding(0) var<uniform> scene: Scene;
@group(1) @binding(0) var tile_map: texture_2d<f32>;
@group(1) @binding(1) var linear_sampler: sampler;

fn hash22(p: vec2<f32>) -> vec2<f32> {
    let q = vec2<f32>(dot(p, vec2<f32>(127.1, 311.7)), dot(p, vec2<f32>(269.5, 183.3)));
    return fract(sin(q) * 43758.5453);
}

// Distance to the nearest cell border: small on the bright web.
fn voronoi_edge(p: vec2<f32>, t: f32) -> f32 {
    let cell = floor(p);
    let f = fract(p);
    var d1 = 8.0;
    var d2 = 8.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let o = vec2<f32>(f32(i), f32(j));
            let h = hash22(cell + o);
            let site = o + 0.5 + 0.45 * sin(t + 6.2831 * h);
            let d = length(site - f);
            if (d < d1) {
                d2 = d1;
                d1 = d;
            } else if (d < d2) {
                d2 = d;
            }
        }
    }
    return d2 - d1;
}

fn caustic(p: vec2<f32>, t: f32) -> f32 {
    var c = 0.0;
    var scale = 1.0;
    for (var k = 0u; k < caustic_layers; k++) {
        let e = voronoi_edge(p * scale + vec2<f32>(f32(k) * 3.7, 0.0), t * (1.0 + 0.3 * f32(k)));
        c += pow(1.0 - smoothstep(0.0, 0.22, e), 3.0) / scale;
        scale *= 1.7;
    }
    return c;
}

@fragment
fn fs_main(in: FragmentInput) -> FragmentOutput {
    var out: FragmentOutput;
    let n = normalize(in.normal);

    // Floor tiles with grout.
    let tuv = in.uv * scene.tiles_per_unit;
    let edge = min(fract(tuv), vec2<f32>(1.0) - fract(tuv));
    let grout = smoothstep(grout_width, grout_width + 0.02, min(edge.x, edge.y));
    let tile = textureSample(tile_map, linear_sampler, in.uv).rgb;
    let albedo = mix(vec3<f32>(0.35, 0.38, 0.4), tile, grout);

    // Project the caustic pattern along the light direction onto the water plane.
    let l = normalize(scene.light_pos - in.world_pos);
    let depth = max(scene.water_height - in.world_pos.y, 0.0);
    let on_surface = in.world_pos.xz + l.xz / max(l.y, 0.2) * depth;
    let p = on_surface * scene.caustic_scale;
    let t = scene.time * scene.caustic_speed;
    let shift = l.xz * dispersion * scene.caustic_scale;
    let rgb = vec3<f32>(caustic(p + shift, t), caustic(p, t), caustic(p - shift, t));

    // Light through the water: Beer–Lambert on the path down and back up.
    let path = depth / max(l.y, 0.2) + depth;
    let transmit = exp(-scene.absorption * path * (vec3<f32>(1.0) - scene.water_color));
    let n_l = max(dot(n, l), 0.0);
    let lit = scene.light_color * transmit * (n_l * (0.6 + scene.caustic_intensity * rgb));

    out.color = vec4<f32>(albedo * (lit + scene.water_color * 0.15), 1.0);
    out.color = vec4<f32>(out.color.rgb / (out.color.rgb + vec3<f32>(1.0)), out.color.a);
    return out;
}
