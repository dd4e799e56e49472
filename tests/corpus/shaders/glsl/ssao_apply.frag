#version 450
// Composition: albedo and lighting multiplied by a blurred ambient-occlusion buffer.
layout(location = 0) in vec2 inUV;
layout(location = 0) out vec4 outFragColor;

layout(binding = 0) uniform sampler2D samplerAlbedo;
layout(binding = 1) uniform sampler2D samplerNormal;
layout(binding = 2) uniform sampler2D samplerSSAOBlur;
layout(binding = 3) uniform UBO {
    vec4 lightDir;
    int ssaoOnly;
    float aoStrength;
} ubo;

void main() {
    vec3 albedo = texture(samplerAlbedo, inUV).rgb;
    vec3 N = normalize(texture(samplerNormal, inUV).rgb * 2.0 - 1.0);
    float ao = texture(samplerSSAOBlur, inUV).r;
    float ndl = max(dot(N, -ubo.lightDir.xyz), 0.0);
    vec3 lit = albedo * (0.25 + 0.75 * ndl);
    float aoTerm = mix(1.0, ao, ubo.aoStrength);
    outFragColor = vec4(lit * aoTerm, 1.0);
}
