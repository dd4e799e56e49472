#version 450
// Terrain: four layers of a texture array blended by height and slope.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outFragColor;

layout(set = 0, binding = 0) uniform TerrainUBO {
    vec4 layerHeights;
    vec4 lightDir;
    float uvScale;
} terrain;
layout(set = 0, binding = 1) uniform sampler2DArray samplerLayers;

void main() {
    vec2 uv = inUV * terrain.uvScale;
    float h = inWorldPos.y;
    float slope = 1.0 - normalize(inNormal).y;
    vec3 grass = texture(samplerLayers, vec3(uv, 0.0)).rgb;
    vec3 dirt = texture(samplerLayers, vec3(uv, 1.0)).rgb;
    vec3 rock = texture(samplerLayers, vec3(uv, 2.0)).rgb;
    vec3 snow = texture(samplerLayers, vec3(uv, 3.0)).rgb;
    vec3 color = mix(grass, dirt, smoothstep(terrain.layerHeights.x, terrain.layerHeights.y, h));
    color = mix(color, rock, smoothstep(0.3, 0.6, slope));
    color = mix(color, snow, smoothstep(terrain.layerHeights.z, terrain.layerHeights.w, h));
    float ndotl = max(dot(normalize(inNormal), -terrain.lightDir.xyz), 0.15);
    outFragColor = vec4(color * ndotl, 1.0);
}
