#version 450
// Snow accumulation on upward faces: rock and snow textures blended by the normal and a noise map.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 1, binding = 0) uniform sampler2D rockTex;
layout(set = 1, binding = 1) uniform sampler2D snowTex;
layout(set = 1, binding = 2) uniform sampler2D noiseTex;
layout(set = 0, binding = 0) uniform Weather {
    vec4 sunDir;
    float snowAmount;
    float snowSharpness;
} weather;

void main() {
    vec3 N = normalize(inNormal);
    float noise = texture(noiseTex, inWorldPos.xz * 0.05).r;
    float cover = smoothstep(1.0 - weather.snowAmount, 1.0 - weather.snowAmount + weather.snowSharpness, N.y + noise * 0.2);
    vec3 rock = texture(rockTex, inUV).rgb;
    vec3 snow = texture(snowTex, inUV * 2.0).rgb;
    vec3 albedo = mix(rock, snow, cover);
    float ndl = max(dot(N, -weather.sunDir.xyz), 0.0);
    outColor = vec4(albedo * (0.2 + 0.8 * ndl), 1.0);
}
