#version 450
// Exponential height fog over a textured, lit surface; fog density as a specialization constant.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(constant_id = 0) const float FOG_DENSITY = 0.02;
layout(constant_id = 1) const float FOG_FALLOFF = 0.15;
layout(set = 0, binding = 0) uniform Camera {
    vec4 position;
    vec4 fogColor;
    vec4 sunDir;
} camera;
layout(set = 1, binding = 0) uniform sampler2D diffuseTex;

void main() {
    vec3 albedo = texture(diffuseTex, inUV).rgb;
    float ndl = max(dot(normalize(inNormal), -camera.sunDir.xyz), 0.0);
    vec3 lit = albedo * (0.2 + 0.8 * ndl);
    float dist = length(camera.position.xyz - inWorldPos);
    float heightTerm = exp(-max(inWorldPos.y, 0.0) * FOG_FALLOFF);
    float fog = 1.0 - exp(-dist * FOG_DENSITY * heightTerm);
    outColor = vec4(mix(lit, camera.fogColor.rgb, clamp(fog, 0.0, 1.0)), 1.0);
}
