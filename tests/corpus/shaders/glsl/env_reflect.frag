#version 450
// Reflective surface: environment cube map with Schlick Fresnel over a base color.
layout(location = 0) in vec3 inPos;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec4 outFragColor;

layout(binding = 0) uniform UBO {
    mat4 invModel;
    vec4 camPos;
    vec4 baseColor;
    float lodBias;
} ubo;
layout(binding = 1) uniform samplerCube samplerEnv;

float fresnelSchlick(float cosTheta, float f0) {
    return f0 + (1.0 - f0) * pow(1.0 - cosTheta, 5.0);
}

void main() {
    vec3 I = normalize(inPos - ubo.camPos.xyz);
    vec3 N = normalize(inNormal);
    vec3 R = reflect(I, N);
    R = vec3(ubo.invModel * vec4(R, 0.0));
    vec3 env = textureLod(samplerEnv, R, ubo.lodBias).rgb;
    float F = fresnelSchlick(max(dot(-I, N), 0.0), 0.04);
    outFragColor = vec4(mix(ubo.baseColor.rgb, env, F), 1.0);
}
