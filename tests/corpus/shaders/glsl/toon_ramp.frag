#version 450
// Toon shading: the diffuse term looked up in a 1D-style ramp texture, rim light from a push constant.
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inViewVec;
layout(location = 2) in vec3 inLightVec;
layout(location = 3) in vec2 inUV;
layout(location = 0) out vec4 outFragColor;

layout(set = 0, binding = 1) uniform sampler2D rampTexture;
layout(set = 0, binding = 2) uniform sampler2D baseTexture;
layout(push_constant) uniform PushConsts {
    layout(offset = 0) vec4 rimColor;
    layout(offset = 16) float rimPower;
} push;

void main() {
    vec3 N = normalize(inNormal);
    vec3 L = normalize(inLightVec);
    vec3 V = normalize(inViewVec);
    float ndl = dot(N, L) * 0.5 + 0.5;
    vec3 ramp = texture(rampTexture, vec2(ndl, 0.5)).rgb;
    vec3 base = texture(baseTexture, inUV).rgb;
    float rim = pow(1.0 - max(dot(N, V), 0.0), push.rimPower);
    outFragColor = vec4(base * ramp + rim * push.rimColor.rgb, 1.0);
}
