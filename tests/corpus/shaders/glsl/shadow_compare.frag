#version 450
// Hardware depth comparison: a sampler2DShadow sampled four times around the texel (2x2 PCF).
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inLightVec;
layout(location = 2) in vec4 inShadowCoord;
layout(location = 3) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform sampler2DShadow shadowMap;
layout(set = 1, binding = 0) uniform sampler2D albedoTex;
layout(push_constant) uniform Shadow {
    layout(offset = 0) float texelSize;
    layout(offset = 4) float bias;
} shadowParams;

void main() {
    vec3 sc = inShadowCoord.xyz / inShadowCoord.w;
    float t = shadowParams.texelSize;
    float ref = sc.z - shadowParams.bias;
    float s = texture(shadowMap, vec3(sc.xy + vec2(-t, -t), ref));
    s += texture(shadowMap, vec3(sc.xy + vec2(t, -t), ref));
    s += texture(shadowMap, vec3(sc.xy + vec2(-t, t), ref));
    s += texture(shadowMap, vec3(sc.xy + vec2(t, t), ref));
    s *= 0.25;
    vec3 albedo = texture(albedoTex, inUV).rgb;
    float ndl = max(dot(normalize(inNormal), normalize(inLightVec)), 0.0);
    outColor = vec4(albedo * (0.15 + 0.85 * ndl * s), 1.0);
}
