#version 450
// Matcap (lit sphere) material as sculpting tools and stylized engines draw it: the normal, bent
// by a detail normal map, is taken to view space and looks up a matcap texture; a second matcap
// adds a glossy layer and a cavity term darkens creases. The view matrix comes in the camera UBO,
// the per-draw tint and blend in a per-material UBO, the blend mode is a specialization
// constant.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 3) in vec4 inTangent;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform Camera {
    mat4 view;
    vec3 camera_pos;
    float time;
} camera;

layout(set = 1, binding = 0) uniform sampler2D matcapDiffuse;
layout(set = 1, binding = 1) uniform sampler2D matcapGloss;
layout(set = 1, binding = 2) uniform sampler2D detailNormal;

layout(set = 1, binding = 3) uniform Draw {
    vec4 tint;
    float detailScale;
    float detailStrength;
    float glossAmount;
    float cavityStrength;
} draw;

// 0: multiply the gloss layer, 1: add it, 2: screen it.
layout(constant_id = 0) const int GLOSS_BLEND = 1;

vec3 detailNormalWS(vec3 n, vec4 t, vec2 uv) {
    vec3 tangent = normalize(t.xyz - n * dot(n, t.xyz));
    vec3 bitangent = cross(n, tangent) * t.w;
    vec3 ts = texture(detailNormal, uv * draw.detailScale).xyz * 2.0 - 1.0;
    ts.xy *= draw.detailStrength;
    return normalize(mat3(tangent, bitangent, n) * ts);
}

vec2 matcapUV(vec3 nWorld, vec3 posWorld) {
    // View-space normal, corrected by the view direction so the matcap does not swim at the edges.
    vec3 nv = normalize(mat3(camera.view) * nWorld);
    vec3 pv = normalize((camera.view * vec4(posWorld, 1.0)).xyz);
    vec3 r = reflect(pv, nv);
    float m = 2.0 * sqrt(r.x * r.x + r.y * r.y + (r.z + 1.0) * (r.z + 1.0));
    return r.xy / m + 0.5;
}

void main() {
    vec3 n0 = normalize(inNormal);
    vec3 n = detailNormalWS(n0, inTangent, inUV);
    vec2 uv = matcapUV(n, inWorldPos);
    vec3 base = texture(matcapDiffuse, uv).rgb * draw.tint.rgb;
    vec3 gloss = texture(matcapGloss, uv).rgb * draw.glossAmount;

    vec3 color;
    if (GLOSS_BLEND == 0) {
        color = base * (1.0 + gloss);
    } else if (GLOSS_BLEND == 1) {
        color = base + gloss;
    } else {
        color = 1.0 - (1.0 - base) * (1.0 - gloss);
    }

    // Cavity: where the detail normal turns away from the surface normal.
    float cavity = clamp(dot(n, n0), 0.0, 1.0);
    color *= mix(1.0, cavity * cavity, draw.cavityStrength);
    outColor = vec4(clamp(color, 0.0, 1.0), draw.tint.a);
}
