#version 450
// marble.frag: shaders/marble.wgsl written in GLSL 450, line for line (same inputs, same uniform
// block, same helpers), to check that a GLSL shader has the same nodes as its WGSL twin.
//
// Differences forced by the language: the inputs are separate `in` variables instead of a struct,
// the output is an `out` variable written at the end of `main`, and WGSL's
// `select(0.0, 1.0, c)` is GLSL's `mix(0.0, 1.0, c)` with a bool (a ternary `c ? 1.0 : 0.0` would
// be a branch: naga's GLSL front end lowers `?:` to an `if`).

layout(location = 0) in vec3 world_pos;
layout(location = 1) in vec3 normal;
layout(location = 4) in vec3 object_pos;

layout(location = 0) out vec4 frag_color;

layout(set = 0, binding = 0) uniform Scene {
    vec3 camera_pos;
    float time;
    vec3 light_pos;
    float shininess;
    vec3 light_color;
    float noise_scale;
} scene;

const vec3 VEIN_COLOR = vec3(0.20, 0.17, 0.22);
const vec3 BASE_COLOR = vec3(0.88, 0.86, 0.82);
const vec3 CLOUD_COLOR = vec3(0.66, 0.66, 0.68);
const float VEIN_FREQUENCY = 6.0;
const float TURBULENCE_GAIN = 4.0;
const float AMBIENT = 0.12;
const float SPECULAR = 0.45;

// Pseudo-random unit gradient at lattice point `c` (the classic sine hash), dotted with the offset
// `d` from that corner.
float corner_grad(vec3 c, vec3 d) {
    vec3 q = vec3(
        dot(c, vec3(127.1, 311.7, 74.7)),
        dot(c, vec3(269.5, 183.3, 246.1)),
        dot(c, vec3(113.5, 271.9, 124.6))
    );
    vec3 g = normalize(fract(sin(q) * 43758.5453) * 2.0 - vec3(1.0));
    return dot(g, d);
}

// 3D gradient noise, roughly in [-1, 1]; straight-line code (no loops).
float gradient_noise(vec3 p) {
    vec3 pf = floor(p);
    vec3 c = pf;
    vec3 f = p - pf;
    // quintic fade 6t^5 - 15t^4 + 10t^3
    vec3 w = f * f * f * (f * (f * 6.0 - vec3(15.0)) + vec3(10.0));
    float g000 = corner_grad(c, f);
    float g100 = corner_grad(c + vec3(1.0, 0.0, 0.0), f - vec3(1.0, 0.0, 0.0));
    float g010 = corner_grad(c + vec3(0.0, 1.0, 0.0), f - vec3(0.0, 1.0, 0.0));
    float g110 = corner_grad(c + vec3(1.0, 1.0, 0.0), f - vec3(1.0, 1.0, 0.0));
    float g001 = corner_grad(c + vec3(0.0, 0.0, 1.0), f - vec3(0.0, 0.0, 1.0));
    float g101 = corner_grad(c + vec3(1.0, 0.0, 1.0), f - vec3(1.0, 0.0, 1.0));
    float g011 = corner_grad(c + vec3(0.0, 1.0, 1.0), f - vec3(0.0, 1.0, 1.0));
    float g111 = corner_grad(c + vec3(1.0, 1.0, 1.0), f - vec3(1.0, 1.0, 1.0));
    float x00 = mix(g000, g100, w.x);
    float x10 = mix(g010, g110, w.x);
    float x01 = mix(g001, g101, w.x);
    float x11 = mix(g011, g111, w.x);
    float y0 = mix(x00, x10, w.y);
    float y1 = mix(x01, x11, w.y);
    return mix(y0, y1, w.z);
}

void main() {
    // Solid-texture coordinates.
    vec3 p = object_pos * scene.noise_scale;

    // Turbulence: five octaves of |noise|, each its own expression.
    float n0 = abs(gradient_noise(p));
    float n1 = abs(gradient_noise(p * 2.0 + vec3(17.3, 5.1, 9.7))) * 0.5;
    float n2 = abs(gradient_noise(p * 4.0 + vec3(3.7, 31.9, 11.3))) * 0.25;
    float n3 = abs(gradient_noise(p * 8.0 + vec3(23.1, 7.7, 41.5))) * 0.125;
    float n4 = abs(gradient_noise(p * 16.0 + vec3(5.9, 13.3, 29.1))) * 0.0625;
    float s1 = n0 + n1;
    float s2 = s1 + n2;
    float s3 = s2 + n3;
    float s4 = s3 + n4;
    float turbulence = s4;

    // Marble veins: stripes along x, bent by the turbulence.
    float stripes = sin(p.x * VEIN_FREQUENCY + turbulence * TURBULENCE_GAIN);
    float vein = smoothstep(0.0, 0.5, abs(stripes));
    vec3 cloudy = mix(BASE_COLOR, CLOUD_COLOR, clamp(turbulence * 0.8, 0.0, 1.0));
    vec3 albedo = mix(VEIN_COLOR, cloudy, vein);

    // Blinn-Phong with one point light.
    vec3 n = normalize(normal);
    vec3 l = normalize(scene.light_pos - world_pos);
    vec3 v = normalize(scene.camera_pos - world_pos);
    vec3 h = normalize(l + v);
    float n_dot_l = max(dot(n, l), 0.0);
    float n_dot_h = max(dot(n, h), 0.0);
    vec3 diffuse = albedo * (n_dot_l * scene.light_color);
    vec3 ambient = albedo * AMBIENT;
    float spec_mask = mix(0.0, 1.0, n_dot_l > 0.0);
    vec3 specular = scene.light_color * (SPECULAR * pow(n_dot_h, scene.shininess) * spec_mask);

    vec3 color = clamp(ambient + diffuse + specular, vec3(0.0), vec3(1.0));
    frag_color = vec4(color, 1.0);
}
