#version 450
// Signed-distance-field text: smoothed edge from the SDF atlas, outline and drop shadow.
layout(location = 0) in vec2 inUV;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform sampler2D fontSDF;
layout(set = 0, binding = 1) uniform Style {
    vec4 textColor;
    vec4 outlineColor;
    vec2 shadowOffset;
    float outlineWidth;
    float smoothing;
} style;

void main() {
    float dist = texture(fontSDF, inUV).a;
    float alpha = smoothstep(0.5 - style.smoothing, 0.5 + style.smoothing, dist);
    float outline = smoothstep(0.5 - style.outlineWidth - style.smoothing, 0.5 - style.outlineWidth + style.smoothing, dist);
    float shadowDist = texture(fontSDF, inUV - style.shadowOffset).a;
    float shadow = smoothstep(0.3, 0.5, shadowDist) * 0.5;
    vec3 color = mix(style.outlineColor.rgb, style.textColor.rgb, alpha);
    float a = max(outline, shadow);
    outColor = vec4(color * outline, a);
}
