#version 450
// Heat haze over a hot surface (exhaust, desert road, a fire): the scene color behind the
// geometry is read at a screen position shifted by two scrolling noise layers; the shift grows
// with the heat mask and fades at grazing angles, and a few taps along the shift smear it. The
// tap count is a specialization constant; the scene color is a combined image sampler.
layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform Haze {
    vec3 camera_pos;
    float time;
    vec2 resolution;
    float strength;
    float scrollSpeed;
    vec4 heatTint;
    float noiseScale;
    float heatFalloff;
} haze;

layout(set = 1, binding = 0) uniform sampler2D sceneColor;
layout(set = 1, binding = 1) uniform sampler2D distortionNoise;
layout(set = 1, binding = 2) uniform sampler2D heatMask;

layout(constant_id = 0) const int SMEAR_TAPS = 3;

void main() {
    vec2 screenUV = gl_FragCoord.xy / haze.resolution;

    vec2 uv = inUV * haze.noiseScale;
    vec2 n1 = texture(distortionNoise, uv + vec2(0.0, -haze.time * haze.scrollSpeed)).rg * 2.0 - 1.0;
    vec2 n2 = texture(distortionNoise, uv * 1.7 + vec2(haze.time * haze.scrollSpeed * 0.3, -haze.time * haze.scrollSpeed * 1.3)).rg * 2.0 - 1.0;
    vec2 offset = (n1 + 0.5 * n2) * haze.strength;

    float heat = texture(heatMask, inUV).r;
    heat = pow(heat, haze.heatFalloff);
    vec3 N = normalize(inNormal);
    vec3 V = normalize(haze.camera_pos - inWorldPos);
    float facing = clamp(dot(N, V), 0.0, 1.0);
    offset *= heat * facing;

    vec3 color = vec3(0.0);
    float weightSum = 0.0;
    for (int i = 0; i < SMEAR_TAPS; i++) {
        float t = float(i) / float(max(SMEAR_TAPS - 1, 1));
        float w = 1.0 - 0.5 * t;
        color += texture(sceneColor, screenUV + offset * (1.0 - 0.4 * t)).rgb * w;
        weightSum += w;
    }
    color /= weightSum;

    color = mix(color, color * haze.heatTint.rgb, heat * haze.heatTint.a);
    outColor = vec4(color, 1.0);
}
