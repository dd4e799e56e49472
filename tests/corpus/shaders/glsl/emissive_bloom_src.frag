#version 450
// Emissive material writing HDR color: base, emissive mask texture, pulsing intensity.
layout(location = 0) in vec2 inUV;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec3 inViewDir;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform Frame {
    float time;
    float emissiveStrength;
} frame;
layout(set = 1, binding = 0) uniform sampler2D baseColorTex;
layout(set = 1, binding = 1) uniform sampler2D emissiveTex;

void main() {
    vec3 base = texture(baseColorTex, inUV).rgb;
    vec3 emissive = texture(emissiveTex, inUV).rgb;
    float pulse = 0.75 + 0.25 * sin(frame.time * 3.0);
    float ndv = max(dot(normalize(inNormal), normalize(inViewDir)), 0.0);
    vec3 color = base * (0.25 + 0.75 * ndv) + emissive * frame.emissiveStrength * pulse;
    outColor = vec4(color, 1.0);
}
