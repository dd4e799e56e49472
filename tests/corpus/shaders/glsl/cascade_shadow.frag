#version 450
// Cascaded shadow maps in a texture array: cascade chosen by view depth, hand-compared depth.
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inViewPos;
layout(location = 2) in vec3 inWorldPos;
layout(location = 3) in vec2 inUV;
layout(location = 0) out vec4 outFragColor;

#define SHADOW_MAP_CASCADE_COUNT 4
layout(set = 0, binding = 1) uniform sampler2DArray shadowMap;
layout(set = 0, binding = 2) uniform UBO {
    vec4 cascadeSplits;
    mat4 cascadeViewProjMat[SHADOW_MAP_CASCADE_COUNT];
    vec3 lightDir;
} ubo;
layout(set = 1, binding = 0) uniform sampler2D colorMap;

float textureProj(vec4 shadowCoord, float layer) {
    float dist = texture(shadowMap, vec3(shadowCoord.st, layer)).r;
    return (shadowCoord.z > -1.0 && shadowCoord.z < 1.0 && dist < shadowCoord.z - 0.005) ? 0.3 : 1.0;
}

void main() {
    vec3 color = texture(colorMap, inUV).rgb;
    uint cascadeIndex = 0u;
    if (inViewPos.z < ubo.cascadeSplits.x) { cascadeIndex = 1u; }
    if (inViewPos.z < ubo.cascadeSplits.y) { cascadeIndex = 2u; }
    if (inViewPos.z < ubo.cascadeSplits.z) { cascadeIndex = 3u; }
    vec4 shadowCoord = ubo.cascadeViewProjMat[cascadeIndex] * vec4(inWorldPos, 1.0);
    shadowCoord = shadowCoord / shadowCoord.w;
    shadowCoord.xy = shadowCoord.xy * 0.5 + 0.5;
    float shadow = textureProj(shadowCoord, float(cascadeIndex));
    float diffuse = max(dot(normalize(inNormal), normalize(-ubo.lightDir)), 0.1);
    outFragColor = vec4(color * diffuse * shadow, 1.0);
}
