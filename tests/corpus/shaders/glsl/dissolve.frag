#version 450
// Dissolve effect: a noise texture against a threshold, glowing edge, discard below it.
layout(location = 0) in vec2 inUV;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform sampler2D baseMap;
layout(set = 0, binding = 1) uniform sampler2D noiseMap;
layout(push_constant) uniform Dissolve {
    layout(offset = 0) float threshold;
    layout(offset = 4) float edgeWidth;
    layout(offset = 16) vec4 edgeColor;
} dissolve;

void main() {
    float n = texture(noiseMap, inUV).r;
    if (n < dissolve.threshold) {
        discard;
    }
    vec3 base = texture(baseMap, inUV).rgb;
    float edge = 1.0 - smoothstep(0.0, dissolve.edgeWidth, n - dissolve.threshold);
    vec3 lit = base * (0.3 + 0.7 * max(normalize(inNormal).y, 0.0));
    outColor = vec4(mix(lit, dissolve.edgeColor.rgb, edge), 1.0);
}
