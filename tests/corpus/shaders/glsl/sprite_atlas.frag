#version 450
// 2D sprite from an atlas layer (texture array), tinted, with alpha test.
layout(location = 0) in vec2 inUV;
layout(location = 1) flat in int inLayer;
layout(location = 2) in vec4 inTint;
layout(location = 0) out vec4 outColor;

layout(set = 0, binding = 0) uniform sampler2DArray atlas;
layout(constant_id = 0) const float ALPHA_CUTOFF = 0.5;

void main() {
    vec4 texel = texture(atlas, vec3(inUV, float(inLayer)));
    vec4 color = texel * inTint;
    if (color.a < ALPHA_CUTOFF) {
        discard;
    }
    outColor = vec4(color.rgb * color.a, 1.0);
}
