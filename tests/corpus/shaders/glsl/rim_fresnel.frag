#version 450
// Hologram-style rim light with scan lines; colors and speeds from a UBO.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform Holo {
    vec4 cameraPos;
    vec4 rimColor;
    vec4 baseColor;
    float time;
    float scanDensity;
} holo;
layout(set = 0, binding = 1) uniform sampler2D patternTex;

void main() {
    vec3 N = normalize(inNormal);
    vec3 V = normalize(holo.cameraPos.xyz - inWorldPos);
    float rim = pow(1.0 - clamp(dot(N, V), 0.0, 1.0), 3.0);
    float scan = 0.5 + 0.5 * sin(inWorldPos.y * holo.scanDensity + holo.time * 4.0);
    float pattern = texture(patternTex, inUV + vec2(0.0, holo.time * 0.1)).r;
    vec3 color = holo.baseColor.rgb * pattern * scan + holo.rimColor.rgb * rim;
    outColor = vec4(color, 1.0);
}
