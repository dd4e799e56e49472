#version 450
// Kajiya-Kay anisotropic highlights along a tangent shifted by a shift texture.
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inTangent;
layout(location = 2) in vec3 inViewDir;
layout(location = 3) in vec3 inLightDir;
layout(location = 4) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 1, binding = 0) uniform sampler2D hairColor;
layout(set = 1, binding = 1) uniform sampler2D shiftTex;
layout(push_constant) uniform Hair {
    layout(offset = 32) vec4 specColor1;
    layout(offset = 48) vec4 specColor2;
    layout(offset = 64) float shift1;
    layout(offset = 68) float shift2;
} hair;

float strandSpecular(vec3 T, vec3 V, vec3 L, float exponent) {
    vec3 H = normalize(L + V);
    float dotTH = dot(T, H);
    float sinTH = sqrt(max(1.0 - dotTH * dotTH, 0.0));
    float dirAtten = smoothstep(-1.0, 0.0, dotTH);
    return dirAtten * pow(sinTH, exponent);
}

void main() {
    vec3 N = normalize(inNormal);
    vec3 V = normalize(inViewDir);
    vec3 L = normalize(inLightDir);
    float shiftTexel = texture(shiftTex, inUV).r - 0.5;
    vec3 T1 = normalize(inTangent + (hair.shift1 + shiftTexel) * N);
    vec3 T2 = normalize(inTangent + (hair.shift2 + shiftTexel) * N);
    vec3 base = texture(hairColor, inUV).rgb;
    vec3 diffuse = base * clamp(mix(0.25, 1.0, dot(N, L)), 0.0, 1.0);
    vec3 spec = hair.specColor1.rgb * strandSpecular(T1, V, L, 80.0);
    spec += hair.specColor2.rgb * strandSpecular(T2, V, L, 20.0) * texture(shiftTex, inUV * 4.0).g;
    outColor = vec4(diffuse + spec, 1.0);
}
