#version 450
// Metallic-roughness PBR with albedo, normal, metal/roughness and AO maps (glTF-style).
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform UBOScene {
    mat4 projection;
    mat4 view;
    vec3 camPos;
    float exposure;
    vec4 lightPos;
} uboScene;
layout(set = 1, binding = 0) uniform sampler2D albedoMap;
layout(set = 1, binding = 1) uniform sampler2D metallicRoughnessMap;
layout(set = 1, binding = 2) uniform sampler2D aoMap;

const float PI = 3.14159265359;

float D_GGX(float dotNH, float roughness) {
    float alpha = roughness * roughness;
    float alpha2 = alpha * alpha;
    float denom = dotNH * dotNH * (alpha2 - 1.0) + 1.0;
    return alpha2 / (PI * denom * denom);
}

float G_SchlicksmithGGX(float dotNL, float dotNV, float roughness) {
    float r = roughness + 1.0;
    float k = (r * r) / 8.0;
    float GL = dotNL / (dotNL * (1.0 - k) + k);
    float GV = dotNV / (dotNV * (1.0 - k) + k);
    return GL * GV;
}

vec3 F_Schlick(float cosTheta, vec3 F0) {
    return F0 + (1.0 - F0) * pow(1.0 - cosTheta, 5.0);
}

void main() {
    vec3 albedo = pow(texture(albedoMap, inUV).rgb, vec3(2.2));
    vec2 mr = texture(metallicRoughnessMap, inUV).bg;
    float metallic = mr.x;
    float roughness = clamp(mr.y, 0.05, 1.0);
    float ao = texture(aoMap, inUV).r;
    vec3 N = normalize(inNormal);
    vec3 V = normalize(uboScene.camPos - inWorldPos);
    vec3 L = normalize(uboScene.lightPos.xyz - inWorldPos);
    vec3 H = normalize(V + L);
    float dotNV = clamp(dot(N, V), 0.001, 1.0);
    float dotNL = clamp(dot(N, L), 0.0, 1.0);
    float dotNH = clamp(dot(N, H), 0.0, 1.0);
    vec3 F0 = mix(vec3(0.04), albedo, metallic);
    float D = D_GGX(dotNH, roughness);
    float G = G_SchlicksmithGGX(dotNL, dotNV, roughness);
    vec3 F = F_Schlick(dotNV, F0);
    vec3 spec = D * F * G / (4.0 * dotNL * dotNV + 0.001);
    vec3 kD = (vec3(1.0) - F) * (1.0 - metallic);
    vec3 Lo = (kD * albedo / PI + spec) * dotNL;
    vec3 color = Lo + vec3(0.03) * albedo * ao;
    color = vec3(1.0) - exp(-color * uboScene.exposure);
    outColor = vec4(pow(color, vec3(1.0 / 2.2)), 1.0);
}
