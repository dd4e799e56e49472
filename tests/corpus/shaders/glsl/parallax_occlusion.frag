#version 450
// Parallax occlusion mapping: a fixed-step search in a height map, then normal-mapped lighting.
layout(location = 0) in vec2 inUV;
layout(location = 1) in vec3 inTangentLightPos;
layout(location = 2) in vec3 inTangentViewPos;
layout(location = 3) in vec3 inTangentFragPos;
layout(location = 0) out vec4 outColor;

layout(set = 1, binding = 0) uniform sampler2D sColorMap;
layout(set = 1, binding = 1) uniform sampler2D sNormalHeightMap;
layout(set = 0, binding = 0) uniform UBO {
    float heightScale;
    float parallaxBias;
    float numLayers;
    int mappingMode;
} ubo;

vec2 parallaxOcclusionMapping(vec2 uv, vec3 viewDir) {
    float layerDepth = 1.0 / 16.0;
    float currLayerDepth = 0.0;
    vec2 deltaUV = viewDir.xy * ubo.heightScale / (viewDir.z * 16.0);
    vec2 currUV = uv;
    float height = 1.0 - textureLod(sNormalHeightMap, currUV, 0.0).a;
    for (int i = 0; i < 16; i++) {
        currLayerDepth += layerDepth;
        currUV -= deltaUV;
        height = 1.0 - textureLod(sNormalHeightMap, currUV, 0.0).a;
    }
    return currUV;
}

void main() {
    vec3 V = normalize(inTangentViewPos - inTangentFragPos);
    vec2 uv = parallaxOcclusionMapping(inUV, V);
    vec3 N = normalize(textureLod(sNormalHeightMap, uv, 0.0).rgb * 2.0 - 1.0);
    vec3 L = normalize(inTangentLightPos - inTangentFragPos);
    vec3 H = normalize(L + V);
    vec3 color = texture(sColorMap, uv).rgb;
    vec3 ambient = 0.2 * color;
    vec3 diffuse = max(dot(L, N), 0.0) * color;
    vec3 specular = vec3(0.15) * pow(max(dot(N, H), 0.0), 32.0);
    outColor = vec4(ambient + diffuse + specular, 1.0);
}
