#version 450
// Tangent-space normal mapping with a Blinn-Phong highlight.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 3) in vec4 inTangent;
layout(location = 0) out vec4 outFragColor;

layout(set = 0, binding = 0) uniform UBO {
    vec4 lightPos;
    vec4 viewPos;
    float shininess;
} ubo;
layout(set = 1, binding = 0) uniform sampler2D samplerColor;
layout(set = 1, binding = 1) uniform sampler2D samplerNormal;

vec3 perturbNormal(vec3 n, vec4 t, vec2 uv) {
    vec3 N = normalize(n);
    vec3 T = normalize(t.xyz - dot(t.xyz, N) * N);
    vec3 B = cross(N, T) * t.w;
    mat3 TBN = mat3(T, B, N);
    vec3 tangentNormal = texture(samplerNormal, uv).xyz * 2.0 - 1.0;
    return normalize(TBN * tangentNormal);
}

void main() {
    vec3 N = perturbNormal(inNormal, inTangent, inUV);
    vec3 L = normalize(ubo.lightPos.xyz - inWorldPos);
    vec3 V = normalize(ubo.viewPos.xyz - inWorldPos);
    vec3 H = normalize(L + V);
    vec3 color = texture(samplerColor, inUV).rgb;
    float diff = max(dot(N, L), 0.0);
    float spec = pow(max(dot(N, H), 0.0), ubo.shininess);
    outFragColor = vec4(color * (0.1 + diff) + vec3(spec * 0.5), 1.0);
}
