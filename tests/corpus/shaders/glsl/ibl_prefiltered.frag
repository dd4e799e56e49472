#version 450
// Image-based lighting: prefiltered specular cube map by roughness, BRDF lookup table, irradiance cube.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform UBOParams {
    vec4 camPos;
    float exposure;
    float gamma;
    float prefilteredMips;
} uboParams;
layout(set = 0, binding = 1) uniform samplerCube samplerIrradiance;
layout(set = 0, binding = 2) uniform sampler2D samplerBRDFLUT;
layout(set = 0, binding = 3) uniform samplerCube prefilteredMap;
layout(set = 1, binding = 0) uniform sampler2D albedoMap;

layout(push_constant) uniform Material {
    layout(offset = 12) float roughness;
    layout(offset = 16) float metallic;
} material;

vec3 F_SchlickR(float cosTheta, vec3 F0, float roughness) {
    return F0 + (max(vec3(1.0 - roughness), F0) - F0) * pow(1.0 - cosTheta, 5.0);
}

void main() {
    vec3 N = normalize(inNormal);
    vec3 V = normalize(uboParams.camPos.xyz - inWorldPos);
    vec3 R = reflect(-V, N);
    vec3 albedo = texture(albedoMap, inUV).rgb;
    vec3 F0 = mix(vec3(0.04), albedo, material.metallic);
    float NdotV = max(dot(N, V), 0.0);
    vec2 brdf = texture(samplerBRDFLUT, vec2(NdotV, material.roughness)).rg;
    vec3 reflection = textureLod(prefilteredMap, R, material.roughness * uboParams.prefilteredMips).rgb;
    vec3 irradiance = texture(samplerIrradiance, N).rgb;
    vec3 F = F_SchlickR(NdotV, F0, material.roughness);
    vec3 specular = reflection * (F * brdf.x + brdf.y);
    vec3 kD = (1.0 - F) * (1.0 - material.metallic);
    vec3 color = kD * irradiance * albedo + specular;
    color = vec3(1.0) - exp(-color * uboParams.exposure);
    outColor = vec4(pow(color, vec3(1.0 / uboParams.gamma)), 1.0);
}
