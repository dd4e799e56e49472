#version 450
// Post pass: color grading through a LUT strip, vignette and film grain from a noise texture.
layout(location = 0) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform sampler2D sceneColor;
layout(set = 0, binding = 1) uniform sampler2D gradeLUT;
layout(set = 0, binding = 2) uniform sampler2D grainTex;
layout(push_constant) uniform Post {
    layout(offset = 0) float vignetteStrength;
    layout(offset = 4) float grainAmount;
    layout(offset = 8) float time;
} post;

void main() {
    vec3 color = texture(sceneColor, inUV).rgb;
    vec3 graded = vec3(
        texture(gradeLUT, vec2(color.r, 0.167)).r,
        texture(gradeLUT, vec2(color.g, 0.5)).g,
        texture(gradeLUT, vec2(color.b, 0.833)).b);
    vec2 d = inUV - 0.5;
    float vignette = 1.0 - post.vignetteStrength * dot(d, d) * 2.0;
    float grain = texture(grainTex, inUV * 8.0 + vec2(post.time * 7.0, post.time * 3.0)).r - 0.5;
    outColor = vec4(graded * vignette + grain * post.grainAmount, 1.0);
}
