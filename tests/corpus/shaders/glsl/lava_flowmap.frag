#version 450
// Flowing lava with a flow map (the two-phase technique from Valve's water): the surface texture
// is advected along the flow vectors in two phases half a period apart and cross-faded so it never
// stretches without bound. Cooled crust is dark and rough; the cracks glow by temperature through
// a blackbody-like ramp. Emission boost is a specialization constant.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform Lava {
    vec3 camera_pos;
    float time;
    vec3 light_pos;
    float flowSpeed;
    vec4 crustColor;
    float flowStrength;
    float period;
    float uvScale;
    float glowPower;
} lava;

layout(set = 1, binding = 0) uniform sampler2D flowMap;
layout(set = 1, binding = 1) uniform sampler2D lavaTex;

layout(constant_id = 0) const float EMISSION_BOOST = 3.0;

vec3 blackbody(float t) {
    // A cheap ramp: dark red -> orange -> yellow-white.
    return clamp(vec3(t * 3.0, t * 3.0 - 1.0, t * 3.0 - 2.0), 0.0, 1.0) * vec3(1.0, 0.85, 0.7);
}

void main() {
    vec2 uv = inUV * lava.uvScale;
    vec2 flow = (texture(flowMap, inUV).rg * 2.0 - 1.0) * lava.flowStrength;

    float t = lava.time * lava.flowSpeed / lava.period;
    float phase0 = fract(t);
    float phase1 = fract(t + 0.5);
    vec4 s0 = texture(lavaTex, uv - flow * phase0 * lava.period);
    vec4 s1 = texture(lavaTex, uv - flow * phase1 * lava.period + vec2(0.37, 0.21));
    float blend = abs(phase0 - 0.5) * 2.0;
    vec4 s = mix(s0, s1, blend);

    // Crust where the texture is high, glowing cracks where it is low.
    float heat = pow(clamp(1.0 - s.r, 0.0, 1.0), lava.glowPower);
    vec3 N = normalize(inNormal);
    vec3 L = normalize(lava.light_pos - inWorldPos);
    vec3 V = normalize(lava.camera_pos - inWorldPos);
    vec3 H = normalize(L + V);
    float diffuse = max(dot(N, L), 0.0);
    float spec = pow(max(dot(N, H), 0.0), 16.0) * 0.1 * (1.0 - heat);
    vec3 crust = lava.crustColor.rgb * (0.5 + 0.5 * s.g) * (0.15 + 0.85 * diffuse) + vec3(spec);
    vec3 glow = blackbody(heat) * EMISSION_BOOST * heat;
    vec3 color = crust * (1.0 - heat) + glow;
    outColor = vec4(color / (1.0 + color), 1.0);
}
