#version 450
// Water: two scrolling normal maps, reflection from a cube map, depth-tinted refraction color.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform WaterUBO {
    vec4 cameraPos;
    vec4 shallowColor;
    vec4 deepColor;
    float time;
    float waveScale;
} water;
layout(set = 0, binding = 1) uniform sampler2D waveNormals;
layout(set = 0, binding = 2) uniform samplerCube reflectionCube;

void main() {
    vec2 uv0 = inUV * water.waveScale + vec2(water.time * 0.03, 0.0);
    vec2 uv1 = inUV * water.waveScale * 1.7 - vec2(0.0, water.time * 0.02);
    vec3 n0 = texture(waveNormals, uv0).xzy * 2.0 - 1.0;
    vec3 n1 = texture(waveNormals, uv1).xzy * 2.0 - 1.0;
    vec3 N = normalize(n0 + n1 + vec3(0.0, 2.0, 0.0));
    vec3 V = normalize(water.cameraPos.xyz - inWorldPos);
    vec3 R = reflect(-V, N);
    vec3 refl = texture(reflectionCube, R).rgb;
    float fresnel = 0.02 + 0.98 * pow(1.0 - max(dot(N, V), 0.0), 5.0);
    vec3 body = mix(water.shallowColor.rgb, water.deepColor.rgb, clamp(V.y, 0.0, 1.0));
    outColor = vec4(mix(body, refl, fresnel), 1.0);
}
