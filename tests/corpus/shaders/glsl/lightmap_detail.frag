#version 450
// Baked lightmap (second UV set) times a detail-modulated base texture.
layout(location = 0) in vec2 inUV;
layout(location = 1) in vec2 inLightmapUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform sampler2D baseTex;
layout(set = 0, binding = 1) uniform sampler2D detailTex;
layout(set = 0, binding = 2) uniform sampler2D lightmapTex;
layout(push_constant) uniform Params {
    layout(offset = 8) float detailScale;
    layout(offset = 12) float lightmapIntensity;
} params;

void main() {
    vec3 base = texture(baseTex, inUV).rgb;
    vec3 detail = texture(detailTex, inUV * params.detailScale).rgb * 2.0;
    vec3 lightmap = texture(lightmapTex, inLightmapUV).rgb * params.lightmapIntensity;
    outColor = vec4(base * detail * lightmap, 1.0);
}
